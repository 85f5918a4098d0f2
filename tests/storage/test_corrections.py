"""Corrections of stored readings in every store: the values as typed are kept, the
corrections listed in order with the value each replaced, checked as a post is, durable in
the embedded store's journal and run file."""

from __future__ import annotations

import math
from collections.abc import Iterator
from contextlib import closing
from pathlib import Path

import h5py
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rigserver.storage import HDF5Store, MemoryStore, RunStore
from rigserver.storage.corrections import CorrectedReadings, CorrectionRefused, applied
from rigserver.storage.runfile import RunFile, corrected_copy
from schemas.corrections import Correction
from schemas.runs import RunState
from schemas.stands import MEASUREMENTS, StandKind
from tests.storage.conftest import T0, friction, make_run, open_store


@pytest.fixture(params=["memory", "hdf5", "postgres"])
def store(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[RunStore]:
    s = open_store(request.param, tmp_path, request)
    yield s
    s.close()


def _run_with_rows(store: RunStore, rows: int = 10) -> str:
    run_id = store.create_run(make_run()).id
    store.append(run_id, 0, "friction", friction(0, rows))
    store.append(run_id, 1, MEASUREMENTS, {"pin_mass_before": np.array([12.3456])})
    store.append(run_id, 2, MEASUREMENTS, {"pin_mass_after": np.array([12.3400])})
    return run_id


def test_two_corrections_of_one_cell_are_both_listed_with_what_they_replaced(
    store: RunStore,
) -> None:
    run_id = _run_with_rows(store)
    typed = float(friction(0, 10)["friction_moment"][3])
    first = store.correct_reading(run_id, "friction", 3, {"friction_moment": 4.0}, "misread", "k")
    row = store.correct_reading(run_id, "friction", 3, {"friction_moment": 4.5}, "again", "k")
    assert row.values["friction_moment"] == 4.5
    assert row.original["friction_moment"] == typed
    assert first.corrections[0].was == typed
    listed = store.corrections(run_id)
    assert [(c.n, c.row, c.channel, c.was, c.now, c.reason) for c in listed] == [
        (1, 3, "friction_moment", typed, 4.0, "misread"),
        (2, 3, "friction_moment", 4.0, 4.5, "again"),
    ]
    assert all(c.by == "k" and c.unit == "N*m" for c in listed)
    # the values as typed are never overwritten
    assert store.read(run_id, "friction", ["friction_moment"], 3, 4)["friction_moment"][0] == typed
    assert store.get_run(run_id).corrections == 2


def test_a_retry_stores_nothing_and_a_struck_row_takes_no_correction(store: RunStore) -> None:
    run_id = _run_with_rows(store)
    store.correct_reading(run_id, "friction", 3, {"load": 301.0}, "misread", "k")
    again = store.correct_reading(run_id, "friction", 3, {"load": 301.0}, "misread", "k")
    assert len(again.corrections) == 1
    struck = store.strike_reading(run_id, "friction", 5, "typed twice", "k")
    assert struck.struck and struck.corrections[-1].channel is None
    assert len(store.strike_reading(run_id, "friction", 5, "typed twice", "k").corrections) == 1
    with pytest.raises(CorrectionRefused, match="row 5 of friction is struck out") as refused:
        store.correct_reading(run_id, "friction", 5, {"load": 301.0}, "x", "k")
    assert refused.value.violations[0].field == "index"
    assert len(store.corrections(run_id)) == 2


@pytest.mark.parametrize(
    ("values", "reason", "field", "message"),
    [
        ({"friction_moment": 15.5}, "r", "values.friction_moment", "0 <= value <= 15 N\\*m"),
        ({"friction_moment": math.nan}, "r", "values.friction_moment", "not a finite number"),
        ({"speed": 700.0}, "r", "values.speed", "one of 300, 500, 1000 rpm"),
        ({"wear": 1.0}, "r", "values.wear", "has no channel 'wear'"),
        # time must increase: row 3 sits between 1.0 s and 2.0 s (friction(): 0.5 s a row)
        ({"time": 2.5}, "r", "values.time", "the value after it is 2 s"),
        ({"load": 301.0}, "  ", "reason", "1 to 500 characters"),
        ({"load": 301.0}, "x" * 501, "reason", "1 to 500 characters"),
    ],
)
def test_a_bad_correction_is_refused_naming_the_field(
    store: RunStore, values: dict[str, float], reason: str, field: str, message: str
) -> None:
    run_id = _run_with_rows(store)
    with pytest.raises(CorrectionRefused, match=message) as refused:
        store.correct_reading(run_id, "friction", 3, values, reason, "k")
    assert refused.value.violations[0].field == field
    assert store.corrections(run_id) == []


def test_an_index_out_of_range_or_an_unknown_group_is_refused(store: RunStore) -> None:
    run_id = _run_with_rows(store)
    with pytest.raises(CorrectionRefused, match=r"friction has no row 10 \(0 <= index < 10\)"):
        store.correct_reading(run_id, "friction", 10, {"load": 301.0}, "r", "k")
    with pytest.raises(CorrectionRefused, match="no group 'wear_track'") as refused:
        store.strike_reading(run_id, "wear_track", 0, "r", "k")
    assert refused.value.violations[0].field == "group"
    # a cell nothing was posted to (measurements: NaN) is posted, not corrected
    with pytest.raises(CorrectionRefused, match="holds no pin_mass_after"):
        store.correct_reading(run_id, MEASUREMENTS, 0, {"pin_mass_after": 12.0}, "r", "k")


def test_a_finished_run_is_corrected_and_says_so(store: RunStore) -> None:
    run_id = _run_with_rows(store)
    store.correct_reading(run_id, "friction", 1, {"load": 302.0}, "before the end", "k")
    assert not store.get_run(run_id).corrected_after_finish
    store.end_run(run_id, RunState.FINISHED)
    store.correct_reading(run_id, MEASUREMENTS, 1, {"pin_mass_after": 12.3410}, "scale", "k")
    run = store.get_run(run_id)
    assert run.corrected_after_finish and run.corrections == 2
    with RunFile.open(store.run_file(run_id), writable=False) as rf:
        held = rf.corrections()
        assert rf.read(MEASUREMENTS, ["pin_mass_after"], 1, 2)["pin_mass_after"][0] == 12.34
    assert [c.now for c in held] == [302.0, 12.3410]


def test_the_run_file_keeps_the_values_as_typed_and_the_table_with_units(
    tmp_path: Path,
) -> None:
    with HDF5Store(tmp_path / "data") as store:
        run_id = _run_with_rows(store)
        store.correct_reading(run_id, "friction", 2, {"friction_moment": 2.5}, "misread", "k")
        store.strike_reading(run_id, "friction", 4, "typed twice", "k")
        path = store.run_file(run_id)
    with h5py.File(path, "r") as f:  # plain h5py, as a lab user opens it
        entry = f["entry"]
        assert entry["friction/friction_moment"][2] == friction(0, 10)["friction_moment"][2]
        table = entry["corrections"]
        assert table.attrs["NX_class"] == "NXcollection"
        assert list(table["row"][()]) == [2, 4]
        assert list(table["channel"].asstr()[()]) == ["friction_moment", ""]
        assert list(table["unit"].asstr()[()]) == ["N*m", ""]
        assert table["now"][0] == 2.5 and math.isnan(table["now"][1])
        assert table["was"].attrs["units"] == "see unit"
    # reopened, the store has them (the journal), and so has the file
    with HDF5Store(tmp_path / "data") as store:
        assert [c.reason for c in store.corrections(run_id)] == ["misread", "typed twice"]
        copy = tmp_path / "corrected.h5"
        corrected_copy(store.run_file(run_id), copy)
    with h5py.File(copy, "r") as f:
        moment = f["entry/friction/friction_moment"][()]
        expected = np.delete(friction(0, 10)["friction_moment"], 4)
        expected[2] = 2.5
        np.testing.assert_array_equal(moment, expected)
        assert f["entry/friction/time"].shape == (9,)
        assert "corrected" in f["entry"].attrs["readings"]


def test_an_imported_run_brings_its_corrections(tmp_path: Path) -> None:
    original = make_run(StandKind.SMTS2)
    fixes = [
        Correction(
            n=1,
            group="friction",
            row=0,
            channel="load",
            was=300.0,
            now=302.0,
            unit="N",
            reason="r",
            by="k",
            at=T0,
        )
    ]
    stores: list[RunStore] = [HDF5Store(tmp_path / "data"), MemoryStore()]
    for store in stores:
        with closing(store):
            update = {"state": RunState.FINISHED, "ended": T0, "corrections": 1}
            run = original.model_copy(update=update)
            assert store.import_run(run, None, None, [], fixes)
            assert store.corrections(run.id) == fixes
            with RunFile.open(store.run_file(run.id), writable=False) as rf:
                assert rf.corrections() == fixes


class _Rows:
    """A group of one channel ``v`` = 0, 1, 2, ... read in chunks (analysis.Readings)."""

    def __init__(self, n: int) -> None:
        self.values = np.arange(n, dtype=np.float64)

    def rows(self, group: str) -> int:
        return len(self.values)

    def read(self, group: str, channels: list[str] | None = None) -> dict[str, np.ndarray]:
        return {"v": self.values.copy()}

    def iter_chunks(
        self, group: str, channels: list[str] | None = None, rows: int = 1 << 20
    ) -> Iterator[dict[str, np.ndarray]]:
        for start in range(0, len(self.values), rows):
            yield {"v": self.values[start : start + rows].copy()}

    def measurements(self) -> dict[str, float]:
        return {}


@settings(max_examples=60, deadline=None)
@given(
    n=st.integers(1, 40),
    chunk=st.integers(1, 50),
    edits=st.lists(st.tuples(st.integers(0, 39), st.booleans()), max_size=12),
)
def test_corrected_chunks_join_to_the_corrected_whole(
    n: int, chunk: int, edits: list[tuple[int, bool]]
) -> None:
    """Whatever the chunk size, the corrected chunks are the corrected group: the later
    correction of a cell wins, a struck row is left out wherever it falls."""
    fixes = [
        Correction(
            n=i + 1,
            group="g",
            row=row,
            channel=None if strike else "v",
            now=None if strike else -float(i),
            reason="r",
            by="k",
            at=T0,
        )
        for i, (row, strike) in enumerate(edits)
        if row < n
    ]
    readings = CorrectedReadings(_Rows(n), fixes)
    joined = np.concatenate([c["v"] for c in readings.iter_chunks("g", rows=chunk)])
    expected = {row: float(row) for row in range(n)}
    for c in fixes:
        if c.channel is None:
            expected.pop(c.row, None)
        elif c.row in expected:
            expected[c.row] = c.now  # type: ignore[assignment]
    struck = {c.row for c in fixes if c.channel is None}
    # a cell corrected after its row was struck stays out with its row
    want = [v for row, v in sorted(expected.items()) if row not in struck]
    np.testing.assert_array_equal(joined, want)
    np.testing.assert_array_equal(readings.read("g")["v"], want)
    assert readings.rows("g") == len(want)
    np.testing.assert_array_equal(applied({"v": np.arange(n, dtype=float)}, fixes, "g")["v"], want)
