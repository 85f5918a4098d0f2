"""The agent: a stand's file, followed as it is written (``tail``) or read whole (``import``),
spooled as the batches of one run.

The run is opened through the spool with the map's metadata and constants, and the file's
cursor (device, inode, byte offset and line after the last row spooled) is written in the
transaction of each batch. Started again with the same file, stand, group and spool after a
crash or a reboot, the agent finds the cursor, goes on with the same run, and reads from the
first row not yet spooled, by the header in effect there.

The file's dialect (:mod:`rigclient.dialect`) is found from its first lines: the preamble
before the header becomes the run's notes. A line that cannot be read (a cell that is not a
number, a value outside its channel's limits, a line over 64 KiB) is reported (file, line,
column, why) and kept in the spool as a reject; the rows around it are delivered. A new
header line mid-file is recognised: the rows after it are read by its names, or the agent
stops there, naming the line, when the map cannot place them (never by position across it).
"""

from __future__ import annotations

import getpass
import hashlib
import itertools
import re
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rigclient.client import Client, RunHandle
from rigclient.dialect import (
    FileSettings,
    Header,
    cells,
    delimiter_of,
    encoding_of,
    find_header,
)
from rigclient.errors import InputError
from rigclient.follow import MAX_LINE, Follower, Line
from rigclient.mapping import StandMap, configuration
from rigclient.spool import Cursor, Reject
from rigclient.table import Table, sniff, units_line
from rigclient.units import unit_factor
from schemas.stands import MEASUREMENTS, Stand, StandKind, default_stands

HEAD = 256 << 10  # bytes of a file's start in which its header must be
#: A line of a block's preamble inside a file (CETR/Bruker UMT: ``Step = 2``).
_BLOCK_PREAMBLE = re.compile(r"^\s*[^\d\s=,;\t][^=]{0,80}?\s*=\s*\S")
NOTES = 5000  # characters of a run's notes (schemas.runs.RunCreate)


@dataclass(frozen=True, slots=True)
class Batching:
    """When the agent spools a batch, and when it gives up waiting for more.

    Attributes
    ----------
    rows : int
        A batch every ``rows`` rows ...
    seconds : float
        ... or ``seconds`` after its first row was read, whichever comes first.
    finish_after_idle : float or None
        Finish the run when the file has not grown for this long, s (None: never).
    poll : float
        Pause between looks at a file that did not grow, s.
    """

    rows: int = 200
    seconds: float = 2.0
    finish_after_idle: float | None = None
    poll: float = 0.2

    def __post_init__(self) -> None:
        if self.rows < 1 or self.seconds <= 0 or self.poll <= 0:
            raise InputError(
                f"batches need rows >= 1, seconds > 0 and poll > 0; got rows={self.rows}, "
                f"seconds={self.seconds}, poll={self.poll}"
            )


@dataclass(slots=True)
class Outcome:
    """What the agent spooled: the run (None until an import's first row), rows, batches
    and lines rejected."""

    run: RunHandle | None
    rows: int = 0
    batches: int = 0
    rejected: int = 0
    partial: bool = False


def run_metadata(path: Path, stand: str, mapping: StandMap | None, **given: Any) -> dict[str, Any]:
    """The run's opening: the command line's fields, else the map's, else the file name as
    title and the user as operator."""
    meta: dict[str, Any] = dict(mapping.run if mapping is not None else {})
    meta.update({k: v for k, v in given.items() if v})
    note = mapping.describe() if mapping is not None else ""
    if note:
        meta["notes"] = f"{meta['notes']}\n\n{note}" if meta.get("notes") else note
    meta.setdefault("title", path.name)
    meta.setdefault("operator", getpass.getuser())
    meta["stand"] = stand
    if isinstance(meta.get("configuration"), dict):
        where = mapping.source if mapping is not None else ""
        meta["configuration"] = configuration(stand, meta["configuration"], where=where)
        meta["given_by"] = "file"  # the map's, for the file: not the operator's at the stand
    return meta


