"""The running-in as the end of the transient (issue 37, item 1): the steady part is the
longest tail whose lap means stay within ±δ of its mean (δ = 5 %, docs/models.md, section
6); a slow drift and a once-per-lap oscillation stay inside, a record that never settles is
said so, without a number."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from rigserver.core.tribometer import STEADY_BAND, STEADY_SHARE, settled_from
from rigserver.reports.i18n import Lang
from rigsim.batches import Batch, SimulatedRun
from schemas.results import PinOnDiscResults
from schemas.runs import RunCreate
from schemas.stands import StandKind
from tests.reports.rendered import report_html
from tests.reports.simulated import Simulated, analysed

#: A pin-on-disc record as a real one reads: 3 N over 30 m on a 5 mm track radius.
RADIUS = 5e-3
LAP = 2.0 * math.pi * RADIUS
READINGS_PER_LAP = 40


def _record(mu_of: Any, length: float, seed: int = 0) -> Simulated:
    """A pin-on-disc run whose friction record is μ(s) (s, m) plus a once-per-lap
    oscillation of 0.02 and 1 % white noise, read 40 times a lap."""
    laps = np.arange(0.0, length / LAP, 1.0 / READINGS_PER_LAP)
    s = laps * LAP
    rng = np.random.default_rng(seed)
    mu = mu_of(s) + 0.02 * np.sin(2.0 * math.pi * laps) + 0.01 * rng.standard_normal(s.size)
    columns: dict[str, NDArray[np.float64]] = {
        "time": s / 0.05,
        "friction_coefficient": mu,
        "normal_load": np.full(s.size, 3.0),
        "distance": s,
        "laps": laps,
    }
    body = RunCreate(
        stand=StandKind.PIN_ON_DISC,
        operator="test",
        configuration={"track_radius": RADIUS},
    )
    sim: SimulatedRun[None] = SimulatedRun(body, (Batch("friction", columns, 0.0),), None)
    return analysed(StandKind.PIN_ON_DISC, sim)


def _record_run(mu_of: Any, length: float, seed: int = 0) -> PinOnDiscResults:
    values = _record(mu_of, length, seed).result.values
    assert isinstance(values, PinOnDiscResults)
    return values


def _drifting(s: NDArray[np.float64]) -> NDArray[np.float64]:
    """The record of issue 37: a rise to a peak held from 2 to 6 m, down to the level by
    7 m, then a drift of 7 % over the 23 m left."""
    rise = 0.3 + 0.45 * s / 2.0
    fall = 0.75 - 0.25 * (s - 6.0)
    steady = 0.5 * (1.0 + 0.07 * (s - 7.0) / 23.0)
    return np.select([s < 2.0, s < 6.0, s < 7.0], [rise, np.full_like(s, 0.75), fall], steady)


def test_a_drifting_steady_state_runs_in_for_about_seven_metres() -> None:
    v = _record_run(_drifting, 30.0)
    # the band about the tail's mean m ≈ 0.5·(1 + 0.035) = 0.518 is entered where the fall
    # 0.75 - 0.25·(s - 6) reaches (1 + δ)·m ≈ 0.543 (s ≈ 6.83 m), the noise allowance
    # z·σ̂ of a block of laps moving it by a few centimetres
    assert v.running_in_distance is not None
    assert 6.5 <= v.running_in_distance <= 7.2
    assert v.friction_steady == pytest.approx(0.5 * 1.035, abs=0.005)
    assert v.friction_static == pytest.approx(0.75, abs=0.1)  # the peak, 0.75 + noise


def test_a_record_without_running_in_is_steady_from_its_start() -> None:
    v = _record_run(lambda s: 0.4 + 0.0 * s, 10.0)
    assert v.running_in_distance == 0.0
    assert v.friction_steady == pytest.approx(0.4, abs=0.002)


def test_a_record_that_never_settles_says_so_without_a_number() -> None:
    # μ falls from 0.8 to 0.3 over the record, steadily: its last fifth alone spans 0.1
    v = _record_run(lambda s: 0.8 - 0.5 * s / 10.0, 10.0)
    assert v.running_in_distance is None and v.running_in_laps is None
    assert v.friction_steady is None and v.friction_steady_uncertainty is None
    assert any("did not settle" in note for note in v.notes)
    assert v.friction_static == pytest.approx(0.8, abs=0.06)


@pytest.mark.parametrize(
    ("lang", "said"), [("en", "does not settle"), ("ru", "не устанавливается")]
)
def test_the_report_of_a_record_that_never_settles_says_so(lang: Lang, said: str) -> None:
    s = _record(lambda s: 0.8 - 0.5 * s / 10.0, 10.0)
    html = report_html(s, lang)
    assert said in html


@settings(max_examples=60, deadline=None)
@given(
    level=st.floats(0.05, 1.5),
    n=st.integers(4, 400),
    seed=st.integers(0, 2**32 - 1),
)
def test_a_record_inside_the_band_is_steady_from_its_start(level: float, n: int, seed: int) -> None:
    # values within ±ε·c of any level c, ε = δ/(2 + δ): their mean m ≥ c(1 - ε) and any
    # value's distance from it ≤ 2εc ≤ δ·c·(1 - ε) ≤ δ·m
    eps = STEADY_BAND / (2.0 + STEADY_BAND)
    y = level * (1.0 + eps * np.random.default_rng(seed).uniform(-1.0, 1.0, n))
    assert settled_from(y) == 0


@settings(max_examples=60, deadline=None)
@given(
    level=st.floats(0.05, 1.5),
    n=st.integers(50, 400),
    rise=st.floats(2.0, 5.0),
    falling=st.booleans(),
)
def test_a_steady_ramp_never_settles(level: float, n: int, rise: float, falling: bool) -> None:
    # y = c(1 + r·i/(n - 1)): a tail of k ≥ n/5 values spans c·r·(k - 1)/(n - 1) ≥ 0.18·c·r
    # (n ≥ 50), half of it from the tail's mean at least, above δ·c·(1 + r) for r ≥ 2
    ramp = level * (1.0 + rise * np.arange(n) / (n - 1))
    assert settled_from(ramp[::-1] if falling else ramp) is None


@settings(max_examples=60, deadline=None)
@given(
    n=st.integers(20, 400),
    first=st.floats(0.0, 1.0 - STEADY_SHARE),
    peak=st.floats(1.2, 3.0),
)
def test_a_step_down_into_the_band_ends_the_running_in_there(
    n: int, first: float, peak: float
) -> None:
    # a plateau of k blocks at p > 1.2 above a flat level 1 whose tail holds at least the
    # share: from any j < k the tail's mean is < p and > 1, its first value p exceeds it
    # by more than δ unless p ≤ (1 + δ)·m; the flat tail itself is steady
    k = min(int(first * n), n - math.ceil(STEADY_SHARE * n))
    y = np.r_[np.full(k, peak), np.ones(n - k)]
    found = settled_from(y)
    assert found is not None and found <= k
    # where the plateau is short enough that its tail's mean stays within p/(1 + δ) the
    # running-in is the plateau, to the block
    means = [y[j:].mean() for j in range(k)]
    if all(peak > (1.0 + STEADY_BAND) * m for m in means):
        assert found == k


def test_the_band_rejects_what_is_not_a_record() -> None:
    from rigserver.core.errors import ModelInputError

    with pytest.raises(ModelInputError, match="levels must be finite"):
        settled_from([0.5, float("nan")])
    with pytest.raises(ModelInputError, match="band"):
        settled_from([0.5, 0.5], band=1.5)
