"""The journal's payload files: the readings of each open run's batches, back to back.

``payloads/<run id>.bin`` holds every batch of the run in the order stored, each as
:func:`~rigserver.storage.payloads.encode` lays it out; the journal's ``batches`` table says
where each one is (``at``, ``size``). Bytes past the last committed batch (a write whose
commit failed) are never read, and the next batch is written over them.

Large batches past the page cache. A batch of :data:`DIRECT_BYTES` or more is laid out in
memory aligned to :data:`DIRECT_ALIGN` (:func:`aligned`, which the store calls before its
lock) and written with ``O_DIRECT`` at a :data:`DIRECT_ALIGN` boundary, in one write: the
disk takes it from that memory, and the kernel neither copies it nor takes pages for it.
Pages the page cache has to take are the dear part of a buffered write: in a virtual
machine whose free memory goes back to the host (virtio-balloon's free page reporting, as
on the machines these figures come from) a page not touched for a few seconds is faulted in
by the host again, and ``dd`` writes 0.4 GB/s into such pages (all of it CPU), 5 GB/s into
pages just freed, 2-3 GB/s past the cache with 0.05 s of CPU for 800 MB. The payload is
written once and read once (into the run file, :mod:`~rigserver.storage.embedded.backlog`),
so the page cache gains nothing by holding it. A file system that refuses ``O_DIRECT`` (at
the opening or at the first write) gets buffered writes.

Small batches (single readings) are buffered writes, one ``pwrite`` each; a direct write
aligns its start past them, so the two never share a page.
"""

from __future__ import annotations

import errno
import logging
import mmap
import os
import struct
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from rigserver.storage.errors import StorageUnavailable
from rigserver.storage.payloads import Payload, layout

log = logging.getLogger(__name__)

#: A batch of at least this many bytes is written past the page cache (``O_DIRECT``).
DIRECT_BYTES = 256 << 10
#: Where a direct write starts and how its length is padded: the page size, a multiple of
#: any disk's logical block.
DIRECT_ALIGN = 4096
#: ``O_DIRECT`` where the platform has it (Linux); elsewhere every write is buffered.
_O_DIRECT: int = getattr(os, "O_DIRECT", 0)
#: What a file system answers a direct write it does not take (misaligned for it, or none)
_REFUSALS = (errno.EINVAL, errno.EOPNOTSUPP)
_IOV_MAX = 512
#: A batch up to this many bytes is written as one buffer (a single reading's six parts
#: cost more as a vector of views than joined).
_SMALL_WRITE = 4096
#: Bytes read first of a batch in pieces: enough for the header of any stand's group.
_HEAD_BYTES = 4096


def aligned(payload: Payload) -> Payload:
    """``payload`` as a direct write takes it: a batch of :data:`DIRECT_BYTES` or more
    copied into memory of its own aligned to :data:`DIRECT_ALIGN` and padded with zeros
    (from the heap, which ``rigserver serve`` keeps for the next batch); a smaller one, or
    one already aligned, as it is."""
    size = payload.size
    if size < DIRECT_BYTES or payload.padded is not None:
        return payload
    whole = _whole(size)
    raw = np.empty(whole + DIRECT_ALIGN, np.uint8)
    skip = -raw.ctypes.data % DIRECT_ALIGN
    padded = raw[skip : skip + whole]
    at = 0
    for part in payload.parts:
        data = np.frombuffer(part, np.uint8)
        padded[at : at + len(data)] = data  # NumPy copies without the GIL
        at += len(data)
    padded[at:] = 0
    return Payload([padded[:size].data], size, padded.data)


@dataclass(slots=True, eq=False)
class _File:
    fd: int
    #: where the next batch goes (a large one: at the next DIRECT_ALIGN boundary)
    end: int
    #: the file opened for direct writes (at its first large batch)
    direct: int | None = None
    #: the file system refused direct writes: every batch is buffered
    buffered: bool = not _O_DIRECT


