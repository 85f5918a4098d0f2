"""The journal's payload files: batches read back as written, small ones through the page
cache back to back, large ones past it (``O_DIRECT``) at aligned places, and buffered where
the file system refuses direct writes."""

from __future__ import annotations

import errno
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rigserver.storage.embedded import payload_files as payloads
from rigserver.storage.embedded.payload_files import (
    DIRECT_ALIGN,
    DIRECT_BYTES,
    PayloadFiles,
    aligned,
)
from rigserver.storage.payloads import Payload, decode, encode

MiB = 1 << 20


def _batch(size: int, seed: int) -> bytes:
    return np.random.default_rng(seed).bytes(size)


def _aligned(at: int) -> int:
    return -(-at // DIRECT_ALIGN) * DIRECT_ALIGN


def test_encode_and_decode_round_trip() -> None:
    columns = {"time": np.arange(5.0), "load": np.full(5, 300.0), "empty": np.zeros(0)}
    payload = encode(columns)
    back = decode(b"".join(bytes(memoryview(p)) for p in payload.parts))
    assert payload.size == 4 + 3 * 10 + len("timeloadempty") + 8 * 10
    assert list(back) == list(columns)
    for name, values in columns.items():
        np.testing.assert_array_equal(back[name], values)


def _opened(directory: Path) -> PayloadFiles:
    files = PayloadFiles(directory)
    files.end("run", 0, committed=lambda: 0)
    return files


@pytest.fixture
def files(tmp_path: Path) -> Iterator[PayloadFiles]:
    """Payload files in ``tmp_path`` with the new file of run "run" open."""
    opened = _opened(tmp_path)
    yield opened
    opened.close()


@pytest.fixture
def direct_writes(monkeypatch: pytest.MonkeyPatch) -> list[tuple[int, int]]:
    """(offset, length) of each write through a descriptor opened with ``O_DIRECT``."""
    if not payloads._O_DIRECT:
        pytest.skip("no O_DIRECT on this platform")
    opened: set[int] = set()
    writes: list[tuple[int, int]] = []
    open_, pwritev = os.open, os.pwritev

    def spy_open(path: Any, flags: int, *args: Any) -> int:
        fd = open_(path, flags, *args)
        if flags & payloads._O_DIRECT:
            opened.add(fd)
        return fd

    def spy_pwritev(fd: int, buffers: list[Any], at: int) -> int:
        if fd in opened:
            writes.append((at, sum(memoryview(b).nbytes for b in buffers)))
        return pwritev(fd, buffers, at)

    monkeypatch.setattr(payloads.os, "open", spy_open)
    monkeypatch.setattr(payloads.os, "pwritev", spy_pwritev)
    return writes


def _write(files: PayloadFiles, data: bytes) -> tuple[int, int]:
    """Write ``data`` as the run's next batch, in two parts; its place."""
    size = len(data)
    at = files.end("run", size, committed=lambda: 0)
    files.append("run", Payload([data[: size // 2], memoryview(data)[size // 2 :]], size))
    return at, size


# Sizes on both sides of DIRECT_BYTES: small batches back to back, large ones at the next
# aligned place, each read back as written.
@settings(max_examples=25, deadline=None)
@given(
    sizes=st.lists(
        st.one_of(st.integers(1, 3000), st.integers(DIRECT_BYTES - 2, 2 * MiB + 5000)),
        min_size=1,
        max_size=8,
    ),
    seed=st.integers(0, 99),
)
def test_batches_read_back_as_written(
    tmp_path_factory: pytest.TempPathFactory, sizes: list[int], seed: int
) -> None:
    files = _opened(tmp_path_factory.mktemp("payloads"))
    try:
        places, written, end = [], [], 0
        for i, size in enumerate(sizes):
            data = _batch(size, seed + i)
            at, _ = _write(files, data)
            large = size >= DIRECT_BYTES and not files._files["run"].buffered  # direct
            assert at == (_aligned(end) if large else end)
            end = at + size
            places.append((at, size))
            written.append(data)
        assert list(files.read("run", places)) == written
    finally:
        files.close()


def test_a_large_batch_is_written_past_the_page_cache(
    files: PayloadFiles, tmp_path: Path, direct_writes: list[tuple[int, int]]
) -> None:
    """One write of whole aligned blocks through the direct descriptor; the small batch
    before it through the page cache, and the one after it into the padding."""
    small = _write(files, b"s" * 100)
    size = MiB + 5000
    if files.end("run", size, committed=lambda: 0) % DIRECT_ALIGN:
        pytest.skip(f"{tmp_path} refuses O_DIRECT")
    large = _write(files, _batch(size, 1))
    assert small == (0, 100)
    assert large[0] == DIRECT_ALIGN
    assert direct_writes == [(DIRECT_ALIGN, MiB + 8192)]
    after = _write(files, b"t" * 100)  # into the last block's padding: the end, as before
    assert after == (DIRECT_ALIGN + size, 100)
    assert list(files.read("run", [small, large, after])) == [
        b"s" * 100,
        _batch(size, 1),
        b"t" * 100,
    ]


@settings(max_examples=40, deadline=None)
@given(
    lengths=st.lists(st.integers(0, 3000), min_size=1, max_size=6),
    extra=st.integers(DIRECT_BYTES - 4000, DIRECT_BYTES + 9000),
)
def test_aligned_memory_holds_the_batch_then_zeros(lengths: list[int], extra: int) -> None:
    """A large payload copied into aligned memory: its bytes, then zeros to a whole block,
    starting at an aligned address; a small one, or an aligned one, as it is."""
    rng = np.random.default_rng(len(lengths))
    parts: list[bytes | memoryview] = [rng.bytes(n) for n in lengths]
    parts.append(memoryview(rng.bytes(extra))[1:])  # a view, starting off its buffer
    size = sum(memoryview(p).nbytes for p in parts)
    payload = Payload(parts, size)
    copied = aligned(payload)
    if size < DIRECT_BYTES:
        assert copied is payload
        return
    assert copied.padded is not None and copied.size == size
    padded = np.frombuffer(copied.padded, np.uint8)
    assert padded.ctypes.data % DIRECT_ALIGN == 0
    assert len(padded) == _aligned(size) and len(padded) - size < DIRECT_ALIGN
    assert padded[:size].tobytes() == b"".join(bytes(memoryview(p)) for p in parts)
    assert not padded[size:].any()
    assert b"".join(bytes(p) for p in copied.parts) == padded[:size].tobytes()
    assert aligned(copied) is copied


def test_a_file_system_refusing_direct_io_at_the_opening_gets_buffered_writes(
    files: PayloadFiles, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    open_ = os.open

    def no_direct(path: Any, flags: int, *args: Any) -> int:
        if flags & payloads._O_DIRECT:
            raise OSError(errno.EINVAL, "Invalid argument")
        return open_(path, flags, *args)

    monkeypatch.setattr(payloads.os, "open", no_direct)
    first = _write(files, b"a" * 100)
    large = _write(files, _batch(DIRECT_BYTES, 2))
    assert large == (100, DIRECT_BYTES)  # no alignment: buffered, right after
    assert list(files.read("run", [first, large])) == [b"a" * 100, _batch(DIRECT_BYTES, 2)]


@pytest.mark.usefixtures("direct_writes")
@pytest.mark.parametrize("refusal", [errno.EINVAL, errno.EOPNOTSUPP])
def test_a_direct_write_refused_goes_through_the_page_cache_at_the_same_place(
    files: PayloadFiles, monkeypatch: pytest.MonkeyPatch, refusal: int
) -> None:
    """EINVAL or EOPNOTSUPP from the first direct write (a file system that opens with
    O_DIRECT and then refuses it): the batch is written buffered where it was placed, and
    the later ones buffered after it."""
    _write(files, b"a" * 100)
    if files.end("run", DIRECT_BYTES, committed=lambda: 0) % DIRECT_ALIGN:
        pytest.skip("the file system refuses O_DIRECT")
    direct = files._files["run"].direct
    pwritev = os.pwritev

    def refuse(fd: int, buffers: list[Any], at: int) -> int:
        if fd == direct:
            raise OSError(refusal, os.strerror(refusal))
        return pwritev(fd, buffers, at)

    monkeypatch.setattr(payloads.os, "pwritev", refuse)
    large = _write(files, _batch(DIRECT_BYTES, 3))
    later = _write(files, _batch(DIRECT_BYTES, 4))
    assert large == (DIRECT_ALIGN, DIRECT_BYTES)
    assert later == (DIRECT_ALIGN + DIRECT_BYTES, DIRECT_BYTES)
    assert list(files.read("run", [large, later])) == [
        _batch(DIRECT_BYTES, 3),
        _batch(DIRECT_BYTES, 4),
    ]


@pytest.mark.usefixtures("direct_writes")
def test_a_failed_direct_write_is_raised(
    files: PayloadFiles, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A full disk is no refusal of direct I/O: it is said, not written around."""
    if files.end("run", DIRECT_BYTES, committed=lambda: 0) % DIRECT_ALIGN:
        pytest.skip("the file system refuses O_DIRECT")

    def full(*args: object) -> int:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(payloads.os, "pwritev", full)
    with pytest.raises(OSError, match="No space"):
        _write(files, _batch(DIRECT_BYTES, 5))


def test_a_reopened_file_goes_on_after_the_last_committed_batch(tmp_path: Path) -> None:
    """A batch whose commit failed is written over; a large one goes at the next aligned
    place after the committed end."""
    files = _opened(tmp_path)
    _write(files, b"a" * 1000)
    _write(files, b"b" * 1000)  # say its commit failed
    files.close()
    again = PayloadFiles(tmp_path)
    try:
        assert again.end("run", 1000, committed=lambda: 1000) == 1000
        again.append("run", Payload([b"c" * 1000], 1000))
        at = again.end("run", DIRECT_BYTES, committed=lambda: 1000)
        assert at in (2000, DIRECT_ALIGN)  # buffered, or direct at the next boundary
        again.append("run", Payload([_batch(DIRECT_BYTES, 6)], DIRECT_BYTES))
        assert list(again.read("run", [(0, 1000), (1000, 1000), (at, DIRECT_BYTES)])) == [
            b"a" * 1000,
            b"c" * 1000,
            _batch(DIRECT_BYTES, 6),
        ]
    finally:
        again.close()


def test_dropping_a_file_deletes_it(files: PayloadFiles, tmp_path: Path) -> None:
    _write(files, _batch(DIRECT_BYTES, 7))
    files.drop("run")
    assert files.stored() == []
    assert not (tmp_path / "run.bin").exists()


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
    files = _opened(tmp_path_factory.mktemp("pieces"))
    try:
        rng = np.random.default_rng(len(lengths) * 1000 + rows)
        columns = {f"c{k}": rng.normal(size=n) for k, n in enumerate(lengths)}
        files.end("run", before, committed=lambda: 0)
        files.append("run", Payload([bytes(before)], before))
        payload = encode(columns)
        at = files.end("run", payload.size, committed=lambda: 0)
        files.append("run", payload)
        read = files.pieces("run", at, payload.size, rows, first)
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


def test_a_large_batch_read_in_pieces_after_a_small_one(files: PayloadFiles) -> None:
    """The backlog's reading of a batch written past the page cache, in pieces of the run
    file's chunks: the columns as written."""
    _write(files, b"s" * 100)
    rng = np.random.default_rng(8)
    columns = {"load": rng.normal(size=150_000), "time": np.arange(150_000.0)}
    payload = aligned(encode(columns))  # as the journal hands it over
    size = payload.size
    assert size >= DIRECT_BYTES and payload.padded is not None
    at = files.end("run", size, committed=lambda: 0)
    files.append("run", payload)
    pieces = [{n: v.copy() for n, v in p.items()} for p in files.pieces("run", at, size, 65_536)]
    assert [len(p["time"]) for p in pieces] == [65_536, 65_536, 150_000 - 2 * 65_536]
    for name, values in columns.items():
        np.testing.assert_array_equal(np.concatenate([p[name] for p in pieces]), values)
