"""A series' statistics on simulated runs: the 95 % interval of the mean covers the truth
at its stated rate, levels are compared, outliers are flagged, aborted runs left out."""

from __future__ import annotations

import math
from datetime import UTC, datetime
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rigserver.analysis import analyse
from rigserver.analysis.series import Member, series_statistics
from rigsim.batches import SimulatedRun
from rigsim.simulators import simulate
from rigsim.simulators.smts2 import MODES, Mode, Smts2Settings
from schemas.runs import Run, RunState
from schemas.series import ResultStatistics, Series, SeriesPurpose
from schemas.stands import StandKind, default_stands, with_overrides
from tests.reports.simulated import SimulatedReadings

MADE = datetime(2026, 11, 25, 12, 0, tzinfo=UTC)
STAND = default_stands()[StandKind.SMTS2]


def smts2_run(
    index: int, friction: float, seed: int, state: RunState = RunState.FINISHED
) -> Member:
    """A simulated SMTs-2 run (2000 revolutions) analysed as the service would."""
    sim = simulate(
        StandKind.SMTS2, Smts2Settings(revolutions=2000.0, friction_steady=friction), seed=seed
    )
    return _member(index, sim, state)


def _member(index: int, sim: SimulatedRun[Any], state: RunState) -> Member:
    """A simulated SMTs-2 run as a stored run (its test plan kept), analysed as the service
    would."""
    readings = SimulatedReadings(sim)
    run = Run(
        id=f"20261125T120000Z-{index:08x}",
        stand=StandKind.SMTS2,
        state=state,
        operator="group 1",
        test_plan=sim.run_create.test_plan,
        configuration=with_overrides(STAND.configuration, sim.run_create.configuration).model_dump(
            mode="json"
        ),
        created=MADE,
        rows={g.name: readings.rows(g.name) for g in STAND.groups},
    )
    return Member(run=run, level=None, values=analyse(run, readings).payload["values"])


def repeatability(members: list[Member]) -> Series:
    return Series(
        id="s-000000000001", name="repeats", purpose=SeriesPurpose.REPEATABILITY, created=MADE
    )


def friction_statistics(members: list[Member], series: Series | None = None) -> ResultStatistics:
    detail = series_statistics(series or repeatability(members), members, [])
    return next(s for s in detail.statistics if s.key == "friction_steady")


@settings(max_examples=4, deadline=None)
@given(
    f0=st.floats(0.25, 0.55),
    spread=st.floats(0.01, 0.04),
    runs=st.integers(3, 6),
    base=st.integers(0, 10_000),
)
def test_interval_covers_the_truth_at_its_stated_rate(
    f0: float, spread: float, runs: int, base: int
) -> None:
    """M series of `runs` simulated repeats, each specimen's steady friction drawn from
    N(f0, spread²) (the known spread between specimens); the 95 % interval of the series'
    mean covers f0 in about 95 % of the series.

    Tolerance: were the intervals exact, the count covered is Binomial(M, 0.95), standard
    deviation √(0.95·0.05/M) = 0.0154 for M = 200; 3.5 of those either side fails a correct
    implementation with probability 5·10⁻⁴. The analysis adds to each run's value its own
    estimation error (within-run sd ≈ 0.003, measured over 20 seeds at 2000 rev, which the
    interval absorbs as spread) and a bias of ≈ +0.001 (the running-in tail); a bias b in a
    t-interval of n ≤ 6 runs with spread ≥ 0.01 shifts it by at most b·√n/s = 0.25 standard
    errors, lowering coverage by under 0.01: the lower bound allows that much more.
    """
    rng = np.random.default_rng(base)
    series_count = 200
    covered = 0
    for k in range(series_count):
        members = [
            smts2_run(i, float(rng.normal(f0, spread)), seed=base * 7919 + k * runs + i)
            for i in range(runs)
        ]
        overall = friction_statistics(members).overall
        assert overall is not None and overall.ci_low is not None and overall.ci_high is not None
        covered += overall.ci_low <= f0 <= overall.ci_high
    sd = math.sqrt(0.95 * 0.05 / series_count)
    assert 0.95 - 3.5 * sd - 0.01 <= covered / series_count <= 0.95 + 3.5 * sd


def test_comparison_of_two_oils_finds_the_difference() -> None:
    low = [smts2_run(i, 0.30, seed=100 + i) for i in range(4)]
    high = [smts2_run(10 + i, 0.45, seed=200 + i) for i in range(4)]
    members = [Member(m.run, "oil A", m.values) for m in low] + [
        Member(m.run, "oil B", m.values) for m in high
    ]
    series = Series(
        id="s-000000000002",
        name="two oils",
        purpose=SeriesPurpose.COMPARISON,
        factor="oil",
        created=MADE,
    )
    stats_ = friction_statistics(members, series)
    assert [level.level for level in stats_.levels] == ["oil A", "oil B"]
    comparison = stats_.comparison
    assert comparison is not None and comparison.test == "welch" and comparison.significant
    # The friction coefficients differ by 0.15 by construction; the interval holds it.
    assert comparison.difference_low is not None and comparison.difference_high is not None
    assert comparison.difference_low < 0.15 < comparison.difference_high


