"""The agent: a stand's file, followed as it is written (``tail``) or read whole (``import``),
spooled as the batches of one run.

The run is opened through the spool with the map's metadata and constants, and the file's
cursor (device, inode, byte offset and line after the last row spooled) is written in the
transaction of each batch. Started again with the same file, stand, group and spool after a
crash or a reboot, the agent finds the cursor, goes on with the same run, and reads from the
first row not yet spooled. A line that cannot be read is reported (file, line, column) and
kept in the spool as a reject; the rows around it are delivered.
"""

from __future__ import annotations

import getpass
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rigclient.client import Client, RunHandle
from rigclient.errors import InputError
from rigclient.follow import Follower, Line
from rigclient.mapping import StandMap, unit_factor
from rigclient.spool import Reject
from rigclient.table import Table
from schemas.stands import MEASUREMENTS, Stand, StandKind, default_stands


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
    """What the agent spooled: the run, rows, batches and lines rejected."""

    run: RunHandle
    rows: int = 0
    batches: int = 0
    rejected: int = 0
    partial: bool = False


def run_metadata(path: Path, stand: str, mapping: StandMap | None, **given: Any) -> dict[str, Any]:
    """The run's opening: the command line's fields, else the map's, else the file name as
    title and the user as operator."""
    meta: dict[str, Any] = dict(mapping.run if mapping is not None else {})
    meta.update({k: v for k, v in given.items() if v})
    meta.setdefault("title", path.name)
    meta.setdefault("operator", getpass.getuser())
    meta["stand"] = stand
    return meta


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


class Agent:
    """Spools one file as one run of ``stand``'s ``group``.

    ``say`` gets the messages for the operator (a refused line, a rotation);
    ``on_run`` the run's handle once it is opened or found again.
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
    ) -> None:
        self.client = client
        self.path = path
        self.stand = stand_of(stand, metadata.get("configuration"))
        decl = self.stand.group(group)
        if decl is None:
            known = ", ".join(g.name for g in self.stand.groups)
            raise InputError(f"stand {stand!r} has no channel group {group!r}; known: {known}")
        self.group = decl
        self.mapping = mapping
        self.metadata = metadata
        self.batching = batching
        self.say = say
        self.on_run = on_run
        self.key = f"{kind} {path.resolve()} {stand} {group}"
        self.follower = Follower(path)
        self._rows: list[list[float]] = []
        self._rejects: list[Reject] = []
        self._first = 0.0
        self._mark = (0, 0)  # end offset and number of the last line taken
        self.progress: Callable[[int], None] = lambda done: None  # bytes read so far

    def _table(self, header: str) -> Table:
        table = Table.from_header(
            header, file=str(self.path), group=self.group, mapping=self.mapping
        )
        if table.ignored:
            self.say(f"{self.path}: columns left out: {', '.join(table.ignored)}")
        return table

    def _wait_for_header(self, stop: threading.Event) -> str | None:
        while not stop.is_set():
            if self.follower.is_open or self.follower.open():
                header = self.follower.header()
                if header is not None:
                    return header
            stop.wait(self.batching.poll)
        return None

    def run(self, stop: threading.Event, *, follow: bool = True) -> Outcome | None:
        """Spool the file until ``stop`` is set or, ``follow`` false, to its end; then queue
        the run's finish. None if stopped before the file had a header."""
        found = self.client.source(self.key)
        header = self._wait_for_header(stop)
        if header is None:
            return None
        table = self._table(header)
        if found is not None:
            run, cursor = found
            self.follower.open(cursor)
            self._mark = (self.follower.position, self.follower.line)
            self.say(
                f"{self.path}: going on with run {run.local_id} from line {self.follower.line + 1}"
            )
        else:
            run = self.client.open_run(
                **self.metadata,
                constants=constants(self.stand, self.mapping),
                cursor=self.follower.cursor(self.key, 0, 0),
            )
        try:
            self.on_run(run)  # may stop the agent (a key refused): the run stays spooled
        except BaseException:
            self.follower.close()
            raise
        outcome = Outcome(run)
        idle_since = time.monotonic()
        try:
            while True:
                change = self.follower.changed() if follow else None
                if change is not None:
                    table = self._switch(change, run, table, outcome)
                    idle_since = time.monotonic()
                    continue
                lines = self.follower.lines(final=not follow)
                self.progress(self.follower.size_read)
                for line in lines:
                    table = self._take(line, table, outcome)
                    if len(self._rows) >= self.batching.rows:
                        self._flush(run, table, outcome)
                now = time.monotonic()
                if lines:
                    idle_since = now
                if self._rows and now - self._first >= self.batching.seconds:
                    self._flush(run, table, outcome)
                if lines:
                    continue
                if not follow or stop.is_set():
                    break
                idle = self.batching.finish_after_idle
                if idle is not None and now - idle_since >= idle:
                    self.say(f"{self.path}: no new row for {idle:g} s, finishing")
                    break
                stop.wait(self.batching.poll)
            self._flush(run, table, outcome)
            outcome.partial = self.follower.partial
            if outcome.partial:
                self.say(
                    f"{self.path}:{self.follower.line + 1}: a partial last line (no end of "
                    "line yet) was not taken"
                )
            run.finish()
        finally:
            self.follower.close()
        return outcome

    def _take(self, line: Line, table: Table, outcome: Outcome) -> Table:
        self._mark = (line.end, line.number)
        if line.number == 1:  # the header of a file (the first, or after a rotation)
            return self._table(line.text)
        if not line.text.strip() or line.text.lstrip().startswith("#"):
            return table
        try:
            values = table.parse(line.text, line.number)
        except InputError as exc:
            self.say(f"refused: {exc}")
            self._rejects.append(Reject(str(self.path), line.number, exc.column, str(exc)))
            outcome.rejected += 1
            return table
        if not self._rows:
            self._first = time.monotonic()
        self._rows.append(values)
        return table

    def _flush(self, run: RunHandle, table: Table, outcome: Outcome) -> None:
        cursor = self.follower.cursor(self.key, *self._mark)
        rejects = tuple(self._rejects)
        if self._rows:
            run.post(self.group.name, table.columns(self._rows), cursor=cursor, rejects=rejects)
            outcome.rows += len(self._rows)
            outcome.batches += 1
        elif rejects:
            run.mark(cursor, rejects)
        self._rows, self._rejects = [], []

    def _switch(self, change: str, run: RunHandle, table: Table, outcome: Outcome) -> Table:
        """The file was rotated (read the old one to its end first) or truncated."""
        if change == "rotated":
            for line in self.follower.lines():
                table = self._take(line, table, outcome)
        self._flush(run, table, outcome)
        if self.follower.partial:
            self.say(f"{self.path}:{self.follower.line + 1}: the old file ended in a partial line")
        self.say(f"{self.path}: the file was {change}; reading the new one from its start")
        self.follower.open()
        self._mark = (0, 0)
        run.mark(self.follower.cursor(self.key, *self._mark))
        return table
