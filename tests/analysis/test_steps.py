"""A recipe's steps (issue 37, item 2): the simulated speed sweep (rigsim's four 3-minute
steps at radius 6, 9, 12, 15 mm and 75-300 mm/s, the speed given in rpm) comes back step by
step, and the report draws μ against the sliding speed (a Stribeck curve) and tabulates it."""

from __future__ import annotations

import math
from html import unescape

import numpy as np
import pytest

from rigserver.reports import plots
from rigserver.reports.i18n import Lang
from rigsim.simulators.tribometer import SweepTruth, simulate_sweep
from schemas.results import PinOnDiscResults
from schemas.stands import StandKind
from tests.reports.rendered import report_html
from tests.reports.simulated import Simulated, analysed


def _sweep() -> tuple[Simulated, PinOnDiscResults, SweepTruth]:
    sim = simulate_sweep(seed=4)
    done = analysed(StandKind.PIN_ON_DISC, sim)
    values = done.result.values
    assert isinstance(values, PinOnDiscResults)
    return done, values, sim.truth


def test_the_sweep_comes_back_step_by_step() -> None:
    _, v, t = _sweep()
    assert [s.step for s in v.steps] == [1, 2, 3, 4]
    for found, speed, radius, mu in zip(
        v.steps, t.sliding_speed, t.track_radius, t.friction, strict=True
    ):
        # v = 2πRn/60 of the recorded rpm and radius: the simulated speed to round-off
        assert found.sliding_speed == pytest.approx(speed, rel=1e-12)
        assert found.track_radius == pytest.approx(radius, rel=1e-12)
        assert found.normal_load == pytest.approx(t.load, rel=1e-12)
        assert found.duration == pytest.approx(t.duration, rel=1e-12)
        # no distance in the record: v integrated over the step's time, v·t exactly
        assert found.distance == pytest.approx(speed * t.duration, rel=1e-9)
        # the mean of 1800 readings with a 2 % AR(1) fluctuation (ρ = 0.9): σ of the mean
        # μ·0.02·√((1 + ρ)/((1 - ρ)·n)) = 2.05e-3·μ; five of them
        sigma = mu * 0.02 * math.sqrt(19.0 / 1800)
        assert found.friction_mean == pytest.approx(mu, abs=5 * sigma)
        assert found.friction_steady is not None
        assert found.friction_steady == pytest.approx(mu, abs=5 * sigma * math.sqrt(5))
    assert any("sliding speed integrated" in note for note in v.notes)
    # the whole record's distance: the steps' distances and the moves between them, each
    # at the next step's speed for one reading interval (0.1 s)
    moves = sum(speed * 0.1 for speed in t.sliding_speed[1:])
    assert v.sliding_distance == pytest.approx(sum(s.distance for s in v.steps) + moves)


def test_a_record_without_steps_has_none() -> None:
    from tests.reports.simulated import simulated

    values = simulated(StandKind.PIN_ON_DISC).result.values
    assert isinstance(values, PinOnDiscResults)
    assert values.steps == []


@pytest.mark.parametrize(
    ("lang", "caption", "figure"),
    [
        ("en", "The recipe's steps", "Friction coefficient against the sliding speed"),
        ("ru", "Шаги программы испытания", "Коэффициент трения в зависимости от скорости"),
    ],
)
def test_the_report_draws_and_tabulates_the_steps(lang: Lang, caption: str, figure: str) -> None:
    done, v, _ = _sweep()
    with plots.recording() as drawn:
        html = report_html(done, lang)
    text = unescape(html)
    assert caption in text and figure in text
    # the Stribeck curve: the steps' mean μ against their speeds, as the results hold them
    curves = [line for fig in drawn for ax in fig.axes for line in ax.get_lines()]
    speeds = [s.sliding_speed or math.nan for s in v.steps]
    means = [s.friction_mean for s in v.steps]
    assert any(
        np.array_equal(line.get_xdata(), speeds) and np.array_equal(line.get_ydata(), means)
        for line in curves
    )
