"""The journal's payload files: batches read back as written while a thread prepares the
pages ahead of them, and the prepared zeros are written over, never read."""

from __future__ import annotations

import errno
import os
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rigserver.storage import payloads
from rigserver.storage.payloads import PREPARE_MAX, PREPARE_STEP, PayloadFiles, decode, encode

MiB = 1 << 20


def _batch(size: int, seed: int) -> bytes:
    return np.random.default_rng(seed).bytes(size)


def _until(condition: Callable[[], bool], seconds: float = 10.0) -> bool:
    deadline = time.monotonic() + seconds
    while not condition():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.005)
    return True


def _size(path: Path) -> int:
    return path.stat().st_size


def test_encode_and_decode_round_trip() -> None:
    columns = {"time": np.arange(5.0), "load": np.full(5, 300.0), "empty": np.zeros(0)}
    parts = encode(columns)
    back = decode(b"".join(bytes(memoryview(p)) for p in parts))
    assert list(back) == list(columns)
    for name, values in columns.items():
        np.testing.assert_array_equal(back[name], values)


def _opened(directory: Path, *, prepare: bool = True) -> PayloadFiles:
    files = PayloadFiles(directory, prepare=prepare)
    files.end("run", committed=lambda: 0)
    return files


@pytest.fixture
def files(tmp_path: Path) -> Iterator[PayloadFiles]:
    """Payload files in ``tmp_path`` with the new file of run "run" open."""
    opened = _opened(tmp_path)
    yield opened
    opened.close()


@pytest.fixture
def preparing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[PayloadFiles]:
    """As ``files``, after a batch of 100 bytes, while zeros are on their way to
    [100, 100 + PREPARE_STEP): each write of zeros takes 0.2 s (a slow disk)."""
    started = threading.Event()
    write = os.pwrite

    def slow(fd: int, data: bytes | memoryview, at: int) -> int:
        started.set()
        time.sleep(0.2)
        return write(fd, data, at)

    monkeypatch.setattr(payloads.os, "pwrite", slow)
    opened = _opened(tmp_path)
    opened.append("run", [b"a" * 100], 100)
    assert started.wait(10)
    yield opened
    opened.close()