def test_outlier_is_flagged_and_kept_aborted_runs_left_out() -> None:
    members = [smts2_run(i, 0.40, seed=300 + i) for i in range(5)]
    members.append(smts2_run(5, 0.60, seed=305))  # a pin of another steel slipped in
    members.append(smts2_run(6, 0.10, seed=306, state=RunState.ABORTED))
    stats_ = friction_statistics(members)
    overall = stats_.overall
    assert overall is not None and overall.n == 6  # the aborted run is not counted
    assert overall.grubbs is not None and overall.grubbs.outlier
    assert overall.grubbs.run_id == members[5].run.id
    assert members[5].run.id in [v.run_id for v in stats_.values]  # flagged, not removed


def test_series_without_runs_has_no_statistics() -> None:
    detail = series_statistics(repeatability([]), [], ["20261125T120000Z-0000dead: not found"])
    assert detail.stand is None and detail.statistics == [] and detail.missing


@pytest.mark.parametrize("kind", list(StandKind))
def test_every_headline_has_a_unit_and_a_description(kind: StandKind) -> None:
    from tests.reports.simulated import simulated

    sim = simulated(kind)
    member = Member(run=sim.run, level=None, values=sim.result.payload["values"])
    detail = series_statistics(repeatability([member]), [member], [])
    assert detail.statistics, kind
    for s in detail.statistics:
        assert s.unit and s.description != s.key, s.key
        assert s.overall is not None and s.overall.n == 1, s.key


@pytest.mark.parametrize(
    ("kind", "key", "own"),
    [
        (StandKind.SMTS2, "friction_steady", ("friction_steady_uncertainty",)),
        (
            StandKind.MTOS,
            "steps[2].friction_measured",
            ("steps", 2, "friction_measured_uncertainty"),
        ),
        (StandKind.PROFILOMETER, "ra", ("ra_uncertainty",)),
    ],
)
def test_each_run_shows_its_own_uncertainty_beside_the_spread(
    kind: StandKind, key: str, own: tuple[str | int, ...]
) -> None:
    from tests.reports.simulated import simulated

    sim = simulated(kind)
    values = sim.result.payload["values"]
    expected = values
    for part in own:
        expected = expected[part]
    member = Member(run=sim.run, level=None, values=values)
    detail = series_statistics(repeatability([member]), [member], [])
    found = next(s for s in detail.statistics if s.key == key)
    assert expected is not None and found.values[0].uncertainty == expected


def _mode_run(index: int, mode: Mode, seed: int) -> Member:
    """A simulated SMTs-2 run of lab work 2's second part, its mode in the test plan."""
    sim = simulate(StandKind.SMTS2, Smts2Settings.for_mode(mode), seed=seed)
    return _member(index, sim, RunState.FINISHED)


def test_adhesive_and_oxidative_levels_give_delta_f() -> None:
    """A comparison whose levels are the two modes: f_a, f_ok the levels' mean steady f and
    Δf = (f_a - f_ok)/f_a·100 % (2.16), recomputed here from the runs' own results."""
    runs = [(_mode_run(i, mode, seed=400 + i), mode) for i, mode in enumerate(MODES[1:] * 2)]
    members = [Member(m.run, f"pin {mode}", m.values) for m, mode in runs]  # the plan's mode
    series = Series(
        id="s-000000000003",
        name="adhesive and oxidative",
        purpose=SeriesPurpose.COMPARISON,
        factor="mode",
        created=MADE,
    )
    found = series_statistics(series, members, []).adhesive_oxidative
    assert found is not None
    f = {mode: [m.values["friction_steady"] for m, k in runs if k == mode] for mode in MODES[1:]}
    f_a, f_ok = (sum(v) / len(v) for v in f.values())
    assert found.f_adhesive == pytest.approx(f_a, rel=1e-12)
    assert found.f_oxidative == pytest.approx(f_ok, rel=1e-12)
    assert found.difference == pytest.approx((f_a - f_ok) / f_a * 100, rel=1e-12)
    # the simulator's modes: f ≈ 0.55 adhesive, 0.3 oxidative (the manual's ordering)
    assert found.difference > 0
    one_level = [Member(m.run, "all", m.values) for m, _ in runs]
    assert series_statistics(series, one_level, []).adhesive_oxidative is None
