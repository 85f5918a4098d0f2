"""A file that another program is writing, read line by line as it grows.

Only complete lines (ending in a newline) are given; a partial last line waits for the rest.
The file is known by its device and inode: when the name points to another file (the stand's
software rotated it: renamed the old one and started a new one) the old file is read to its
end and the new one from its start; a file that got shorter than what was read (truncated in
place, or rewritten from its start: the end of the last line read is no longer where it
was) is read again from its start.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO, Literal

from rigclient.spool import Cursor

Change = Literal["rotated", "truncated"]
CHUNK = 1 << 20
TAIL = 256  # bytes of the last line that tell a rewritten file from the same one


@dataclass(frozen=True, slots=True)
class Line:
    """One complete line: its text, number (1-based, the header is 1) and end offset."""

    text: str
    number: int
    end: int


class Follower:
    """Reads the complete lines of ``path`` as they are written."""

    def __init__(self, path: Path, encoding: str = "utf-8") -> None:
        self.path = path
        self.encoding = encoding
        self._file: BinaryIO | None = None
        self.device = self.inode = 0
        self.position = 0  # offset after the last line given
        self.line = 0  # number of the last line given
        self._buffer = b""
        self._tail = b""  # the last bytes of the last line given: the file's fingerprint

    @property
    def is_open(self) -> bool:
        return self._file is not None

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    def open(self, cursor: Cursor | None = None) -> bool:
        """Open the file (False if it does not exist yet), at ``cursor`` if it is this file
        and not shorter than the cursor's position, else at its start."""
        self.close()
        try:
            handle = self.path.open("rb")
        except FileNotFoundError:
            return False
        st = os.fstat(handle.fileno())
        self._file, self.device, self.inode = handle, st.st_dev, st.st_ino
        self.position, self.line, self._buffer = 0, 0, b""
        if (
            cursor is not None
            and (cursor.device, cursor.inode) == (st.st_dev, st.st_ino)
            and st.st_size >= cursor.position
        ):
            handle.seek(cursor.position)
            self.position, self.line = cursor.position, cursor.line
        self._tail = self._read_back(TAIL)
        return True

    def _read_back(self, size: int) -> bytes:
        """The ``size`` bytes before the position (fewer at the file's start)."""
        assert self._file is not None
        size = min(size, self.position)
        return os.pread(self._file.fileno(), size, self.position - size) if size else b""

    def header(self) -> str | None:
        """The file's first line if it is complete, read without moving."""
        assert self._file is not None
        first = os.pread(self._file.fileno(), 64 << 10, 0)
        end = first.find(b"\n")
        return None if end < 0 else first[: end + 1].decode(self.encoding, errors="replace")

    def lines(self, *, final: bool = False) -> list[Line]:
        """The complete lines written since the last call (``final``: the partial last line
        too, for a file that is finished)."""
        assert self._file is not None
        self._buffer += self._file.read(CHUNK)
        out = []
        start = 0
        while True:
            end = self._buffer.find(b"\n", start)
            if end < 0:
                break
            out.append(self._line(self._buffer[start : end + 1]))
            start = end + 1
        self._buffer = self._buffer[start:]
        if final and self._buffer.strip():
            out.append(self._line(self._buffer))
            self._buffer = b""
        return out

    def _line(self, raw: bytes) -> Line:
        self.position += len(raw)
        self.line += 1
        self._tail = raw[-TAIL:]
        return Line(raw.decode(self.encoding, errors="replace"), self.line, self.position)

    @property
    def partial(self) -> bool:
        """A partial last line waits for its end."""
        return bool(self._buffer)

    @property
    def size_read(self) -> int:
        return self.position + len(self._buffer)

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
