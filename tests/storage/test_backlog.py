"""HDF5Store's backlog: large batches reach the run file after their acknowledgement
(rigserver.storage.embedded.backlog), and every use of the file sees them all."""

from __future__ import annotations

import errno
import time
from collections.abc import Iterator
from pathlib import Path

import h5py
import numpy as np
import pytest

from rigserver.storage import HDF5Store, StorageFull
from rigserver.storage.embedded import hdf5 as hdf5_module
from rigserver.storage.embedded import ingest, views
from rigserver.storage.payloads import encode
from rigserver.storage.runfile import RunFile
from schemas.runs import RunState
from tests.storage.conftest import friction, make_run

#: rows of a batch that joins the backlog in these tests (the store's threshold below)
LARGE = 100


class _Writes:
    """What reaches RunFile.append: the first ``time`` value of each batch written."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        self.firsts: list[float] = []
        real = RunFile.append

        def append(rf: RunFile, group: str, columns: dict[str, np.ndarray], rows: int) -> None:
            real(rf, group, columns, rows)
            self.firsts.append(float(columns["time"][0]))

        monkeypatch.setattr(RunFile, "append", append)


@pytest.fixture
def quiet_never(monkeypatch: pytest.MonkeyPatch) -> None:
    """The store never counts as quiet: only uses of the file and the bound write it."""
    monkeypatch.setattr(hdf5_module, "QUIET_SECONDS", 3600.0)


@pytest.fixture
def writes(monkeypatch: pytest.MonkeyPatch) -> _Writes:
    return _Writes(monkeypatch)


@pytest.fixture
def store(tmp_path: Path) -> Iterator[HDF5Store]:
    s = HDF5Store(tmp_path, backlog_rows=LARGE)
    yield s
    s.close()


def _time(start: int, n: int) -> np.ndarray:
    return friction(start, n)["time"]


@pytest.mark.usefixtures("quiet_never")
def test_a_large_batch_is_written_when_the_file_is_read(store: HDF5Store, writes: _Writes) -> None:
    run = store.create_run(make_run())
    receipt = store.append(run.id, 0, "friction", friction(0, LARGE))
    assert receipt.rows == LARGE and not receipt.duplicate
    assert writes.firsts == []  # acknowledged: the journal has it, the file not yet
    # a small batch after it waits behind it, so the file keeps the journal's order
    store.append(run.id, 1, "friction", friction(LARGE, 3))
    assert writes.firsts == []
    np.testing.assert_array_equal(
        store.read(run.id, "friction", ["time"])["time"], _time(0, LARGE + 3)
    )
    assert writes.firsts == [_time(0, 1)[0], _time(LARGE, 1)[0]]


def test_the_backlog_is_written_once_the_store_is_quiet(
    tmp_path: Path, writes: _Writes, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(hdf5_module, "QUIET_SECONDS", 0.05)
    with HDF5Store(tmp_path, backlog_rows=LARGE) as store:
        run = store.create_run(make_run())
        store.append(run.id, 0, "friction", friction(0, LARGE))
        store.append(run.id, 1, "friction", friction(LARGE, LARGE))
        deadline = time.monotonic() + 10
        while len(writes.firsts) < 2 and time.monotonic() < deadline:
            time.sleep(0.01)
        assert writes.firsts == [_time(0, 1)[0], _time(LARGE, 1)[0]]
        np.testing.assert_array_equal(
            store.read(run.id, "friction", ["time"])["time"], _time(0, 2 * LARGE)
        )
        assert len(writes.firsts) == 2  # the read found nothing owed


@pytest.mark.usefixtures("quiet_never")
def test_past_the_bound_the_backlog_is_written_and_then_each_batch_at_once(
    store: HDF5Store, writes: _Writes, monkeypatch: pytest.MonkeyPatch
) -> None:
    one = encode(friction(0, LARGE)).size  # a batch's payload
    monkeypatch.setattr(ingest, "MAX_BACKLOG_BYTES", 2 * one + one // 2)  # two fit
    run = store.create_run(make_run())
    for seq in range(2):
        store.append(run.id, seq, "friction", friction(seq * LARGE, LARGE))
    assert writes.firsts == []
    store.append(run.id, 2, "friction", friction(2 * LARGE, LARGE))  # three do not
    assert writes.firsts == [_time(k * LARGE, 1)[0] for k in range(3)]
    store.append(run.id, 3, "friction", friction(3 * LARGE, LARGE))  # a stream: at once
    assert writes.firsts == [_time(k * LARGE, 1)[0] for k in range(4)]


@pytest.mark.usefixtures("quiet_never")
def test_after_a_quiet_a_large_batch_joins_the_backlog_again(
    store: HDF5Store, writes: _Writes, monkeypatch: pytest.MonkeyPatch
) -> None:
    one = encode(friction(0, LARGE)).size
    monkeypatch.setattr(ingest, "MAX_BACKLOG_BYTES", one // 2)  # none fits
    run = store.create_run(make_run())
    store.append(run.id, 0, "friction", friction(0, LARGE))  # past the bound: written
    assert len(writes.firsts) == 1
    monkeypatch.setattr(ingest, "MAX_BACKLOG_BYTES", 2 * one)
    store.append(run.id, 1, "friction", friction(LARGE, LARGE))  # the stream goes on
    assert len(writes.firsts) == 2
    store._write_backlog()  # what the store's thread does once it is quiet: the stream is over
    store.append(run.id, 2, "friction", friction(2 * LARGE, LARGE))
    assert len(writes.firsts) == 2  # in the backlog
    np.testing.assert_array_equal(
        store.read(run.id, "friction", ["time"])["time"], _time(0, 3 * LARGE)
    )
    assert writes.firsts == [_time(k * LARGE, 1)[0] for k in range(3)]


@pytest.mark.usefixtures("quiet_never")
def test_a_clean_close_writes_the_backlog(tmp_path: Path) -> None:
    with HDF5Store(tmp_path, backlog_rows=LARGE) as store:
        run = store.create_run(make_run())
        for seq in range(3):
            store.append(run.id, seq, "friction", friction(seq * LARGE, LARGE))
    # a clean shutdown is trusted: the next store reads the file as it is, without a rebuild
    with h5py.File(tmp_path / "runs" / f"{run.id}.h5", "r") as f:
        np.testing.assert_array_equal(f["entry/friction/time"][:], _time(0, 3 * LARGE))
    with HDF5Store(tmp_path) as store:
        np.testing.assert_array_equal(
            store.read(run.id, "friction", ["time"])["time"], _time(0, 3 * LARGE)
        )


@pytest.mark.usefixtures("quiet_never")
def test_the_end_of_a_run_writes_the_backlog_into_the_final_file(
    store: HDF5Store, tmp_path: Path
) -> None:
    run = store.create_run(make_run())
    store.append(run.id, 0, "friction", friction(0, LARGE))
    store.append(run.id, 1, "measurements", {"pin_mass_before": [12.5]})
    store.end_run(run.id, RunState.FINISHED)
    with h5py.File(tmp_path / "runs" / f"{run.id}.h5", "r") as f:
        assert bool(f["entry"].attrs["finalized"])
        np.testing.assert_array_equal(f["entry/friction/time"][:], _time(0, LARGE))
        np.testing.assert_array_equal(f["entry/measurements/pin_mass_before"][:], [12.5])


@pytest.mark.usefixtures("quiet_never")
def test_a_failed_backlog_write_is_rebuilt_from_the_journal(
    store: HDF5Store, monkeypatch: pytest.MonkeyPatch
) -> None:
    run = store.create_run(make_run())
    store.append(run.id, 0, "friction", friction(0, LARGE))
    store.append(run.id, 1, "friction", friction(LARGE, LARGE))

    def full(*args: object, **kwargs: object) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    with monkeypatch.context() as m:
        m.setattr(RunFile, "append", full)
        with pytest.raises(StorageFull):
            store.read(run.id, "friction", ["time"])
    # nothing owed was lost with the failed write: the file is rebuilt at its next use
    np.testing.assert_array_equal(
        store.read(run.id, "friction", ["time"])["time"], _time(0, 2 * LARGE)
    )
    store.append(run.id, 2, "friction", friction(2 * LARGE, 5))
    np.testing.assert_array_equal(
        store.read(run.id, "friction", ["time"])["time"], _time(0, 2 * LARGE + 5)
    )


@pytest.mark.usefixtures("quiet_never")
def test_a_file_closed_for_others_writes_its_backlog_first(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(views, "MAX_OPEN_FILES", 1)
    with HDF5Store(tmp_path, backlog_rows=LARGE) as store:
        first = store.create_run(make_run())
        store.append(first.id, 0, "friction", friction(0, LARGE))
        second = store.create_run(make_run())  # opening its file closes the first's
        store.append(second.id, 0, "friction", friction(7, LARGE))
        for run_id, start in ((first.id, 0), (second.id, 7)):
            np.testing.assert_array_equal(
                store.read(run_id, "friction", ["time"])["time"], _time(start, LARGE)
            )
