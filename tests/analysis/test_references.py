"""Profilometer runs named by another run: the MTOS film parameter Λ takes their Rq, the
SMTs-2 disc's wear comes from a profile across its track."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from rigserver.analysis import analyse
from rigsim.simulators import mtos, profilometer
from schemas.results import MtosResults
from schemas.runs import Run
from schemas.stands import StandKind
from tests.analysis.conftest import FakeReadings, friction_record, make_run
from tests.reports.simulated import SimulatedReadings, analysed


@pytest.fixture(scope="module")
def mtos_run() -> Any:
    settings = mtos.MtosSettings(model="short", loads_fluid=(1000.0,), loads_mixed=(1500.0,))
    return analysed(StandKind.MTOS, mtos.simulate(settings, seed=1))


def _named(run: Run, **specimen: str) -> Run:
    return run.model_copy(update={"specimen": {**run.specimen, **specimen}})


def test_rq_from_the_named_profilometer_runs(mtos_run: Any) -> None:
    journal = analysed(
        StandKind.PROFILOMETER,
        profilometer.simulate(profilometer.ProfilometerSettings(ra=0.2e-6), seed=2),
    )
    bush = analysed(
        StandKind.PROFILOMETER,
        profilometer.simulate(profilometer.ProfilometerSettings(ra=0.6e-6), seed=3),
    )
    store = {"J-1": (journal.run, journal.readings), "B-1": (bush.run, bush.readings)}
    run = _named(mtos_run.run, journal_profile_run="J-1", bush_profile_run="B-1")
    v = analyse(run, mtos_run.readings, store.get).values
    assert isinstance(v, MtosResults)
    rq_j, rq_b = journal.result.values.rq, bush.result.values.rq
    assert (v.journal_rq, v.bush_rq) == (rq_j, rq_b)
    assert "profilometer run J-1" in v.roughness_source
    for step in v.steps:  # Λ = h_min/√(Rq_j² + Rq_b²) with the measured Rq
        assert step.film_parameter == pytest.approx(step.h_min / np.hypot(rq_j, rq_b))


def test_unresolved_names_fall_back_to_the_configuration(mtos_run: Any) -> None:
    other = analysed(StandKind.MTOS, mtos_run.sim)
    store = {"M-1": (other.run, SimulatedReadings(other.sim))}
    run = _named(mtos_run.run, journal_profile_run="M-1", bush_profile_run="nope")
    v = analyse(run, mtos_run.readings, store.get).values
    assert isinstance(v, MtosResults) and v.roughness_source == "the stand's configuration"
    c = mtos.simulated_configuration()
    assert (v.journal_rq, v.bush_rq) == (c.journal_rq, c.bush_rq)
    assert any("a mtos run, not a profilometer run" in n for n in v.notes)
    assert any("'nope': no such run in the store" in n for n in v.notes)


def test_disc_wear_from_a_profile_across_the_track() -> None:
    # a parabolic groove 5 μm deep and 2 mm wide across the disc's track: A = 4/3·d0·w, the
    # disc's volume A·2π r2 and k = V/(F·L) with the run's mean load and sliding distance
    x_mm = np.linspace(0.0, 4.0, 4001)
    groove_um = np.where(np.abs(x_mm - 2.0) < 1.0, 5.0 * (1.0 - (x_mm - 2.0) ** 2), 0.0)
    trace = FakeReadings({"profile": {"x": list(x_mm), "y": list(1.0 - groove_um)}}, {})
    profile_run = make_run(StandKind.PROFILOMETER)
    record = friction_record()
    weighings = {"pin_mass_before": 12.25, "pin_mass_after": 12.2}
    run = _named(make_run(StandKind.SMTS2), disc_profile_run="P-1")
    v = analyse(
        run, FakeReadings({"friction": record}, weighings), {"P-1": (profile_run, trace)}.get
    )
    values = v.values
    assert values.disc_wear is not None and values.disc_wear.profile_run == "P-1"
    area = 4.0 / 3.0 * 5e-6 * 1e-3
    assert values.disc_wear.track_area == pytest.approx(area, rel=1e-5)
    volume = area * 2 * np.pi * 0.0225
    assert values.disc_wear.volume == pytest.approx(volume, rel=1e-5)
    distance = 2 * np.pi * 0.0225 * 900  # counter 0 -> 9 hundreds
    assert values.disc_wear.specific_wear_rate == pytest.approx(volume / (300 * distance), rel=1e-5)
