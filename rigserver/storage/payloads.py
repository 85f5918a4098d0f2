"""The journal's payload files: the readings of each open run's batches, back to back.

``payloads/<run id>.bin`` holds every batch of the run in the order stored, each as
:func:`encode` lays it out; the journal's ``batches`` table says where each one is (``at``,
``size``). Bytes past the last committed batch (a write whose commit failed, the zeros
below) are never read, and the next batch is written over them.

Preparing ahead. Writing into pages the page cache does not hold yet costs several times
more than writing over pages it holds: the kernel has to allocate, account and map each new
page (and in a virtual machine the host faults it in first). Measured here with ``dd``: 0.7
to 2 GB/s into a new file, 7 GB/s over its cached pages. So a thread (:class:`_Preparer`)
writes zeros ahead of each file's end, twice the last batch's size (at least
:data:`PREPARE_STEP`, at most :data:`PREPARE_MAX`), and a batch lands in pages already
there: the way databases preallocate their logs, done where a writer is not waiting. It
costs at most that much disk per open run until the run's file is final.
"""

from __future__ import annotations

import logging
import mmap
import os
import struct
import threading
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from rigserver.storage.errors import StorageUnavailable

log = logging.getLogger(__name__)

#: Bytes of zeros written in one step of preparing (a writer waits for at most one step).
PREPARE_STEP = 1 << 20
#: The most a file is prepared past its end.
PREPARE_MAX = 64 << 20
_IOV_MAX = 512
#: A batch up to this many bytes is written as one buffer (a single reading's six parts
#: cost more as a vector of views than joined).
_SMALL_WRITE = 4096
#: Bytes read first of a batch in pieces: enough for the header of any stand's group.
_HEAD_BYTES = 4096
_HEADER = struct.Struct("<I")
_COLUMN = struct.Struct("<HQ")


def encode(columns: dict[str, NDArray[np.float64]]) -> list[bytes | memoryview]:
    """Channel count, then (name length, row count, name) per channel, then the values
    (raw float64, native order: little-endian on every platform rigserver runs on)."""
    head = [_HEADER.pack(len(columns))]
    for name, values in columns.items():
        raw = name.encode()
        head.append(_COLUMN.pack(len(raw), len(values)))
        head.append(raw)
    return [b"".join(head), *(v.data for v in columns.values())]


def decode(data: bytes) -> dict[str, NDArray[np.float64]]:
    """The columns :func:`encode` laid out, as read-only views of ``data``."""
    out: dict[str, NDArray[np.float64]] = {}
    for name, rows, at in _layout(data):
        out[name] = np.frombuffer(data, dtype="<f8", count=rows, offset=at)
    return out


def _layout(head: bytes) -> list[tuple[str, int, int]]:
    """(name, rows, where its values start) of each column, from the first bytes of an
    encoded batch (``struct.error`` if ``head`` is shorter than the header)."""
    (count,) = _HEADER.unpack_from(head, 0)
    at = _HEADER.size
    names: list[tuple[str, int]] = []
    for _ in range(count):
        size, rows = _COLUMN.unpack_from(head, at)
        at += _COLUMN.size
        names.append((head[at : at + size].decode(), rows))
        at += size
    out = []
    for name, rows in names:
        out.append((name, rows, at))
        at += 8 * rows
    return out


@dataclass(slots=True, eq=False)
class _File:
    fd: int
    #: where the next batch goes
    end: int
    #: bytes [0, ready) have been written: batches, or zeros by the preparer
    ready: int
    #: the preparer writes zeros up to here
    wanted: int