def with_preamble(metadata: dict[str, Any], preamble: list[str]) -> dict[str, Any]:
    """The run's metadata with the file's preamble (a vendor's metadata lines) after the
    notes given, within the notes' length."""
    lines = [re.sub(r"[ \t]+", " ", t.replace("\x00", "")).strip() for t in preamble]
    text = "\n".join(t for t in lines if t)
    if not text:
        return metadata
    given = str(metadata.get("notes") or "")
    notes = f"{given}\n\n{text}" if given else text
    if len(notes) > NOTES:
        notes = notes[: NOTES - 1] + "…"
    return {**metadata, "notes": notes}


def constants(stand: Stand, mapping: StandMap | None) -> dict[str, dict[str, list[float]]]:
    """The map's ``[measurements]`` in the channels' units, as one batch."""
    if mapping is None or not mapping.measurements:
        return {}
    group = stand.group(MEASUREMENTS)
    units = {c.name: c.unit for c in group.channels} if group is not None else {}
    out: dict[str, list[float]] = {}
    for name, (value, unit) in mapping.measurements.items():
        if name not in units:
            raise InputError(
                f"{name!r} is not a measurement of {stand.kind.value!r} ({', '.join(units)})",
                file=mapping.source,
                column=name,
            )
        factor = 1.0 if unit is None else unit_factor(unit, units[name], where=name)
        out[name] = [value * factor]
    return {MEASUREMENTS: out}


def stand_of(kind: str, configuration: dict[str, Any] | None = None) -> Stand:
    try:
        return default_stands()[StandKind(kind)].for_run(configuration or {})
    except ValueError:
        known = ", ".join(k.value for k in StandKind)
        raise InputError(f"unknown stand {kind!r}; known: {known}") from None


class NoRow(InputError):
    """An import whose file gave no row: no run is opened."""


class HeaderChanged(InputError):
    """A header line mid-file that the map cannot place: the agent stops before it."""


@dataclass(slots=True)
class _Head:
    """The lines at a file's start until its header is found."""

    lines: list[Line]

    def text(self) -> list[str]:
        return [line.text for line in self.lines]


