"""HDF5Store only: reopening, the catalogue rebuilt from the files, disk full, recovery."""

from __future__ import annotations

import errno
import sqlite3
import threading
import tracemalloc
from pathlib import Path

import h5py
import numpy as np
import pytest

from rigserver.storage import HDF5Store, StorageFull, StorageUnavailable
from rigserver.storage.embedded import hdf5 as hdf5_module
from rigserver.storage.embedded import views
from rigserver.storage.embedded.journal import Journal
from rigserver.storage.runfile import STREAM_CHUNK_ROWS, TABLE_CHUNK_ROWS, RunFile
from schemas.runs import Run, RunQuery, RunState
from schemas.stands import StandKind
from tests.storage.conftest import friction, make_run

RESULTS = {"values": {"h_crit": 2.1e-6}, "units": {"h_crit": "m"}}


def _payload_count(data_dir: Path, run_id: str) -> int:
    """Batches of the run whose readings the journal keeps (in the run's payload file)."""
    payloads = data_dir / "payloads" / f"{run_id}.bin"
    if not payloads.exists():
        return 0
    with sqlite3.connect(data_dir / "journal.sqlite") as db:
        (count, size) = db.execute(
            "SELECT COUNT(*), COALESCE(SUM(size), 0) FROM batches WHERE run_id = ?", (run_id,)
        ).fetchone()
    assert payloads.stat().st_size >= size
    return int(count)


def test_reopen_after_a_clean_close_keeps_everything(tmp_path: Path) -> None:
    with HDF5Store(tmp_path) as store:
        done = store.create_run(make_run(stand=StandKind.MTOS))
        store.append(done.id, 0, "measurements", {"x_zero": [1.5]})
        store.set_results(done.id, RESULTS, {"h_crit": 2.1e-6})
        store.end_run(done.id, RunState.FINISHED)
        live = store.create_run(make_run())
        first = store.append(live.id, 0, "friction", friction(0, 30))
        store.append(live.id, 1, "measurements", {"pin_mass_before": [12.5]})
        before = store.list_runs(RunQuery())
    with HDF5Store(tmp_path) as store:
        assert store.list_runs(RunQuery()) == before
        assert store.results(done.id) == RESULTS
        assert store.receipt(live.id, 0) == first.model_copy(update={"duplicate": True})
        assert store.last_values(live.id, "measurements") == {"pin_mass_before": 12.5}
        assert store.last_values(live.id, "friction")["time"] == 14.5
        store.append(live.id, 2, "friction", friction(30, 10))
        np.testing.assert_array_equal(
            store.read(live.id, "friction", ["time"])["time"], friction(0, 40)["time"]
        )
        np.testing.assert_array_equal(store.read(done.id, "measurements")["x_zero"], [1.5])


def test_a_key_keeps_opening_the_same_run_after_reopening(tmp_path: Path) -> None:
    with HDF5Store(tmp_path) as store:
        first = store.create_run(make_run(), key="lab-pc-3/run-1")
    with HDF5Store(tmp_path) as store:
        assert store.create_run(make_run(), key="lab-pc-3/run-1").id == first.id
        assert store.list_runs(RunQuery()).total == 1


def test_a_retry_after_reopening_is_recognised(tmp_path: Path) -> None:
    # the largest stored seq of an open run is read back from the journal on opening
    with HDF5Store(tmp_path) as store:
        live = store.create_run(make_run())
        first = store.append(live.id, 3, "friction", friction(0, 10))
    with HDF5Store(tmp_path) as store:
        assert store.append(live.id, 3, "friction", friction(0, 10)) == first.model_copy(
            update={"duplicate": True}
        )
        assert store.get_run(live.id).rows["friction"] == 10


def test_one_store_at_a_time_per_directory(tmp_path: Path) -> None:
    with HDF5Store(tmp_path), pytest.raises(StorageUnavailable, match="in use"):
        HDF5Store(tmp_path)
    HDF5Store(tmp_path).close()  # the lock went with the first store


def test_closed_store_refuses_work(tmp_path: Path) -> None:
    store = HDF5Store(tmp_path)
    store.close()
    store.close()
    with pytest.raises(StorageUnavailable, match="closed"):
        store.list_runs(RunQuery())


