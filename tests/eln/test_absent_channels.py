"""Issue 37, item 8: a run whose record lacks channels (a vendor's file without temperature,
distance or wear depth; stored as NaN) exports to .eln and imports back with equal readings
and results, whatever it lacks, in every batch or in some."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rigsim.batches import Batch
from rigsim.cli import settings_for
from rigsim.stands import SIMULATORS
from schemas.stands import StandKind
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
