"""Issue 37, item 8: a run whose record lacks channels (a vendor's file without temperature,
distance or wear depth; stored as NaN) exports to .eln and imports back with equal readings
and results, whatever it lacks, in every batch or in some."""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rigserver.api.problems import ApiProblem
from rigserver.api.routes.eln import _checked
from rigsim.batches import Batch
from rigsim.cli import settings_for
from rigsim.simulators import SIMULATORS
from schemas.stands import StandKind, default_stands
from tests.api.conftest import WRITER
from tests.eln.conftest import Lab, export, import_archive
from tests.eln.test_import import _results, _run_file
from tests.reports.simulated import post

#: The friction record's channels a vendor's file may lack (time and μ it always has).
OPTIONAL = {
    StandKind.PIN_ON_DISC: ("distance", "laps", "temperature", "wear_depth", "friction_force"),
    StandKind.RECIPROCATING: (
        "distance",
        "laps",
        "temperature",
        "wear_depth",
        "friction_force",
        "position",
        "stroke",
    ),
}


@st.composite
def _cases(draw: st.DrawFn) -> tuple[StandKind, frozenset[str], bool]:
    kind = draw(st.sampled_from(sorted(OPTIONAL, key=lambda k: k.value)))
    left_out = draw(st.frozensets(st.sampled_from(OPTIONAL[kind]), min_size=1))
    return kind, left_out, draw(st.booleans())


@settings(
    max_examples=6,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(case=_cases())
def test_a_run_lacking_channels_comes_back_whole(
    lab: Lab, case: tuple[StandKind, frozenset[str], bool]
) -> None:
    kind, left_out, every_batch = case
    s = replace(settings_for(kind, noise=True), laps=40, running_in_laps=8, batch_rows=600)
    sim = SIMULATORS[kind].simulate(s, 5)
    friction = [i for i, b in enumerate(sim.batches) if b.group == "friction"]
    # every batch without them, or every other one (a record that gained a sensor mid-way)
    lacking = set(friction if every_batch else friction[::2])
    batches = tuple(
        Batch(b.group, {n: v for n, v in b.columns.items() if n not in left_out}, b.at)
        if i in lacking
        else b
        for i, b in enumerate(sim.batches)
    )
    original = post(lab.source, replace(sim, batches=batches), WRITER)
    archive = export(lab.source, f"/api/v1/runs/{original}/export.eln")
    answer = import_archive(lab.target, archive)
    assert answer.status_code == 201, answer.text
    imported = answer.json()["id"]
    before, after = _run_file(lab.source, original), _run_file(lab.target, imported)
    assert before.keys() == after.keys()
    for name in left_out:
        assert np.isnan(before[f"friction/{name}"]).any(), name  # stored as absent
    for name, values in before.items():
        np.testing.assert_array_equal(after[name], values, err_msg=name)
    assert _results(lab.target, imported) == _results(lab.source, original)


def _check(columns: dict[str, np.ndarray]) -> None:
    stand = default_stands()[StandKind.PIN_ON_DISC]
    batches = iter([(0, SimpleNamespace(group="friction"), columns)])
    list(_checked(batches, stand))


def test_the_channels_a_run_of_rows_lacks_are_not_checked() -> None:
    # the archive of issue 37: no distance at all, a temperature in the first rows only;
    # refused before as "distance[0] = nan is not a finite number"
    n = 6
    _check(
        {
            "time": np.arange(n, dtype=np.float64),
            "friction_coefficient": np.full(n, 0.5),
            "distance": np.full(n, np.nan),
            "temperature": np.r_[20.0, 21.0, 22.0, np.full(3, np.nan)],
        }
    )


def test_a_bad_reading_among_absent_ones_is_still_refused() -> None:
    # the temperature's rows present are checked as posted: 5000 °C is past its limit, and
    # the distance must not decrease across the rows that have it
    n = 4
    base = {"time": np.arange(n, dtype=np.float64), "friction_coefficient": np.full(n, 0.5)}
    with pytest.raises(ApiProblem, match=r"temperature\[1\] = 5000"):
        _check({**base, "temperature": np.r_[20.0, 5000.0, np.nan, np.nan]})
    with pytest.raises(ApiProblem, match="distance"):
        _check({**base, "distance": np.r_[1.0, 0.5, 0.4, np.nan]})
