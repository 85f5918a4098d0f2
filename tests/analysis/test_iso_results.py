"""The ISO roughness beside the manual's in the results of every profile the service
analyses: the profilometer's runs and the SMTs-2 disc's wear-track profile (issue 23)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rigserver.analysis import analyse
from rigserver.core.profile_filter import transmission
from schemas.labels import ISO_ENDS, ISO_LAMBDA_C_SOURCE
from schemas.results import ProfilometerResults, Smts2Results
from schemas.stands import StandKind
from tests.analysis.conftest import FakeReadings, friction_record, make_run

A_UM, WAVE_MM = 1.0, 0.08  # roughness: 1 µm at 80 µm
W_UM, WAVINESS_MM = 3.0, 4.0  # waviness: 3 µm at 4 mm


def _trace(length_mm: float = 4.8, step_mm: float = 0.5e-3) -> tuple[np.ndarray, np.ndarray]:
    x = np.arange(round(length_mm / step_mm) + 1) * step_mm
    y = A_UM * np.sin(2 * np.pi * x / WAVE_MM) + W_UM * np.sin(2 * np.pi * x / WAVINESS_MM)
    return x, y


def _profilometer(**config: object) -> ProfilometerResults:
    x, y = _trace()
    readings = FakeReadings({"profile": {"x": list(x), "y": list(y)}}, {})
    values = analyse(make_run(StandKind.PROFILOMETER, **config), readings).values
    assert isinstance(values, ProfilometerResults)
    return values


def test_the_iso_parameters_sit_beside_the_manuals() -> None:
    # two sines over whole periods: Rq² = Σ (a_i·T_i)²/2, with T_i what the λc high-pass and
    # the λs low-pass pass of each (ISO 16610-21, eq. 2); the manual's mean line is the
    # least-squares line, which keeps the waviness, so its Rq is near √((1² + 3²)/2) µm
    v = _profilometer()
    assert v.iso is not None and v.rq is not None
    lc, ls = v.iso.lambda_c, v.iso.lambda_s
    assert (lc, ls) == (0.8e-3, 2.5e-6)
    assert v.iso.lambda_c_source == ISO_LAMBDA_C_SOURCE["ra"]
    assert v.iso.ends == ISO_ENDS["discarded"] and v.iso.sections == 5

    def passed(wave_mm: float) -> float:
        lam = wave_mm * 1e-3
        high = 1 - float(transmission(wavelength=lam, cutoff=lc))
        return high * float(transmission(wavelength=lam, cutoff=ls))

    rq = math.hypot(A_UM * passed(WAVE_MM), W_UM * passed(WAVINESS_MM)) / math.sqrt(2) * 1e-6
    assert v.iso.rq == pytest.approx(rq, rel=2e-3)
    assert v.rq == pytest.approx(math.hypot(A_UM, W_UM) / math.sqrt(2) * 1e-6, rel=0.1)
    assert v.iso.rsm == pytest.approx(WAVE_MM * 1e-3, rel=1e-3)


def test_the_configured_filter_is_used() -> None:
    v = _profilometer(lambda_c=0.25e-3, lambda_s=8e-6)
    assert v.iso is not None
    assert (v.iso.lambda_c, v.iso.lambda_s) == (0.25e-3, 8e-6)
    assert v.iso.lambda_c_source == ISO_LAMBDA_C_SOURCE["given"]


def test_a_profile_too_short_says_why() -> None:
    readings = FakeReadings({"profile": {"x": [0.0, 0.01, 0.02, 0.03], "y": [0, 1, 0, 1]}}, {})
    values = analyse(make_run(StandKind.PROFILOMETER), readings).values
    assert isinstance(values, ProfilometerResults) and values.iso is None
    assert any(n.startswith("ISO roughness not computed") for n in values.notes)


def test_the_wear_track_profile_has_its_iso_roughness() -> None:
    # a groove 5 µm deep and 2 mm wide with 0.5 µm of roughness at 50 µm: the λc filter
    # takes the groove's form out, the roughness across the track stays
    x = np.arange(8001) * 0.5e-3
    groove = np.where(np.abs(x - 2.0) < 1.0, 5.0 * (1.0 - (x - 2.0) ** 2), 0.0)
    y = 0.5 * np.sin(2 * np.pi * x / 0.05) - groove
    track = FakeReadings({"profile": {"x": list(x), "y": list(y)}}, {})
    profile_run = make_run(StandKind.PROFILOMETER)
    record = friction_record()
    run = make_run(StandKind.SMTS2).model_copy(update={"specimen": {"disc_profile_run": "P-1"}})
    v = analyse(run, FakeReadings({"friction": record}, {}), {"P-1": (profile_run, track)}.get)
    values = v.values
    assert isinstance(values, Smts2Results) and values.disc_wear is not None
    own = analyse(profile_run, track).values
    assert isinstance(own, ProfilometerResults)
    assert values.disc_wear.iso == own.iso and own.iso is not None
    # Ra ≈ 2·0.5/π = 0.32 µm picks λc = 0.8 mm from the table; the groove's edges, kinks
    # the Gaussian mean line cannot follow, leak into the roughness there and merge a few
    # elements: 10 % on Ra and RSm
    assert own.iso.lambda_c == 0.8e-3
    assert own.iso.ra == pytest.approx(2 * 0.5e-6 / math.pi, rel=0.1)
    assert own.iso.rsm == pytest.approx(0.05e-3, rel=0.1)


@pytest.mark.parametrize("kind", [StandKind.PIN_ON_DISC, StandKind.RECIPROCATING])
def test_the_tribometers_track_has_the_iso_roughness_of_its_first_trace(kind: StandKind) -> None:
    from rigserver.core.iso_roughness import iso_profile
    from tests.reports.simulated import simulated

    s = simulated(kind)
    track = s.result.values.disc_track  # type: ignore[attr-defined]
    assert track is not None and track.iso is not None
    cols = s.readings.read("wear_track")
    first = cols["trace"] == np.unique(cols["trace"])[0]
    order = np.argsort(cols["x"][first], kind="stable")
    expected = iso_profile(cols["x"][first][order] * 1e-3, cols["z"][first][order] * 1e-6)
    assert (track.iso.lambda_c, track.iso.ra) == (expected.lambda_c, expected.parameters.ra)
    assert track.iso.rk == expected.parameters.rk