# Batches of up to 3 MiB back to back keep the preparer busy right where the next batch
# goes: a zero written over a batch shows as a difference.
@settings(max_examples=25, deadline=None)
@given(sizes=st.lists(st.integers(1, 3 * MiB), min_size=1, max_size=12), seed=st.integers(0, 99))
def test_batches_read_back_as_written_while_the_pages_are_prepared(
    tmp_path_factory: pytest.TempPathFactory, sizes: list[int], seed: int
) -> None:
    files = _opened(tmp_path_factory.mktemp("payloads"))
    try:
        places, written = [], []
        for i, size in enumerate(sizes):
            data = _batch(size, seed + i)
            at = files.end("run", committed=lambda: 0)
            files.append("run", [data[: size // 2], memoryview(data)[size // 2 :]], size)
            places.append((at, size))
            written.append(data)
        assert [at for at, _ in places] == [sum(sizes[:i]) for i in range(len(sizes))]
        assert list(files.read("run", places)) == written
    finally:
        files.close()


@pytest.mark.parametrize(
    ("size", "ahead"),
    [(100, PREPARE_STEP), (3 * MiB, 6 * MiB), (40 * MiB, PREPARE_MAX)],
    ids=["small: one step", "twice the batch", "at most PREPARE_MAX"],
)
def test_the_file_is_prepared_ahead_of_its_end(
    files: PayloadFiles, tmp_path: Path, size: int, ahead: int
) -> None:
    files.append("run", [_batch(size, 1)], size)
    assert _until(lambda: _size(tmp_path / "run.bin") >= size + ahead)
    time.sleep(0.05)
    assert _size(tmp_path / "run.bin") == size + ahead  # and no further
    assert list(files.read("run", [(0, size)])) == [_batch(size, 1)]


def test_files_of_a_journal_that_fsyncs_every_commit_are_not_prepared(tmp_path: Path) -> None:
    files = _opened(tmp_path, prepare=False)
    try:
        files.append("run", [_batch(3 * MiB, 1)], 3 * MiB)
        time.sleep(0.05)
        assert _size(tmp_path / "run.bin") == 3 * MiB
        assert list(files.read("run", [(0, 3 * MiB)])) == [_batch(3 * MiB, 1)]
    finally:
        files.close()


def test_small_batches_wake_the_preparer_once_a_half_step(
    files: PayloadFiles, tmp_path: Path
) -> None:
    files.append("run", [b"x" * 100], 100)
    assert _until(lambda: _size(tmp_path / "run.bin") >= 100 + PREPARE_STEP)
    for _ in range(99):  # 9 900 bytes more: less than half a step, asks for nothing
        files.append("run", [b"y" * 100], 100)
    time.sleep(0.05)
    assert _size(tmp_path / "run.bin") == 100 + PREPARE_STEP


def test_a_reopened_file_goes_on_after_the_last_committed_batch(tmp_path: Path) -> None:
    """The zeros past the committed end (and a batch whose commit failed) are written over."""
    files = _opened(tmp_path)
    files.append("run", [b"a" * 1000], 1000)
    files.append("run", [b"b" * 1000], 1000)  # say its commit failed
    assert _until(lambda: _size(tmp_path / "run.bin") >= 1000 + PREPARE_STEP)
    files.close()
    again = PayloadFiles(tmp_path)
    try:
        assert again.end("run", committed=lambda: 1000) == 1000
        again.append("run", [b"c" * 1000], 1000)
        assert list(again.read("run", [(0, 1000), (1000, 1000)])) == [b"a" * 1000, b"c" * 1000]
        assert _size(tmp_path / "run.bin") == 1000 + PREPARE_STEP  # no new bytes: reused
    finally:
        again.close()


def test_a_failure_to_prepare_leaves_the_batches_to_their_own_write(
    files: PayloadFiles, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The disk full for the zeros: the batch is written all the same (its own write
    reports a full disk), and preparing resumes once it succeeds."""

    def full(*args: object) -> int:
        raise OSError(errno.ENOSPC, "No space left on device")

    with monkeypatch.context() as m:
        m.setattr(payloads.os, "pwrite", full)
        files.append("run", [b"a" * 1000], 1000)
        time.sleep(0.05)
        assert _size(tmp_path / "run.bin") == 1000
    files.append("run", [b"b" * 1000], 1000)
    assert _until(lambda: _size(tmp_path / "run.bin") >= 2000 + PREPARE_STEP)
    assert list(files.read("run", [(0, 1000), (1000, 1000)])) == [b"a" * 1000, b"b" * 1000]


def test_a_batch_waits_for_the_step_in_progress_where_it_goes(preparing: PayloadFiles) -> None:
    batch = _batch(2 * PREPARE_STEP, 3)
    preparing.append("run", [batch], len(batch))
    time.sleep(0.3)  # the step done, had it not been waited for
    assert list(preparing.read("run", [(100, len(batch))])) == [batch]


def test_dropping_a_file_while_it_is_prepared(preparing: PayloadFiles, tmp_path: Path) -> None:
    preparing.drop("run")
    assert preparing.stored() == []
    other = os.open(tmp_path / "other", os.O_RDWR | os.O_CREAT)  # may reuse the fd
    time.sleep(0.3)
    assert os.fstat(other).st_size == 0  # the preparer wrote to no reused descriptor
    os.close(other)


@settings(max_examples=60, deadline=None)
@given(
    lengths=st.lists(st.integers(0, 40), min_size=1, max_size=4),
    rows=st.integers(1, 50),
    first=st.none() | st.integers(1, 50),
    before=st.integers(0, 100),
)
def test_a_batch_read_in_pieces_is_the_batch(
    lengths: list[int],
    rows: int,
    first: int | None,
    before: int,
    tmp_path_factory: pytest.TempPathFactory,
) -> None:
    """Pieces of ``first`` rows, then ``rows`` (each column cut at its own length), put
    end to end, are the columns as written, whatever precedes the batch in the file."""
    files = _opened(tmp_path_factory.mktemp("pieces"), prepare=False)
    try:
        rng = np.random.default_rng(len(lengths) * 1000 + rows)
        columns = {f"c{k}": rng.normal(size=n) for k, n in enumerate(lengths)}
        files.append("run", [bytes(before)], before)
        parts = encode(columns)
        size = sum(memoryview(p).nbytes for p in parts)
        files.append("run", parts, size)
        read = files.pieces("run", before, size, rows, first)
        pieces = [{n: v.copy() for n, v in p.items()} for p in read]  # each read over the last
        longest = max(lengths)
        spans = [max(len(v) for v in p.values()) for p in pieces]
        assert sum(spans) == longest
        head = min(first or rows, rows)
        assert spans[0] == min(head, longest)  # then whole pieces of `rows`, the last cut
        assert all(span == rows for span in spans[1:-1])
        assert all(0 < span <= rows for span in spans[1:])
        for name, values in columns.items():
            np.testing.assert_array_equal(np.concatenate([p[name] for p in pieces]), values)
    finally:
        files.close()