class PayloadFiles:
    """The payload files in ``directory``, prepared ahead unless ``prepare`` is false; not
    thread-safe (the journal's caller serialises the calls), but for the preparing thread,
    which only ever writes at or past ``ready``.

    The journal does not prepare when every commit fsyncs its payload files
    (``synchronous=full``): the fsync would write the zeros to disk, and then the batch
    written over them again.
    """

    def __init__(self, directory: Path, *, prepare: bool = True) -> None:
        self.directory = directory
        directory.mkdir(exist_ok=True)
        self._files: dict[str, _File] = {}
        self._preparer = _Preparer() if prepare else None

    def _path(self, run_id: str) -> Path:
        return self.directory / f"{run_id}.bin"

    def end(self, run_id: str, committed: Callable[[], int]) -> int:
        """Where the run's next batch goes: after the last committed batch (``committed()``,
        asked when the file is opened), over whatever a failed write or preparing left."""
        found = self._files.get(run_id)
        if found is None:
            end = committed()
            fd = os.open(self._path(run_id), os.O_RDWR | os.O_CREAT, 0o644)
            size = os.fstat(fd).st_size
            found = self._files[run_id] = _File(fd, end, size, size)
        return found.end

    def append(self, run_id: str, parts: Sequence[bytes | memoryview], size: int) -> None:
        """Write ``parts`` (``size`` bytes) at the run's end (:meth:`end` opened the file).

        The end moves past them first, so a failed write leaves bytes that nothing reads.
        """
        file = self._files[run_id]
        at = file.end
        file.end += size
        if self._preparer is not None:
            self._preparer.claim(file, file.end)
        _write_all(file.fd, [b"".join(parts)] if size <= _SMALL_WRITE else parts, at)
        if self._preparer is not None:
            ahead = min(PREPARE_MAX, max(PREPARE_STEP, 2 * size))
            self._preparer.want(file, file.end, ahead)

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
        next is asked for."""
        path = self._path(run_id)
        fd = self._open_to_read(run_id, path)
        try:
            head = os.pread(fd, min(size, _HEAD_BYTES), at)
            try:
                layout = _layout(head)
            except struct.error:  # names longer than _HEAD_BYTES: the whole batch at once
                layout = _layout(os.pread(fd, size, at))
            longest = max((n for _, n, _ in layout), default=0)
            buffers = _buffers({name: min(rows, count) for name, count, _ in layout})
            starts = [0, *range(min(rows, first or rows), longest, rows)]
            for start, stop in zip(starts, [*starts[1:], longest], strict=True):
                piece: dict[str, NDArray[np.float64]] = {}
                for name, count, offset in layout:
                    n = max(0, min(count, stop) - start)
                    values = buffers[name][:n]
                    if n and os.preadv(fd, [values.data], at + offset + 8 * start) != 8 * n:
                        raise StorageUnavailable(f"{path} is cut short in run {run_id}'s batch")
                    piece[name] = values
                yield piece
        finally:
            os.close(fd)

    def stored(self) -> list[str]:
        """The runs that have a payload file."""
        return [p.stem for p in self.directory.glob("*.bin")]

    def drop(self, run_id: str) -> None:
        """Close and delete the run's file."""
        found = self._files.pop(run_id, None)
        if found is not None:
            if self._preparer is not None:
                self._preparer.forget(found)
            os.close(found.fd)
        self._path(run_id).unlink(missing_ok=True)

    def close(self) -> None:
        if self._preparer is not None:
            self._preparer.stop()
        for file in self._files.values():
            os.close(file.fd)
        self._files.clear()


class _Preparer:
    """A thread writing zeros from each file's ``ready`` up to its ``wanted``, one
    :data:`PREPARE_STEP` at a time; its condition guards ``ready``, ``wanted`` and the file
    it is writing."""

    def __init__(self) -> None:
        self._cond = threading.Condition()
        self._files: list[_File] = []
        self._busy: _File | None = None
        self._stopping = False
        self._zeros = memoryview(bytes(PREPARE_STEP))
        self._thread = threading.Thread(target=self._run, name="rig-payload-prepare", daemon=True)
        self._thread.start()

    def claim(self, file: _File, end: int) -> None:
        """The writer is about to write below ``end``: once the step in progress on this
        file is done, nothing is prepared below ``end`` any more."""
        if end <= file.ready:  # it only grows: no need to ask under the lock
            return
        with self._cond:
            if end > file.ready:
                self._cond.wait_for(lambda: self._busy is not file)
                file.ready = max(file.ready, end)

    def want(self, file: _File, end: int, ahead: int) -> None:
        """Prepare ``file`` up to ``end + ahead``, if that is past what it was asked before
        by half of ``ahead`` or a step, whichever is less (small batches wake the thread once
        per half step)."""
        wanted = min(ahead // 2, PREPARE_STEP)
        if end + ahead - file.wanted < wanted:  # asked before (lowered only on a failure)
            return
        with self._cond:
            if end + ahead - file.wanted >= wanted:
                file.wanted = end + ahead
                if file not in self._files:
                    self._files.append(file)
                self._cond.notify_all()

    def forget(self, file: _File) -> None:
        """Prepare no more of ``file``: it is about to be closed."""
        with self._cond:
            self._cond.wait_for(lambda: self._busy is not file)
            if file in self._files:
                self._files.remove(file)

    def stop(self) -> None:
        with self._cond:
            self._stopping = True
            self._cond.notify_all()
        self._thread.join()

    def _next(self) -> tuple[_File, int, int] | None:
        """The next step (file, from, to), or None to stop; marks the file busy."""
        with self._cond:
            while True:
                if self._stopping:
                    return None
                for file in self._files:
                    if file.wanted > file.ready:
                        self._busy = file
                        return file, file.ready, min(file.wanted, file.ready + PREPARE_STEP)
                self._files.clear()  # every file is ready up to what it wants
                self._cond.wait()

    def _run(self) -> None:
        while (step := self._next()) is not None:
            file, start, stop = step
            try:
                done = os.pwrite(file.fd, self._zeros[: stop - start], start)
            except OSError as exc:  # e.g. the disk is full: the batch's own write will say
                log.debug("preparing a payload file failed: %s", exc)
                done = 0
            with self._cond:
                self._busy = None
                if not done:
                    file.wanted = file.ready  # until the next batch wants more
                else:
                    file.ready = max(file.ready, start + done)
                self._cond.notify_all()


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
