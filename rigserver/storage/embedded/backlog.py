"""What an open run's file still owes: batches the journal has and the file has not yet.

A batch is durable once the journal has it (:mod:`~rigserver.storage.embedded.journal`); the run
file is a view of the journal. A large batch (:data:`BACKLOG_ROWS` rows or more, which the
file would write at once) is acknowledged as soon as the journal has it, and its place in
the journal's payload file joins the run's backlog; so do the run's later batches while
the backlog is not empty (the file keeps the journal's order). The backlog is written to
the file, the oldest batch first, read back from the journal :data:`PIECE_ROWS` rows at a
time:

- before anything uses the file: a read, results, a snapshot, the end of the run, closing
  the file;
- when the store has taken no batch for :data:`QUIET_SECONDS` (:class:`WhenQuiet`);
- at once when it passes :data:`MAX_BACKLOG_BYTES`: the run is then a steady stream, not a
  burst, and its batches are written as they come until the store is next quiet.

So a burst of large batches costs the journal's write per batch while it lasts and the run
file's write after it, where a steady stream costs both per batch. Whatever waits on the
file (a read, the end of a run, the post that passes the bound) waits at most for
:data:`MAX_BACKLOG_BYTES` to be written.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

#: A batch of at least this many rows joins the backlog (the run file's write-behind would
#: write it at once: :data:`rigserver.storage.runfile.WRITE_BEHIND_ROWS`).
BACKLOG_ROWS = 65_536
#: The most one run's file may owe, in bytes of the journal's payload (about half a second of
#: HDF5 writing on the project's machine).
MAX_BACKLOG_BYTES = 256 << 20
#: Rows of a piece of a batch read back from the journal (five channels: 2.5 MiB); a
#: multiple of the run files' chunks (:data:`rigserver.storage.runfile.STREAM_CHUNK_ROWS`).
PIECE_ROWS = 65_536
#: Seconds without a new batch after which the backlog is written.
QUIET_SECONDS = 0.5


@dataclass(frozen=True, slots=True)
class Owed:
    """A batch the file owes: its group, rows, and place (``at``, ``size``) in the run's
    payload file."""

    group: str
    rows: int
    at: int
    size: int


@dataclass(slots=True)
class Backlog:
    """One run's owed batches, oldest first."""

    owed: deque[Owed] = field(default_factory=deque)
    bytes: int = 0

    def __bool__(self) -> bool:
        return bool(self.owed)

    def add(self, owed: Owed) -> None:
        self.owed.append(owed)
        self.bytes += owed.size

    def take(self, count: int) -> list[Owed]:
        """The ``count`` oldest owed batches, out of the backlog."""
        taken = [self.owed.popleft() for _ in range(min(count, len(self.owed)))]
        self.bytes -= sum(o.size for o in taken)
        return taken

    def clear(self) -> None:
        self.owed.clear()
        self.bytes = 0


class WhenQuiet:
    """A thread that calls ``step`` once nothing has :meth:`touched` it for ``quiet``
    seconds after it was :meth:`wanted`, and again (each time after as long a quiet) while
    ``step`` returns True."""

    def __init__(self, step: Callable[[], bool], *, quiet: float, name: str) -> None:
        self._step = step
        self._quiet = quiet
        self._cond = threading.Condition()
        self._wanted = False
        self._stopping = False
        #: when the last batch came (written without the condition: a float, read by the thread)
        self._touched = time.monotonic()
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    def touched(self) -> None:
        """Something happened: the quiet starts again."""
        self._touched = time.monotonic()

    def wanted(self) -> None:
        """There is work for the next quiet."""
        with self._cond:
            if not self._wanted:
                self._wanted = True
                self._cond.notify()

    def close(self) -> None:
        """Stop the thread (a step under way ends first)."""
        with self._cond:
            self._stopping = True
            self._cond.notify()
        self._thread.join()

    def _run(self) -> None:
        while self._wait():
            if self._step():
                self.wanted()

    def _wait(self) -> bool:
        """Until work is wanted and the quiet has lasted; False once stopping."""
        with self._cond:
            self._cond.wait_for(lambda: self._wanted or self._stopping)
            while not self._stopping:
                left = self._touched + self._quiet - time.monotonic()
                if left <= 0:
                    self._wanted = False
                    return True
                self._cond.wait(left)
            return False
