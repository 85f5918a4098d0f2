"""Detection limits (issue 37, item 6): a mass change within the balance's resolution gives
no k and reads "below the balance's resolution (< 0.01 mg)"; the masses are printed to the
balance's resolution."""

from __future__ import annotations

import math
from dataclasses import replace
from html import unescape

import numpy as np
import pytest

from rigsim.batches import Batch
from rigsim.cli import settings_for
from rigsim.simulators import SIMULATORS
from schemas.results import PinOnDiscResults
from schemas.stands import MEASUREMENTS, StandKind
from tests.reports.rendered import report_html
from tests.reports.simulated import Simulated, analysed


def _weighed(change_g: float) -> Simulated:
    """A simulated ball-on-disc test whose ball's mass changed by ``change_g`` grams."""
    kind = StandKind.PIN_ON_DISC
    s = replace(settings_for(kind, noise=True), laps=40, running_in_laps=8)
    sim = SIMULATORS[kind].simulate(s, 3)
    before = next(b for b in sim.batches if "pin_mass_before" in b.columns)
    mass = float(before.columns["pin_mass_before"][0])

    def weighed(b: Batch) -> Batch:
        if b.group != MEASUREMENTS or "pin_mass_after" not in b.columns:
            return b
        return Batch(b.group, {**b.columns, "pin_mass_after": np.array([mass - change_g])}, b.at)

    return analysed(kind, replace(sim, batches=tuple(weighed(b) for b in sim.batches)))


@pytest.mark.parametrize("change", [0.0, 1e-5, -1e-5])
def test_a_change_within_the_resolution_gives_no_k(change: float) -> None:
    # the default balance reads to 0.01 mg (1e-8 kg): no change, or one step either way
    done = _weighed(change)
    v = done.result.values
    assert isinstance(v, PinOnDiscResults)
    assert v.pin_mass is None
    assert v.pin_mass_below == pytest.approx(1e-8)
    for lang, said in (("en", "below the balance's resolution (< 0.01 mg)"), ("ru", "< 0,01 мг")):
        html = unescape(report_html(done, lang))  # type: ignore[arg-type]
        assert said in html


def test_two_steps_of_the_balance_give_a_k() -> None:
    v = _weighed(2e-5).result.values
    assert isinstance(v, PinOnDiscResults)
    assert v.pin_mass is not None and v.pin_mass_below is None
    assert v.pin_mass.mass_loss == pytest.approx(2e-8, rel=1e-6)


def test_the_masses_are_printed_to_the_balances_resolution() -> None:
    done = _weighed(2e-5)
    mass = done.readings.measurements()["pin_mass_before"]
    html = unescape(report_html(done, "en"))
    assert f">{mass:.5f}<" in html  # 0.01 mg = 1e-5 g: five decimals of the gram


def _disc_weighed(factor: float) -> Simulated:
    """The default ball-on-disc test (400 laps) whose disc lost ``factor`` times the mass
    of the volume its track shows."""
    kind = StandKind.PIN_ON_DISC
    s = replace(settings_for(kind, noise=False), laps=400, running_in_laps=80)
    sim = SIMULATORS[kind].simulate(s, 3)
    before = next(b for b in sim.batches if "disc_mass_before" in b.columns)
    mass = float(before.columns["disc_mass_before"][0])
    loss = sim.truth.disc_mass_loss / 1e-3  # g

    def weighed(b: Batch) -> Batch:
        if b.group != MEASUREMENTS or "disc_mass_after" not in b.columns:
            return b
        after = np.array([mass - factor * loss])
        return Batch(b.group, {**b.columns, "disc_mass_after": after}, b.at)

    return analysed(kind, replace(sim, batches=tuple(weighed(b) for b in sim.batches)))


def test_k_by_mass_and_by_track_that_disagree_are_weighed() -> None:
    # the disc weighed 10 times the track's volume (material lost off the track's edges, a
    # chipped disc): the two k differ beyond U = 2√(u₁² + u₂²), and the report trusts the
    # one of the smaller relative uncertainty
    done = _disc_weighed(10.0)
    v = done.result.values
    assert isinstance(v, PinOnDiscResults) and v.disc_mass and v.disc_track
    mass, track = v.disc_mass, v.disc_track
    assert mass.specific_wear_rate_uncertainty and track.specific_wear_rate_uncertainty
    gap = abs(mass.specific_wear_rate - track.specific_wear_rate)
    assert gap > 2 * math.hypot(
        mass.specific_wear_rate_uncertainty, track.specific_wear_rate_uncertainty
    )
    html = unescape(report_html(done, "en"))
    relative_mass = mass.specific_wear_rate_uncertainty / mass.specific_wear_rate
    relative_track = track.specific_wear_rate_uncertainty / track.specific_wear_rate
    trusted = "trust the mass loss" if relative_mass < relative_track else "trust the profiles"
    assert "The disc's k by its mass loss" in html and trusted in html
    assert "differ 10-fold" in html
    # weighed as the track shows: no word
    assert "The disc's k by its mass loss" not in unescape(report_html(_disc_weighed(1.0), "en"))
