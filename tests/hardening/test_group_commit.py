"""Group commits of the HDF5 store: several batches per journal commit, each refused alone;
a failed commit leaves no trace; the readings live in payload files until the run is final."""

from __future__ import annotations

import sqlite3
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pytest

from rigserver.storage import (
    HDF5Store,
    NewBatch,
    SequenceConflict,
    StorageFull,
    StorageUnavailable,
)
from rigserver.storage.base import Columns
from rigserver.storage.embedded.journal import Journal
from schemas.readings import BatchReceipt
from schemas.runs import RunState
from tests.storage.conftest import friction, make_run


def test_one_commit_for_many_batches_each_refused_alone(tmp_path: Path) -> None:
    seen: list[dict[str, float]] = []

    def check(columns: Columns, last: Mapping[str, float]) -> None:
        seen.append(dict(last))
        if columns["load"][0] > 1000:
            raise ValueError("load too high")

    with HDF5Store(tmp_path) as store:
        a, b = store.create_run(make_run()).id, store.create_run(make_run()).id
        bad = friction(10, 10)
        bad["load"] = np.full(10, 2000.0)
        outcomes = store.append_many(
            [
                NewBatch(a, 0, "friction", friction(0, 10), check),
                NewBatch(b, 0, "friction", friction(0, 5), check),
                NewBatch(a, 1, "friction", bad, check),  # refused by its check
                NewBatch(a, 1, "friction", friction(10, 10), check),  # the seq, now right
                NewBatch(a, 1, "friction", friction(10, 10), check),  # a retry in the call
                NewBatch(a, 0, "friction", friction(50, 10), check),  # a reused seq
                NewBatch("20240301T090000Z-00000000", 0, "friction", friction(0, 1)),
            ]
        )
        kinds = [type(o).__name__ for o in outcomes]
        assert kinds == [
            "BatchReceipt",
            "BatchReceipt",
            "ValueError",
            "BatchReceipt",
            "BatchReceipt",
            "SequenceConflict",
            "RunNotFound",
        ]
        receipts = [o for o in outcomes if isinstance(o, BatchReceipt)]
        assert [(r.seq, r.group_rows, r.duplicate) for r in receipts] == [
            (0, 10, False),
            (0, 5, False),
            (1, 20, False),
            (1, 20, True),
        ]
        assert isinstance(outcomes[5], SequenceConflict)
        # each check saw the last values left by the batches before it in the call
        # (friction(0, 10) ends at time 4.5, load 300 + 9 % 3 = 300)
        assert seen[0] == {}
        assert seen[2]["time"] == 4.5
        assert seen[3]["time"] == 4.5  # the refused batch left nothing
        assert store.get_run(a).rows["friction"] == 20
        assert store.get_run(a).batches == 2
        np.testing.assert_array_equal(
            store.read(a, "friction", ["time"])["time"], friction(0, 20)["time"]
        )


def test_a_failed_group_commit_leaves_no_trace(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    store = HDF5Store(tmp_path)
    run_id = store.create_run(make_run()).id
    store.append(run_id, 0, "friction", friction(0, 10))
    real = Journal.add_batch
    calls = 0

    def third_fails(self: Journal, *args: object) -> object:
        nonlocal calls
        calls += 1
        if calls == 3:
            raise sqlite3.OperationalError("database or disk is full")
        return real(self, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(Journal, "add_batch", third_fails)
    batches = [NewBatch(run_id, s, "friction", friction(10 * s, 10)) for s in (1, 2, 3, 4)]
    # seq 1 twice: the second is a retry of the first, which the failure takes away too
    outcomes = store.append_many([batches[0], batches[0], *batches[1:]])
    assert all(isinstance(o, StorageFull) for o in outcomes)
    monkeypatch.setattr(Journal, "add_batch", real)
    assert store.get_run(run_id).rows["friction"] == 10
    assert store.last_values(run_id, "friction")["time"] == 4.5
    assert store.receipt(run_id, 1) is None
    outcomes = store.append_many(
        [NewBatch(run_id, s, "friction", friction(10 * s, 10)) for s in (1, 2, 3, 4)]
    )
    assert [o.group_rows for o in outcomes if isinstance(o, BatchReceipt)] == [20, 30, 40, 50]
    store.close()
    with HDF5Store(tmp_path) as store:  # and so after a reopen
        np.testing.assert_array_equal(
            store.read(run_id, "friction", ["time"])["time"], friction(0, 50)["time"]
        )


def test_readings_live_in_payload_files_until_the_run_is_final(tmp_path: Path) -> None:
    payloads = tmp_path / "payloads"
    with HDF5Store(tmp_path) as store:
        run_id = store.create_run(make_run()).id
        store.append(run_id, 0, "friction", friction(0, 1000))
        # 5 channels x 1000 rows x 8 B, and the header with the names
        assert (payloads / f"{run_id}.bin").stat().st_size > 40_000
        store.end_run(run_id, RunState.FINISHED)
        assert not (payloads / f"{run_id}.bin").exists()
    (payloads / f"{run_id}.bin").write_bytes(b"left by a crash before the unlink")
    with HDF5Store(tmp_path) as store:
        assert not (payloads / f"{run_id}.bin").exists()
        assert store.get_run(run_id).rows["friction"] == 1000


def test_a_journal_of_an_older_rigserver_is_refused_with_a_way_out(tmp_path: Path) -> None:
    with sqlite3.connect(tmp_path / "journal.sqlite") as db:
        db.execute(
            "CREATE TABLE batches (n INTEGER PRIMARY KEY, run_id TEXT, seq INTEGER, grp TEXT, "
            "rows INTEGER, group_rows INTEGER, digest BLOB, UNIQUE (run_id, seq))"
        )
    with pytest.raises(StorageUnavailable, match=r"older rigserver.*move it away"):
        HDF5Store(tmp_path)