def test_catalogue_is_rebuilt_from_the_run_files(tmp_path: Path) -> None:
    with HDF5Store(tmp_path) as store:
        done = store.create_run(make_run(operator="Petrov"))
        store.append(done.id, 0, "friction", friction(0, 20))
        store.set_results(done.id, RESULTS, {"h_crit": 2.1e-6})
        store.end_run(done.id, RunState.FINISHED)
        live = store.create_run(make_run(stand=StandKind.PROFILOMETER))
        store.append(live.id, 0, "profile", {"x": [0.0, 0.5, 1.0], "y": [1.0, -1.0, 0.5]})
        store.append(live.id, 1, "measurements", {"base_length": [0.8]})
        before = {r.id: r for r in store.list_runs(RunQuery()).runs}
    for name in ("journal.sqlite", "journal.sqlite-wal", "journal.sqlite-shm"):
        (tmp_path / name).unlink(missing_ok=True)

    with HDF5Store(tmp_path) as store:
        after = {r.id: r for r in store.list_runs(RunQuery()).runs}
        assert after[done.id] == before[done.id]
        assert store.results(done.id) == RESULTS
        np.testing.assert_array_equal(
            store.read(done.id, "friction", ["load"])["load"], friction(0, 20)["load"]
        )
        recovered = after[live.id]
        assert recovered.state is RunState.OPEN
        assert recovered.rows == {"profile": 3, "measurements": 1}
        store.append(live.id, 2, "profile", {"x": [1.5], "y": [0.25]})
        np.testing.assert_array_equal(
            store.read(live.id, "profile", ["y"])["y"], [1.0, -1.0, 0.5, 0.25]
        )
        assert store.last_values(live.id, "measurements") == {"base_length": 0.8}
        store.end_run(live.id, RunState.FINISHED)
    with h5py.File(tmp_path / "runs" / f"{live.id}.h5", "r") as f:
        assert bool(f["entry"].attrs["finalized"])
        np.testing.assert_array_equal(f["entry/profile/x"][:], [0.0, 0.5, 1.0, 1.5])


def test_unreadable_file_is_left_out_of_a_rebuilt_catalogue(tmp_path: Path) -> None:
    (tmp_path / "runs").mkdir()
    (tmp_path / "runs" / "20240301T090000Z-00000000.h5").write_bytes(b"not HDF5")
    with HDF5Store(tmp_path) as store:
        assert store.list_runs(RunQuery()).total == 0


def _open_run_of_ten_rows(tmp_path: Path) -> tuple[HDF5Store, Run]:
    """An embedded store in ``tmp_path`` and an open SMTs-2 run in it, its rows 0 to 9 stored."""
    store = HDF5Store(tmp_path)
    run = store.create_run(make_run())
    store.append(run.id, 0, "friction", friction(0, 10))
    return store, run


def _no_space(*args: object, **kwargs: object) -> None:
    raise OSError(errno.ENOSPC, "No space left on device")


def test_disk_full_in_the_journal_is_storage_full_and_passes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    store, run = _open_run_of_ten_rows(tmp_path)
    real = Journal.add_batch

    def full(*args: object, **kwargs: object) -> None:
        raise sqlite3.OperationalError("database or disk is full")

    monkeypatch.setattr(Journal, "add_batch", full)
    with pytest.raises(StorageFull, match="disk of the data directory is full"):
        store.append(run.id, 1, "friction", friction(10, 10))
    assert store.receipt(run.id, 1) is None
    monkeypatch.setattr(Journal, "add_batch", real)
    assert not store.append(run.id, 1, "friction", friction(10, 10)).duplicate
    store.close()
    with HDF5Store(tmp_path) as store:
        np.testing.assert_array_equal(
            store.read(run.id, "friction", ["time"])["time"], friction(0, 20)["time"]
        )


