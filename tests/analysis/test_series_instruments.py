"""Series statistics that respect the instruments: Grubbs' flag is an outlier only when the
run's deviation exceeds what the runs' own expanded uncertainties explain
(docs/series.md), and identical results in two runs are flagged as copied data."""

from __future__ import annotations

import math
from datetime import UTC, datetime

from rigserver.analysis.series import _explained, _summary, identical_runs
from schemas.runs import RunState
from schemas.series import SeriesRun
from schemas.stands import StandKind

#: Five runs, the last far from the others: Grubbs' G = 1.78 > G_crit(5, 0.05) = 1.715
#: (ASTM E178, table 1).
VALUES = [10.0, 10.1, 10.05, 10.08, 11.5]
IDS = [f"r{i}" for i in range(5)]


def test_a_flagged_run_beyond_its_uncertainty_is_an_outlier() -> None:
    summary = _summary(VALUES, IDS, 4, [0.05] * 5)
    g = summary.grubbs
    assert g is not None and g.flagged and g.run_id == "r4"
    # deviation from the others' mean; U = 2·√(0.05² + (√(4·0.05²)/4)²) = 0.1118
    assert g.deviation == 11.5 - (10.0 + 10.1 + 10.05 + 10.08) / 4
    assert g.explained is not None and math.isclose(g.explained, 2 * math.sqrt(0.0025 + 0.025**2))
    assert g.outlier


def test_a_flagged_run_its_instruments_explain_is_no_outlier() -> None:
    # each run's own u = 1.0: U = 2·√(1 + 0.25) = 2.236 > |Δ| = 1.4425
    g = _summary(VALUES, IDS, 4, [1.0] * 5).grubbs
    assert g is not None and g.flagged and not g.outlier
    assert g.deviation is not None and g.explained is not None
    assert abs(g.deviation) <= g.explained


def test_without_the_runs_uncertainties_grubbs_alone_decides() -> None:
    g = _summary(VALUES, IDS, 4).grubbs
    assert g is not None and g.flagged and g.outlier and g.explained is None
    assert _explained(0, [0.1, None, 0.1]) is None


def _row(run_id: str, values: dict[str, float | None]) -> SeriesRun:
    return SeriesRun(
        run_id=run_id,
        stand=StandKind.SMTS2,
        state=RunState.FINISHED,
        operator="o",
        created=datetime(2026, 11, 26, tzinfo=UTC),
        values=values,
    )


def test_identical_results_are_flagged_as_copied_data() -> None:
    rows = [
        _row("a", {"f": 0.4, "m": 49.5}),
        _row("b", {"f": 0.41, "m": 49.5}),
        _row("c", {"f": 0.4, "m": 49.5}),
        _row("d", {"f": None, "m": None}),
        _row("e", {"f": None, "m": None}),
    ]
    assert identical_runs(rows) == [["a", "c"]]