class PayloadFiles:
    """The payload files in ``directory``; not thread-safe (the journal's caller serialises
    the calls)."""

    def __init__(self, directory: Path) -> None:
        self.directory = directory
        directory.mkdir(exist_ok=True)
        self._files: dict[str, _File] = {}

    def _path(self, run_id: str) -> Path:
        return self.directory / f"{run_id}.bin"

    def end(self, run_id: str, size: int, committed: Callable[[], int]) -> int:
        """Where the run's next batch, of ``size`` bytes, goes: after the last committed
        batch (``committed()``, asked when the file is opened), over whatever a failed write
        left; a large batch at the next :data:`DIRECT_ALIGN` boundary."""
        file = self._files.get(run_id)
        if file is None:
            fd = os.open(self._path(run_id), os.O_RDWR | os.O_CREAT, 0o644)
            file = self._files[run_id] = _File(fd, committed())
        if size >= DIRECT_BYTES and file.direct is None and not file.buffered:
            try:
                file.direct = os.open(self._path(run_id), os.O_WRONLY | _O_DIRECT)
            except OSError as exc:  # e.g. EINVAL: a file system without direct I/O
                self._refused(file, exc)
        return _place(file, size)

    def append(self, run_id: str, payload: Payload) -> None:
        """Write ``payload`` where :meth:`end` said, which opened the file.

        The end moves past it first, so a failed write leaves bytes that nothing reads.
        """
        file = self._files[run_id]
        size = payload.size
        at = _place(file, size)
        file.end = at + size
        if file.direct is not None and size >= DIRECT_BYTES:
            padded = aligned(payload).padded
            assert padded is not None  # a large batch's
            try:
                return _write_all(file.direct, [padded], at)
            except OSError as exc:
                if exc.errno not in _REFUSALS:  # not a refusal of direct I/O: a failure
                    raise
                self._refused(file, exc)
        parts = payload.parts
        _write_all(file.fd, [b"".join(parts)] if size <= _SMALL_WRITE else parts, at)

    @staticmethod
    def _refused(file: _File, exc: OSError) -> None:
        """Direct I/O refused by the file system: this file's batches are buffered."""
        log.info("payload files written through the page cache: %s", exc)
        if file.direct is not None:
            os.close(file.direct)
        file.direct, file.buffered = None, True

    def sync(self, run_id: str) -> None:
        """fsync the run's file."""
        os.fsync(self._files[run_id].fd)

    @staticmethod
    def _open_to_read(run_id: str, path: Path) -> int:
        try:
            return os.open(path, os.O_RDONLY)
        except FileNotFoundError:
            raise StorageUnavailable(
                f"the readings of run {run_id} are no longer in the journal ({path} is missing)"
            ) from None

    def read(self, run_id: str, places: Sequence[tuple[int, int]]) -> Iterator[bytes]:
        """The bytes at each (at, size) of ``places``, in order."""
        path = self._path(run_id)
        fd = self._open_to_read(run_id, path)
        try:
            for at, size in places:
                data = os.pread(fd, size, at)
                if len(data) != size:
                    raise StorageUnavailable(f"{path} is cut short at byte {at + len(data)}")
                yield data
        finally:
            os.close(fd)

    def pieces(
        self, run_id: str, at: int, size: int, rows: int, first: int | None = None
    ) -> Iterator[dict[str, NDArray[np.float64]]]:
        """The batch at (``at``, ``size``) in pieces of ``first`` rows (default ``rows``,
        at most ``rows``), then ``rows`` (a column shorter than the batch's longest ends
        early), read one piece at a time into the same buffers: a piece is valid until the
        next is asked for. The pages read are given back to the system after each piece:
        read once, the page cache gains nothing by holding them, and the next piece reads
        into the pages just given back."""
        path = self._path(run_id)
        fd = self._open_to_read(run_id, path)
        try:
            head = os.pread(fd, min(size, _HEAD_BYTES), at)
            try:
                columns = layout(head)
            except struct.error:  # names longer than _HEAD_BYTES: the whole batch at once
                columns = layout(os.pread(fd, size, at))
            longest = max((n for _, n, _ in columns), default=0)
            buffers = _buffers({name: min(rows, count) for name, count, _ in columns})
            starts = [0, *range(min(rows, first or rows), longest, rows)]
            for start, stop in zip(starts, [*starts[1:], longest], strict=True):
                piece: dict[str, NDArray[np.float64]] = {}
                for name, count, offset in columns:
                    n = max(0, min(count, stop) - start)
                    values = buffers[name][:n]
                    if n and os.preadv(fd, [values.data], at + offset + 8 * start) != 8 * n:
                        raise StorageUnavailable(f"{path} is cut short in run {run_id}'s batch")
                    piece[name] = values
                yield piece
                _uncache(fd, at, size)
        finally:
            os.close(fd)

    def stored(self) -> list[str]:
        """The runs that have a payload file."""
        return [p.stem for p in self.directory.glob("*.bin")]

    def drop(self, run_id: str) -> None:
        """Close and delete the run's file."""
        found = self._files.pop(run_id, None)
        if found is not None:
            _close(found)
        self._path(run_id).unlink(missing_ok=True)

    def close(self) -> None:
        for file in self._files.values():
            _close(file)
        self._files.clear()


def _place(file: _File, size: int) -> int:
    """Where a batch of ``size`` bytes goes in ``file``."""
    if file.direct is not None and size >= DIRECT_BYTES:
        return _whole(file.end)
    return file.end


def _uncache(fd: int, at: int, size: int) -> None:
    """Drop the page cache's clean pages of bytes [at, at + size) of ``fd`` (where the
    platform can)."""
    if hasattr(os, "posix_fadvise"):
        os.posix_fadvise(fd, at, size, os.POSIX_FADV_DONTNEED)


def _whole(size: int) -> int:
    """``size`` rounded up to a whole :data:`DIRECT_ALIGN`."""
    return -(-size // DIRECT_ALIGN) * DIRECT_ALIGN


def _close(file: _File) -> None:
    os.close(file.fd)
    if file.direct is not None:
        os.close(file.direct)


def _buffers(lengths: dict[str, int]) -> dict[str, NDArray[np.float64]]:
    """Arrays of the lengths in one anonymous mapping of their own, given back to the system
    when the last of them goes (malloc, as ``rigserver serve`` sets it up, keeps what it
    frees: the memory of a backlog written once would stay with the process)."""
    mapping = mmap.mmap(-1, max(1, 8 * sum(lengths.values())))
    out, at = {}, 0
    for name, n in lengths.items():
        out[name] = np.frombuffer(mapping, "<f8", n, at)
        at += 8 * n
    return out


def _write_all(fd: int, parts: Sequence[bytes | memoryview], at: int) -> None:
    """Write the parts at offset ``at`` (pwritev returns short on large writes)."""
    views = [memoryview(p).cast("B") for p in parts]
    while views:
        done = os.pwritev(fd, views[:_IOV_MAX], at)
        at += done
        while views and done >= len(views[0]):
            done -= len(views[0])
            views.pop(0)
        if views and done:
            views[0] = views[0][done:]