def test_disk_full_in_the_run_file_keeps_the_batch(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    store, run = _open_run_of_ten_rows(tmp_path)
    real = RunFile.append

    monkeypatch.setattr(RunFile, "append", _no_space)
    with pytest.raises(StorageFull, match="retry with the same seq"):
        store.append(run.id, 1, "friction", friction(10, 10))
    monkeypatch.setattr(RunFile, "append", real)
    # the batch was journaled: the retry is a duplicate, and the file view is rebuilt
    assert store.append(run.id, 1, "friction", friction(10, 10)).duplicate
    store.append(run.id, 2, "friction", friction(20, 10))
    np.testing.assert_array_equal(
        store.read(run.id, "friction", ["time"])["time"], friction(0, 30)["time"]
    )
    store.close()


def test_an_end_that_could_not_finalize_is_completed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    store, run = _open_run_of_ten_rows(tmp_path)
    with monkeypatch.context() as m:
        m.setattr(RunFile, "finalize", _no_space)
        with pytest.raises(StorageFull):
            store.end_run(run.id, RunState.FINISHED)
    assert store.get_run(run.id).state is RunState.FINISHED
    assert _payload_count(tmp_path, run.id) == 1  # kept until the file is final
    assert store.end_run(run.id, RunState.FINISHED).state is RunState.FINISHED
    assert _payload_count(tmp_path, run.id) == 0
    store.close()
    with h5py.File(tmp_path / "runs" / f"{run.id}.h5", "r") as f:
        assert bool(f["entry"].attrs["finalized"])
        np.testing.assert_array_equal(f["entry/friction/time"][:], friction(0, 10)["time"])


def test_payloads_are_dropped_once_the_file_is_final(tmp_path: Path) -> None:
    with HDF5Store(tmp_path) as store:
        run = store.create_run(make_run())
        first = store.append(run.id, 0, "friction", friction(0, 10))
        store.append(run.id, 1, "friction", friction(10, 10))
        assert _payload_count(tmp_path, run.id) == 2
        store.end_run(run.id, RunState.FINISHED)
        assert _payload_count(tmp_path, run.id) == 0
        assert store.append(run.id, 0, "friction", friction(0, 10)) == first.model_copy(
            update={"duplicate": True}
        )


def test_files_beyond_the_open_limit_are_closed_and_reopened(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(views, "MAX_OPEN_FILES", 2)
    with HDF5Store(tmp_path) as store:
        runs = [store.create_run(make_run()).id for _ in range(4)]
        for seq in range(3):
            for k, run_id in enumerate(runs):
                store.append(run_id, seq, "friction", friction(10 * seq + k, 1))
        for k, run_id in enumerate(runs):
            np.testing.assert_array_equal(
                store.read(run_id, "friction", ["time"])["time"],
                [0.5 * (10 * s + k) for s in range(3)],
            )


def test_synchronous_full(tmp_path: Path) -> None:
    with HDF5Store(tmp_path, synchronous="full") as store:
        run = store.create_run(make_run())
        store.append(run.id, 0, "friction", friction(0, 3))
        assert store.get_run(run.id).rows["friction"] == 3


def test_chunks_fit_the_group(tmp_path: Path) -> None:
    with HDF5Store(tmp_path) as store:
        run = store.create_run(make_run(stand=StandKind.SLIDE_BEARING))
        path = store.run_file(run.id)
    with h5py.File(path, "r") as f:
        assert f["entry/rows/p1"].chunks == (TABLE_CHUNK_ROWS,)
        assert f["entry/measurements/x_zero"].chunks == (TABLE_CHUNK_ROWS,)
    with HDF5Store(tmp_path) as store:
        run = store.create_run(make_run())
        path = store.run_file(run.id)
    with h5py.File(path, "r") as f:
        assert f["entry/friction/time"].chunks == (STREAM_CHUNK_ROWS,)


def test_iter_chunks_reads_in_bounded_memory(tmp_path: Path) -> None:
    rows = 1 << 20  # 8 MiB per channel
    with HDF5Store(tmp_path) as store:
        run = store.create_run(make_run(stand=StandKind.PROFILOMETER))
        x = np.linspace(0.0, 50.0, rows)
        store.append(run.id, 0, "profile", {"x": x, "y": np.sin(x)})
        store.end_run(run.id, RunState.FINISHED)
        tracemalloc.start()
        try:
            total = 0.0
            for chunk in store.iter_chunks(run.id, "profile", ["x"], rows=1 << 16):
                total += float(chunk["x"].sum())
            _, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
    assert total == pytest.approx(float(x.sum()), rel=1e-12)
    assert peak < 2 * 8 * (1 << 16) + (1 << 20)  # a chunk or two, not the 8 MiB channel


def test_other_runs_go_on_while_an_ended_runs_file_is_fsynced(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the fsync of a large run's file takes seconds: it must not hold the store's lock
    store = HDF5Store(tmp_path)
    ending = store.create_run(make_run())
    other = store.create_run(make_run())
    store.append(ending.id, 0, "friction", friction(0, 1000))
    during: dict[str, object] = {}
    fsync = hdf5_module.fsync_path

    def slow_fsync(path: Path) -> None:
        if path.name == f"{ending.id}.h5":
            worker = threading.Thread(
                target=lambda: during.update(
                    receipt=store.append(other.id, 0, "friction", friction(0, 5)),
                    rows=store.read(ending.id, "friction", ["time"])["time"].size,
                )
            )
            worker.start()
            worker.join(timeout=10)
            during["blocked"] = worker.is_alive()
        fsync(path)

    monkeypatch.setattr(hdf5_module, "fsync_path", slow_fsync)
    store.end_run(ending.id, RunState.FINISHED)
    assert during["blocked"] is False
    assert during["rows"] == 1000  # the finalized file, read while it was fsynced
    assert store.get_run(other.id).rows["friction"] == 5
    with h5py.File(tmp_path / "runs" / f"{ending.id}.h5") as f:
        assert f["entry"].attrs["state"] == "finished"
    store.close()
    with HDF5Store(tmp_path) as again:  # final: nothing left to complete
        assert again.read(ending.id, "friction", ["time"])["time"].size == 1000