class Agent:
    """Spools one file as one run of ``stand``'s ``group``.

    ``more``: an import's files after the first, read after it in their order (each its
    own header; the rows go on as one run). ``say`` gets the messages for the operator (a
    refused line, a rotation);
    ``on_run`` the run's handle once it is opened or found again. ``idempotency_key``
    opens the run (an imported file's digest), else a fresh key does.
    """

    def __init__(
        self,
        client: Client,
        path: Path,
        *,
        stand: str,
        group: str,
        mapping: StandMap | None,
        metadata: dict[str, Any],
        batching: Batching,
        say: Callable[[str], None],
        on_run: Callable[[RunHandle], None] = lambda run: None,
        kind: str = "tail",
        idempotency_key: str | None = None,
        more: Sequence[Path] = (),
    ) -> None:
        self.client = client
        self.path = path
        self.files = [path, *more]  # an import's files, read one after another as one run
        self._next = 1
        self.stand = stand_of(stand, metadata.get("configuration"))
        decl = self.stand.group(group)
        if decl is None:
            known = ", ".join(g.name for g in self.stand.groups)
            raise InputError(f"stand {stand!r} has no channel group {group!r}; known: {known}")
        self.group = decl
        self.mapping = mapping
        self.settings = mapping.file if mapping is not None else FileSettings()
        self.metadata = metadata
        self.batching = batching
        self.say = say
        self.on_run = on_run
        self.idempotency_key = idempotency_key
        self.key = f"{kind} {path.resolve()} {stand} {group}"
        if more:  # a set of files: all of them, in their order, name the source
            names = "\n".join(str(p.resolve()) for p in self.files)
            self.key += f" and {len(more)} more ({hashlib.sha256(names.encode()).hexdigest()[:16]})"
        self.follower = Follower(path)
        self.preamble: list[str] = []
        self._delimiter: str | None = None
        self._head: _Head | None = _Head([])
        self._rows: list[list[float]] = []
        self._rejects: list[Reject] = []
        self._first = 0.0
        self._mark = (0, 0)  # end offset and number of the last line taken
        self._units_line = 0  # the number of the header's units line, if it has one
        self._last_header: Line | None = None  # a header mid-file, until a row follows it
        self._block_said = False
        self._opening: Cursor | None = None  # where the run's opening puts the file's cursor
        self.progress: Callable[[int], None] = lambda done: None  # bytes read so far

    def _table(
        self, text: str, line: int, width: int | None = None, units: list[str] | None = None
    ) -> Table:
        table = Table.from_header(
            text,
            units_row=units,
            file=str(self.path),
            group=self.group,
            mapping=self.mapping,
            line=line,
            delimiter=self._delimiter,
            decimal=self.settings.decimal,
            width=width,
        )
        if table.ignored:
            self.say(f"{self.path}: columns left out: {', '.join(table.ignored)}")
        return table

    def _open(self) -> bool:
        """Open the file once it exists and has a byte past a byte-order mark; its encoding
        is then known."""
        if not self.follower.is_open and not self.follower.open():
            return False
        head = self.follower.head(64 << 10)
        encoding = encoding_of(head, self.settings.encoding)
        if len(head) <= encoding.bom:
            return False
        self.follower.encoding = encoding.codec
        if self.follower.position < encoding.bom:
            self.follower.open(start=(encoding.bom, 0))
        return True

    def _header(self, final: bool) -> tuple[Table, list[Line]] | None:
        """The table of the header among the head's lines (and the lines after it), once
        one is found; :class:`InputError` past :data:`HEAD` bytes without one."""
        assert self._head is not None
        lines = self._head.lines
        long = next((ln for ln in lines if ln.overlong), None)
        in_head = [ln for ln in lines if ln.start < HEAD and not ln.overlong]
        found = find_header([ln.text for ln in in_head], self.settings, final=final)
        if found is None and not final:
            found = self._lone_header(in_head)
        if found is None:
            if long is not None and final:
                raise InputError(
                    f"line {long.number} is over {MAX_LINE >> 10} KiB, and no header with a "
                    "row under it was found: a header is bounded",
                    file=str(self.path),
                )
            if self.follower.size_read > HEAD:
                raise InputError(
                    f"no header and data row in its first {HEAD >> 10} KiB", file=str(self.path)
                )
            return None
        header = in_head[found.index]
        self._delimiter = found.delimiter
        units: list[str] | None = None
        self._units_line = 0
        above = [ln for ln in in_head[: found.index] if ln.text.strip()]
        if above and units_line(header.text, above[-1].text, found.delimiter):
            units = [c.strip() for c in cells(header.text, found.delimiter)]
            self._units_line = header.number
            header = above[-1]  # the names, above their units
        rest = [ln for ln in lines[lines.index(header) + 1 :] if ln.number != self._units_line]
        width = next((len(cells(ln.text, found.delimiter)) for ln in rest if ln.text.strip()), 0)
        table = self._table(header.text, header.number, width or None, units)
        self.preamble = [ln.text for ln in lines[: lines.index(header)] if not ln.overlong]
        self._head = None
        self._mark = (header.end, header.number)
        return table, rest

    def _lone_header(self, lines: list[Line]) -> Header | None:
        """A file being written whose first line names the channels: its header (a row
        has yet to come, but the run opens now)."""
        given = self.settings.header
        texts = [ln for ln in lines if ln.text.strip()][:1]
        if not texts or (given is not None and texts[0].number != given):
            return None
        delimiter = delimiter_of(self.settings.delimiter) if self.settings.delimiter else None
        try:
            Table.from_header(
                texts[0].text,
                file=str(self.path),
                group=self.group,
                mapping=self.mapping,
                delimiter=delimiter,
            )
        except InputError:
            return None
        return Header(lines.index(texts[0]), delimiter or sniff(texts[0].text))

    def opening(self) -> dict[str, Any]:
        """The run's opening as :meth:`run` spools it for a finished file (its head is read
        to its first row, then put back); :class:`NoRow` if no line is a row it takes (no
        run is opened for it, here or on the server)."""
        refused, first = 0, ""
        try:
            for k, path in enumerate(self.files):
                if k:
                    self.follower.close()
                    self.path, self.follower, self._head = path, Follower(path), _Head([])
                head = self._read_head(threading.Event(), follow=False)
                assert head is not None
                table, lines = head
                if k == 0:
                    opening = with_preamble(self.metadata, self.preamble)
                rest = iter(lambda: self.follower.lines(final=True), [])
                for line in itertools.chain(lines, itertools.chain.from_iterable(rest)):
                    text = line.text
                    if not text.strip() or line.overlong or text.lstrip().startswith("#"):
                        continue
                    try:
                        table.parse(text, line.number)
                    except InputError as exc:
                        if table.is_header(text) or _BLOCK_PREAMBLE.match(text):
                            continue  # a block's header or preamble
                        refused, first = refused + 1, first or str(exc)
                        continue
                    return opening
            self._rejects = [Reject(str(self.path), 0, "", first)] if first else []
            raise NoRow(self._no_row(Outcome(None, rejected=refused)), file=str(self.files[0]))
        finally:
            self._rejects = []
            self.follower.close()
            self.path = self.files[0]
            self.follower = Follower(self.path)
            self._head, self._mark, self._delimiter, self.preamble = _Head([]), (0, 0), None, []

    def _read_head(self, stop: threading.Event, follow: bool) -> tuple[Table, list[Line]] | None:
        while not stop.is_set():
            opened = self._open()
            if not opened and not follow:
                why = "an empty file" if self.path.is_file() else "no such file"
                raise InputError(why, file=str(self.path))
            if opened:
                assert self._head is not None
                self._head.lines += self.follower.lines(final=not follow)
                found = self._header(final=not follow)
                if found is not None:
                    return found
                if not follow:
                    raise InputError("no header line", file=str(self.path))
            stop.wait(self.batching.poll)
        return None

    def run(self, stop: threading.Event, *, follow: bool = True) -> Outcome | None:
        """Spool the file until ``stop`` is set or, ``follow`` false, to its end; then queue
        the run's finish. None if stopped before the file had a header (an import: before
        its first row). An import opens its run with its first row: :class:`NoRow` if the
        file has none, and no run is opened."""
        found = self.client.source(self.key)
        if found is not None and len(self.files) > 1:
            self._skip_to(found[1])
        try:
            head = self._read_head(stop, follow)
        except BaseException:
            self.follower.close()
            raise
        if head is None:
            self.follower.close()
            return None
        table, pending = head
        outcome = Outcome(None)
        if found is not None:
            run, cursor = found
            table, pending = self._resume(cursor, table, pending)
            self.say(f"{self.path}: going on with run {run.local_id} from line {self._mark[1] + 1}")
            outcome.run = run
        self._opening = self.follower.cursor(self.key, *self._mark)
        try:
            if outcome.run is not None:
                self.on_run(outcome.run)  # may stop the agent (a key refused)
            elif follow:  # a file being written: its run opens with its header
                self._opened(outcome)
        except BaseException:
            self.follower.close()
            raise
        idle_since = time.monotonic()
        try:
            while True:
                change = self.follower.changed() if follow and not pending else None
                if change is not None:
                    table = self._switch(change, table, outcome)
                    idle_since = time.monotonic()
                    continue
                lines = pending or self.follower.lines(final=not follow)
                pending = []
                self.progress(self.follower.size_read)
                for line in lines:
                    table = self._take(line, table, outcome, final=not follow)
                    if len(self._rows) >= self.batching.rows:
                        self._flush(table, outcome)
                now = time.monotonic()
                if lines:
                    idle_since = now
                if self._rows and now - self._first >= self.batching.seconds:
                    self._flush(table, outcome)
                if lines:
                    continue
                if not follow and not stop.is_set() and self._next < len(self.files):
                    table, pending = self._next_file(stop, table, outcome)
                    continue
                if not follow or stop.is_set():
                    break
                idle = self.batching.finish_after_idle
                if idle is not None and now - idle_since >= idle:
                    self.say(f"{self.path}: no new row for {idle:g} s, finishing")
                    break
                stop.wait(self.batching.poll)
            self._flush(table, outcome)
            outcome.partial = self.follower.partial
            if outcome.partial:
                self.say(
                    f"{self.path}:{self.follower.line + 1}: a partial last line (no end of "
                    "line yet) was not taken"
                )
            if outcome.run is None:
                if stop.is_set():
                    return None
                raise NoRow(self._no_row(outcome), file=str(self.path))
            outcome.run.finish()
            self.client.forget_headers(self.key)
        except HeaderChanged:
            self._flush(table, outcome)
            raise
        finally:
            self.follower.close()
        return outcome

    def _next_file(
        self, stop: threading.Event, table: Table, outcome: Outcome
    ) -> tuple[Table, list[Line]]:
        """The next of an import's files: its header (and units line) read, the rows
        after it pending; the run goes on (its channels' order and clock carried)."""
        self._flush(table, outcome)
        if self.follower.partial:
            self.say(f"{self.path}:{self.follower.line + 1}: a partial last line was not taken")
        self.follower.close()
        self.path = self.files[self._next]
        self._next += 1
        self.follower = Follower(self.path)
        self._head, self._delimiter, self._last_header = _Head([]), None, None
        head = self._read_head(stop, follow=False)
        assert head is not None  # an import reads to the end or raises
        new, rest = head
        if outcome.run is not None:
            outcome.run.mark(self.follower.cursor(self.key, *self._mark))
        return new.carry(table), rest

    def _skip_to(self, cursor: Cursor) -> None:
        """An import of several files cut short: go on from the file of its cursor."""
        for k, path in enumerate(self.files):
            try:
                info = path.stat()
            except OSError:
                continue
            if (info.st_dev, info.st_ino) == (cursor.device, cursor.inode):
                self.path, self._next = path, k + 1
                self.follower = Follower(path)
                return

    def _resume(
        self, cursor: Cursor, table: Table, pending: list[Line]
    ) -> tuple[Table, list[Line]]:
        """Go on from ``cursor`` if it is this file's and past its header, by the header in
        effect there; else from the header (the rows after it were not spooled)."""
        header_end = self._mark[0]
        same = (cursor.device, cursor.inode) == (self.follower.device, self.follower.inode)
        if not same or cursor.position <= header_end:
            return table, pending
        self.follower.open(cursor)
        if not self.follower.resumed(cursor):  # shorter than the cursor: read from its start
            self.follower.open(start=self._mark)
            return table, []
        self._mark = (cursor.position, cursor.line)
        kept = self.client.header_before(cursor)
        if kept is not None:
            table = self._remap(Line(kept[1], kept[0], 0), table)
        return table, []

    def _remap(self, line: Line, table: Table, units: list[str] | None = None) -> Table:
        """The table of a header line met mid-file (with its ``units`` line, if it has
        one); :class:`HeaderChanged` if the map cannot place its columns."""
        try:
            new = self._table(line.text, line.number, units=units)
        except InputError as exc:
            reason = str(exc).split(": ", 1)[-1] if exc.file else str(exc)
            raise HeaderChanged(
                f"a new header line: {reason}; the rows before it are spooled, the agent "
                "stops here: fix the map and start it again",
                file=str(self.path),
                line=line.number,
                column=exc.column,
            ) from None
        new.carry(table)
        return new

    def _take(self, line: Line, table: Table, outcome: Outcome, *, final: bool) -> Table:
        if self._head is not None:  # a new file (rotated): its header first
            self._head.lines.append(line)
            found = self._header(final=final)
            if found is None:
                return table
            new, rest = found
            new.carry(table)
            for later in rest:
                new = self._take(later, new, outcome, final=final)
            return new
        if line.overlong:
            why = f"a line of {line.overlong} bytes, over {MAX_LINE >> 10} KiB"
            self._reject(InputError(why, file=str(self.path), line=line.number), line, outcome)
            return table
        if not line.text.strip() or line.text.lstrip().startswith("#"):
            self._mark = (line.end, line.number)
            return table
        try:
            values = table.parse(line.text, line.number)
        except InputError as exc:
            header = self._last_header
            if header is not None and units_line(line.text, header.text, table.delimiter):
                units = [c.strip() for c in cells(line.text, table.delimiter)]
                self._mark = (line.end, line.number)
                return self._remap(header, table, units)  # the header's units, under it
            if _BLOCK_PREAMBLE.match(line.text) and not table.is_header(line.text):
                if self._last_header is not None or not self._block_said:
                    self.say(f"{self.path}:{line.number}: a block's preamble, left out")
                self._block_said, self._last_header = True, None
                self._mark = (line.end, line.number)
                return table
            if not table.is_header(line.text):
                self._reject(exc, line, outcome)
                return table
            new = self._remap(line, table)
            self._flush(table, outcome)
            cursor = self.follower.cursor(self.key, line.end, line.number)
            self.client.keep_header(cursor, line.start, line.text)
            self.say(f"{self.path}:{line.number}: a new header; the rows after it by its names")
            self._mark = (line.end, line.number)
            self._last_header = line
            return new
        self._last_header = None
        if not self._rows:
            self._first = time.monotonic()
        self._rows.append(values)
        self._mark = (line.end, line.number)
        return table

    def _reject(self, error: InputError, line: Line, outcome: Outcome) -> None:
        """A line kept in the spool as a reject (with the next batch), and counted."""
        self.say(f"refused: {error}")
        self._rejects.append(Reject(str(self.path), line.number, error.column, str(error)))
        outcome.rejected += 1
        self._mark = (line.end, line.number)

    def _opened(self, outcome: Outcome) -> RunHandle:
        """The run, opened now if it is not yet (an import opens it with its first row)."""
        if outcome.run is None:
            outcome.run = self.client.open_run(
                **with_preamble(self.metadata, self.preamble),
                constants=constants(self.stand, self.mapping),
                cursor=self._opening,
                idempotency_key=self.idempotency_key,
            )
            self.on_run(outcome.run)  # may stop the agent (a key refused): the run stays
        return outcome.run

    def _no_row(self, outcome: Outcome) -> str:
        """Why an import opened no run: no line of the file was a row it could take."""
        if not outcome.rejected:
            return "no row under the header; no run opened"
        first = self._rejects[0].message if self._rejects else ""
        return (
            f"no row could be taken ({outcome.rejected} lines refused, the first: {first}); "
            "no run opened: fix the map (a column's unit, factor or offset) or the file and "
            "import it again"
        )

    def _flush(self, table: Table, outcome: Outcome) -> None:
        if outcome.run is None and not self._rows:
            return  # an import's lines refused before its first row: kept until it opens
        run = self._opened(outcome)
        cursor = self.follower.cursor(self.key, *self._mark)
        rejects = tuple(self._rejects)
        if self._rows:
            run.post(self.group.name, table.columns(self._rows), cursor=cursor, rejects=rejects)
            outcome.rows += len(self._rows)
            outcome.batches += 1
        elif rejects:
            run.mark(cursor, rejects)
        self._rows, self._rejects = [], []

    def _switch(self, change: str, table: Table, outcome: Outcome) -> Table:
        """The file was rotated (read the old one to its end first) or truncated: the new
        one is read from its start, its header first."""
        if change == "rotated":
            for line in self.follower.lines():
                table = self._take(line, table, outcome, final=False)
        self._flush(table, outcome)
        if self.follower.partial:
            self.say(f"{self.path}:{self.follower.line + 1}: the old file ended in a partial line")
        self.say(f"{self.path}: the file was {change}; reading the new one from its start")
        self.client.forget_headers(self.key)
        self.follower.open()
        self._head = _Head([])
        self._open()
        self._mark = (self.follower.position, 0)
        self._opened(outcome).mark(self.follower.cursor(self.key, *self._mark))
        return table
