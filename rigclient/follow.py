"""A file that another program is writing, read line by line as it grows.

Only complete lines are given; a partial last line waits for the rest. A line ends with LF,
CRLF or a CR alone (old Mac exports); a CR at the end of what was read waits for the next
byte (it may be the first half of a CRLF) unless the file's lines are known to end in a CR
alone, or the file is finished. In UTF-16 the line ends are the code units of LF and CR.

A line is bounded: one longer than :data:`MAX_LINE` bytes is given as :attr:`Line.overlong`
(its first bytes only, the rest skipped without being kept), so no line of a file can make
the agent hold more than that, nor reach the csv module's field limit.

The file is known by its device and inode: when the name points to another file (the stand's
software rotated it: renamed the old one and started a new one) the old file is read to its
end and the new one from its start; a file that got shorter than what was read (truncated in
place, or rewritten from its start: the end of the last line read is no longer where it
was) is read again from its start.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO, Literal

from rigclient.spool import Cursor

Change = Literal["rotated", "truncated"]
CHUNK = 1 << 20
TAIL = 256  # bytes of the last line that tell a rewritten file from the same one
MAX_LINE = 64 << 10  # bytes of the longest line taken (a header or a row)
SHOWN = 80  # characters of an overlong line kept to name it


@dataclass(frozen=True, slots=True)
class Line:
    """One complete line: its text (without the line end), number (1-based), the byte
    offsets of its start and end (after the line end), and its length in bytes if it was
    longer than :data:`MAX_LINE` (its text is then its first characters only)."""

    text: str
    number: int
    end: int
    start: int = 0
    overlong: int = 0


class Follower:
    """Reads the complete lines of ``path`` as they are written, in ``encoding``."""

    def __init__(self, path: Path, encoding: str = "utf-8") -> None:
        self.path = path
        self.encoding = encoding
        self._file: BinaryIO | None = None
        self.device = self.inode = 0
        self.position = 0  # offset after the last line given
        self.line = 0  # number of the last line given
        self._buffer = b""
        self._skipped = 0  # bytes of an overlong line dropped so far (its start is kept)
        self._cr_alone = False  # the file's lines end in a CR alone
        self._tail = b""  # the last bytes of the last line given: the file's fingerprint

    @property
    def encoding(self) -> str:
        return self._encoding

    @encoding.setter
    def encoding(self, name: str) -> None:
        self._encoding = name
        self.unit = 2 if name.replace("_", "-").lower().startswith("utf-16") else 1
        self._lf, self._cr = (c.encode(name)[-self.unit :] for c in "\n\r")
        self._ends = re.compile(re.escape(self._lf) + b"|" + re.escape(self._cr))

    @property
    def is_open(self) -> bool:
        return self._file is not None

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    def open(self, cursor: Cursor | None = None, *, start: tuple[int, int] = (0, 0)) -> bool:
        """Open the file (False if it does not exist yet), at ``cursor`` if it is this file
        and not shorter than the cursor's position, else at ``start`` (offset and number of
        the line before it)."""
        self.close()
        try:
            handle = self.path.open("rb")
        except FileNotFoundError:
            return False
        st = os.fstat(handle.fileno())
        self._file, self.device, self.inode = handle, st.st_dev, st.st_ino
        self._buffer, self._skipped = b"", 0
        self.position, self.line = start
        if (
            cursor is not None
            and (cursor.device, cursor.inode) == (st.st_dev, st.st_ino)
            and st.st_size >= cursor.position
        ):
            self.position, self.line = cursor.position, cursor.line
        handle.seek(self.position)
        self._tail = self._read_back(TAIL)
        return True

    def resumed(self, cursor: Cursor | None) -> bool:
        """Whether :meth:`open` took ``cursor``'s position."""
        return cursor is not None and (self.position, self.line) == (cursor.position, cursor.line)

    def _read_back(self, size: int) -> bytes:
        """The ``size`` bytes before the position (fewer at the file's start)."""
        assert self._file is not None
        size = min(size, self.position)
        return os.pread(self._file.fileno(), size, self.position - size) if size else b""

    def head(self, size: int) -> bytes:
        """The file's first ``size`` bytes (fewer if it is shorter), read without moving."""
        assert self._file is not None
        return os.pread(self._file.fileno(), size, 0)

    def lines(self, *, final: bool = False, limit: int | None = None) -> list[Line]:
        """The complete lines written since the last call (``final``: the partial last line
        too, once the end of a file that is finished is reached; ``limit``: at most this
        many lines). Reads on while an overlong line has no end yet."""
        assert self._file is not None
        out: list[Line] = []
        while True:
            data = self._file.read(CHUNK) if len(self._buffer) < CHUNK else b""
            at_end = len(self._buffer) < CHUNK and len(data) < CHUNK
            self._buffer += data
            start = 0
            while limit is None or len(out) < limit:
                found = self._end_of_line(start, final and at_end)
                if found is None:
                    break
                end, after = found
                out.append(self._line(self._buffer[start:end], self._buffer[start:after]))
                start = after
            self._buffer = self._buffer[start:]
            if len(self._buffer) > MAX_LINE:  # no line end within the bound: drop what follows
                keep = MAX_LINE - MAX_LINE % self.unit
                drop = len(self._buffer) - keep
                drop -= drop % self.unit  # whole code units, so the next line end is found
                self._skipped += drop
                self._buffer = self._buffer[:keep] + self._buffer[keep + drop :]
            if out or at_end:
                break
        more = limit is None or len(out) < limit
        if final and at_end and more and (self._buffer.strip(b"\x00 \t") or self._skipped):
            out.append(self._line(self._buffer, self._buffer))
            self._buffer = b""
        return out

    def _end_of_line(self, start: int, final: bool) -> tuple[int, int] | None:
        """The end of the line from ``start`` in the buffer and the offset after its line
        end, or None if it has no end yet."""
        u, buf, lf = self.unit, self._buffer, self._lf
        at = start
        while True:
            hit = self._ends.search(buf, at)
            if hit is None:
                return None
            k = hit.start()
            if (k - start) % u:  # not on a code unit boundary (UTF-16): a byte of a character
                at = k + 1
                continue
            if hit.group() == lf:
                return k, k + u
            if buf[k + u : k + 2 * u] == lf:
                return k, k + 2 * u
            if k + u < len(buf):
                self._cr_alone = True
                return k, k + u
            return (k, k + u) if final or self._cr_alone else None

    def _line(self, raw: bytes, taken: bytes) -> Line:
        """The line ``raw`` (without its end) that took the bytes ``taken`` of the buffer
        (and those skipped before them)."""
        start = self.position
        self.position += len(taken) + self._skipped
        self.line += 1
        overlong = len(raw) + self._skipped if len(raw) + self._skipped > MAX_LINE else 0
        self._tail = taken[-TAIL:] if len(taken) >= TAIL or not self._skipped else b""
        self._skipped = 0
        if not self._tail:
            self._tail = self._read_back(TAIL)
        text = raw.decode(self.encoding, errors="replace")
        if overlong:
            text = text[:SHOWN]
        return Line(text, self.line, self.position, start, overlong)

    @property
    def partial(self) -> bool:
        """A partial last line waits for its end."""
        return bool(self._buffer) or bool(self._skipped)

    @property
    def size_read(self) -> int:
        return self.position + len(self._buffer) + self._skipped

    def changed(self) -> Change | None:
        """Whether the name now points to another file, or the file got shorter."""
        try:
            st = self.path.stat()
        except FileNotFoundError:
            return None  # between the rename and the new file: wait
        if (st.st_dev, st.st_ino) != (self.device, self.inode):
            return "rotated"
        if st.st_size < self.size_read or self._read_back(len(self._tail)) != self._tail:
            return "truncated"  # shorter, or rewritten from the start past where we were
        return None

    def cursor(self, key: str, position: int, line: int) -> Cursor:
        """The file's identity with a position in it (after a line taken)."""
        return Cursor(key, str(self.path), self.device, self.inode, position, line)
