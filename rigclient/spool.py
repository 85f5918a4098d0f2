"""The durable spool of a lab PC: runs, their batches until the server has them, file cursors.

One SQLite database in WAL mode (``spool.sqlite`` in the spool directory) with
``synchronous=FULL``: a commit returns after the write-ahead log is fsync'd, so a batch
that :meth:`Spool.append` returned for survives a kill -9 of the agent and a power cut.
Tables:

``runs``      one per opened run: the opening body, its Idempotency-Key, the server's id once
              the opening is delivered, the next seq, batches acknowledged, whether the finish
              is queued and delivered, and the server's problem if it refused something.
``batches``   the batches not yet acknowledged, as npz bytes, by ``(run, seq)``; deleted in
              the transaction that counts their acknowledgement.
``sources``   the file an agent follows for a run: path, device, inode, byte position after
              the last row spooled and its line number, written in the batch's transaction.
``rejects``   lines of a file that could not be read (file, line, column, why), kept with the
              run and shown by ``rigclient status``.
``headers``   the header lines an agent met in a file after its first (a header changed
              mid-file): where each starts and its text, so that an agent started again
              reads the rows after the cursor by the header in effect there.

Every writing method is one transaction. sqlite3 errors are translated: a full disk (or a
file size limit) is :class:`SpoolFull`, other failures :class:`SpoolError`; in both cases
nothing of the call was committed.
"""

from __future__ import annotations

import errno
import io
import json
import secrets
import sqlite3
import time
import uuid
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from rigclient.errors import SpoolError, SpoolFull, UnknownRun
from rigclient.http import npz_bytes

FILENAME = "spool.sqlite"
#: SQLite's answers to a write that found no room (ENOSPC; EFBIG past a file size limit).
_NO_ROOM = ("SQLITE_FULL", "SQLITE_IOERR_WRITE")

_SCHEMA = """
CREATE TABLE IF NOT EXISTS runs (
    local_id TEXT PRIMARY KEY,
    stand TEXT NOT NULL,
    body TEXT NOT NULL,
    idempotency_key TEXT NOT NULL,
    server_id TEXT,
    next_seq INTEGER NOT NULL DEFAULT 0,
    acknowledged INTEGER NOT NULL DEFAULT 0,
    finish_queued INTEGER NOT NULL DEFAULT 0,
    finished INTEGER NOT NULL DEFAULT 0,
    refused TEXT,
    refused_what TEXT,
    created REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS batches (
    local_id TEXT NOT NULL,
    seq INTEGER NOT NULL,
    grp TEXT NOT NULL,
    rows INTEGER NOT NULL,
    payload BLOB NOT NULL,
    created REAL NOT NULL,
    PRIMARY KEY (local_id, seq)
);
CREATE TABLE IF NOT EXISTS sources (
    key TEXT PRIMARY KEY,
    local_id TEXT NOT NULL,
    path TEXT NOT NULL,
    device INTEGER NOT NULL,
    inode INTEGER NOT NULL,
    position INTEGER NOT NULL,
    line INTEGER NOT NULL
);
CREATE TABLE IF NOT EXISTS rejects (
    local_id TEXT NOT NULL,
    file TEXT NOT NULL,
    line INTEGER NOT NULL,
    col TEXT NOT NULL,
    message TEXT NOT NULL,
    created REAL NOT NULL
);
"""

_FILE_SCHEMA = """
CREATE TABLE IF NOT EXISTS headers (
    key TEXT NOT NULL,
    device INTEGER NOT NULL,
    inode INTEGER NOT NULL,
    start INTEGER NOT NULL,
    line INTEGER NOT NULL,
    text TEXT NOT NULL,
    PRIMARY KEY (key, device, inode, start)
);
"""


@dataclass(frozen=True, slots=True)
class SpoolLimits:
    """The bounds of a spool.

    Attributes
    ----------
    max_bytes : int
        Largest size of the batches not yet acknowledged, bytes.
    max_age : float
        Largest age of the oldest batch not yet acknowledged, s: past it the server has been
        out of reach too long, and the caller is told instead of spooling on.
    """

    max_bytes: int = 2 << 30
    max_age: float = 14 * 86_400.0

    def __post_init__(self) -> None:
        if self.max_bytes <= 0 or self.max_age <= 0:
            raise ValueError(
                f"spool limits must be > 0, got max_bytes={self.max_bytes}, max_age={self.max_age}"
            )


@dataclass(frozen=True, slots=True)
class Cursor:
    """Where a followed file stands after the rows of a batch: its identity and position.

    Attributes
    ----------
    key : str
        The source's name in the spool (the file, stand and group of a ``tail``).
    path : str
    device, inode : int
        The file's identity (``os.stat``), to tell a rotated file from the same one.
    position : int
        Byte offset after the last row spooled.
    line : int
        Line number (1-based) of the last line read.
    """

    key: str
    path: str
    device: int
    inode: int
    position: int
    line: int


@dataclass(frozen=True, slots=True)
class Reject:
    """A line of a file that could not be read: where and why."""

    file: str
    line: int
    column: str
    message: str


@dataclass(frozen=True, slots=True)
class Pending:
    """A batch to deliver: the run's local and server ids, seq, group, npz payload."""

    local_id: str
    server_id: str
    seq: int
    group: str
    payload: bytes


@dataclass(frozen=True, slots=True)
class RunRecord:
    """One run as the spool knows it (``rigclient status``)."""

    local_id: str
    stand: str
    title: str
    server_id: str | None
    batches: int
    acknowledged: int
    pending: int
    finish_queued: bool
    finished: bool
    refused: dict[str, Any] | None
    refused_what: str | None
    rejects: int
    created: float

    @property
    def state(self) -> str:
        """``refused``, ``delivered`` (finished on the server), ``finishing``, ``open``."""
        if self.refused is not None:
            return "refused"
        if self.finished:
            return "delivered"
        return "finishing" if self.finish_queued else "open"

    @property
    def done(self) -> bool:
        """Nothing left to deliver: finished on the server, or opened, acknowledged and not
        asked to finish yet."""
        if self.finish_queued:
            return self.finished
        return self.server_id is not None and self.pending == 0


def columns_of(payload: bytes) -> dict[str, np.ndarray[Any, np.dtype[np.float64]]]:
    """The columns of a spooled batch."""
    with np.load(io.BytesIO(payload)) as npz:
        return {name: np.asarray(npz[name], dtype=np.float64) for name in npz.files}


def new_local_id() -> str:
    """A local run id: ``local-`` UTC time and 32 random bits (the server's id comes later)."""
    return f"local-{datetime.now(UTC):%Y%m%dT%H%M%S}Z-{secrets.token_hex(4)}"


class Spool:
    """The spool in ``directory`` (made if missing). One connection: calls from several
    threads take a lock (:class:`rigclient.Client` holds one); the sender has its own."""

    def __init__(
        self, directory: str | Path, limits: SpoolLimits | None = None, *, create: bool = True
    ) -> None:
        self.directory = Path(directory)
        self.path = self.directory / FILENAME
        self.limits = limits or SpoolLimits()
        if not create and not self.path.exists():
            raise SpoolError(f"no spool in {self.directory} (no {FILENAME})")
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            self._db = sqlite3.connect(
                self.path, timeout=30.0, isolation_level=None, check_same_thread=False
            )
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute("PRAGMA synchronous=FULL")
            self._db.executescript(_SCHEMA)
            self._db.executescript(_FILE_SCHEMA)
        except (OSError, sqlite3.Error) as exc:
            raise _translate(exc, f"open the spool {self.path}") from exc

    def close(self) -> None:
        self._db.close()

    def __enter__(self) -> Spool:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @contextmanager
    def _write(self, what: str) -> Iterator[sqlite3.Connection]:
        """One immediate transaction; sqlite3 errors translated, nothing committed on error."""
        try:
            self._db.execute("BEGIN IMMEDIATE")
        except sqlite3.Error as exc:
            raise _translate(exc, what) from exc
        try:
            yield self._db
            self._db.execute("COMMIT")
        except BaseException as exc:
            if self._db.in_transaction:
                self._db.execute("ROLLBACK")
            if isinstance(exc, sqlite3.Error):
                raise _translate(exc, what) from exc
            raise

    # --- writing ------------------------------------------------------------------------

    def open_run(
        self,
        stand: str,
        body: Mapping[str, Any],
        *,
        constants: Mapping[str, Mapping[str, ArrayLike]] | None = None,
        cursor: Cursor | None = None,
        idempotency_key: str | None = None,
    ) -> str:
        """A new run with a fresh Idempotency-Key (or ``idempotency_key``: an imported
        file's digest), its first batches (``constants``: group -> columns) and the source
        it follows, in one transaction; its local id."""
        local_id = new_local_id()
        key = idempotency_key or str(uuid.uuid4())
        now = time.time()
        with self._write("open a run in the spool") as db:
            db.execute(
                "INSERT INTO runs (local_id, stand, body, idempotency_key, created) "
                "VALUES (?, ?, ?, ?, ?)",
                (local_id, stand, json.dumps(dict(body)), key, now),
            )
            for group, columns in (constants or {}).items():
                self._insert(db, local_id, group, columns, now)
            if cursor is not None:
                self._move(db, local_id, cursor)
        return local_id

    def append(
        self,
        local_id: str,
        group: str | None,
        columns: Mapping[str, ArrayLike] | None,
        *,
        cursor: Cursor | None = None,
        rejects: tuple[Reject, ...] = (),
    ) -> int | None:
        """Spool one batch (with the cursor after its rows and the lines rejected on the
        way), durably; its seq, or None when only the cursor and rejects were written."""
        now = time.time()
        with self._write(f"spool a batch of run {local_id}") as db:
            self._require_open(db, local_id)
            seq = None
            if group is not None and columns is not None:
                self._check_limits(db, now)
                seq = self._insert(db, local_id, group, columns, now)
            for r in rejects:
                db.execute(
                    "INSERT INTO rejects VALUES (?, ?, ?, ?, ?, ?)",
                    (local_id, r.file, r.line, r.column, r.message, now),
                )
            if cursor is not None:
                self._move(db, local_id, cursor)
        return seq

    def queue_finish(self, local_id: str) -> None:
        """Ask for the run's finish after its last batch; the file it followed is forgotten."""
        with self._write(f"finish run {local_id}") as db:
            self._require_open(db, local_id)
            db.execute("UPDATE runs SET finish_queued = 1 WHERE local_id = ?", (local_id,))
            db.execute("DELETE FROM sources WHERE local_id = ?", (local_id,))

    def opened(self, local_id: str, server_id: str) -> None:
        with self._write(f"record the server id of run {local_id}") as db:
            db.execute("UPDATE runs SET server_id = ? WHERE local_id = ?", (server_id, local_id))

    def acknowledged(self, local_id: str, seq: int) -> None:
        """The server has the batch: drop its payload, count it."""
        with self._write(f"record the receipt of batch {seq} of run {local_id}") as db:
            gone = db.execute(
                "DELETE FROM batches WHERE local_id = ? AND seq = ?", (local_id, seq)
            ).rowcount
            db.execute(
                "UPDATE runs SET acknowledged = acknowledged + ? WHERE local_id = ?",
                (gone, local_id),
            )

    def finished(self, local_id: str) -> None:
        with self._write(f"record the finish of run {local_id}") as db:
            db.execute("UPDATE runs SET finished = 1 WHERE local_id = ?", (local_id,))

    def refused(self, local_id: str, what: str, problem: Mapping[str, Any]) -> None:
        """The server refused ``what`` of the run: its delivery stops, the batch stays."""
        with self._write(f"record a refusal of run {local_id}") as db:
            db.execute(
                "UPDATE runs SET refused = ?, refused_what = ? WHERE local_id = ?",
                (json.dumps(dict(problem)), what, local_id),
            )

    def _require_open(self, db: sqlite3.Connection, local_id: str) -> None:
        row = db.execute(
            "SELECT finish_queued FROM runs WHERE local_id = ?", (local_id,)
        ).fetchone()
        if row is None:
            raise UnknownRun(f"no run {local_id} in the spool {self.path}")
        if row[0]:
            raise SpoolError(f"run {local_id} is finished: it takes no more batches")

    def _check_limits(self, db: sqlite3.Connection, now: float) -> None:
        size, oldest = db.execute(
            "SELECT COALESCE(SUM(LENGTH(payload)), 0), MIN(created) FROM batches"
        ).fetchone()
        if size >= self.limits.max_bytes:
            raise SpoolFull(
                f"the spool {self.path} holds {size / 1e6:.1f} MB not yet delivered, the "
                f"limit (max_bytes) is {self.limits.max_bytes / 1e6:.1f} MB: the server has "
                "not taken the batches (see `rigclient status`)"
            )
        if oldest is not None and now - oldest > self.limits.max_age:
            raise SpoolFull(
                f"the oldest batch in the spool {self.path} waits since "
                f"{(now - oldest) / 3600:.1f} h, the limit (max_age) is "
                f"{self.limits.max_age / 3600:.1f} h: the server has not taken the batches "
                "(see `rigclient status`)"
            )

    def _insert(
        self,
        db: sqlite3.Connection,
        local_id: str,
        group: str,
        columns: Mapping[str, ArrayLike],
        now: float,
    ) -> int:
        payload = npz_bytes(columns)
        rows = max((np.size(v) for v in columns.values()), default=0)
        (seq,) = db.execute(
            "UPDATE runs SET next_seq = next_seq + 1 WHERE local_id = ? RETURNING next_seq - 1",
            (local_id,),
        ).fetchone()
        db.execute(
            "INSERT INTO batches VALUES (?, ?, ?, ?, ?, ?)",
            (local_id, seq, group, rows, payload, now),
        )
        return int(seq)

    def _move(self, db: sqlite3.Connection, local_id: str, c: Cursor) -> None:
        db.execute(
            "INSERT OR REPLACE INTO sources VALUES (?, ?, ?, ?, ?, ?, ?)",
            (c.key, local_id, c.path, c.device, c.inode, c.position, c.line),
        )

    # --- reading ------------------------------------------------------------------------

    def source(self, key: str) -> Cursor | None:
        """Where the agent that follows ``key`` stopped, or None."""
        row = self._db.execute(
            "SELECT key, path, device, inode, position, line FROM sources WHERE key = ?", (key,)
        ).fetchone()
        return None if row is None else Cursor(*row)

    def source_run(self, key: str) -> str | None:
        row = self._db.execute("SELECT local_id FROM sources WHERE key = ?", (key,)).fetchone()
        return None if row is None else str(row[0])

    def opening(self, local_id: str) -> tuple[dict[str, Any], str]:
        """The body and Idempotency-Key of the run's opening."""
        row = self._db.execute(
            "SELECT body, idempotency_key FROM runs WHERE local_id = ?", (local_id,)
        ).fetchone()
        if row is None:
            raise UnknownRun(f"no run {local_id} in the spool {self.path}")
        return json.loads(row[0]), str(row[1])

    def next_batch(self, local_id: str, seq: int = 0) -> Pending | None:
        """The run's first batch not acknowledged from ``seq`` on."""
        row = self._db.execute(
            "SELECT b.local_id, r.server_id, b.seq, b.grp, b.payload FROM batches b "
            "JOIN runs r USING (local_id) WHERE b.local_id = ? AND b.seq >= ? "
            "ORDER BY b.seq LIMIT 1",
            (local_id, seq),
        ).fetchone()
        return None if row is None else Pending(*row)

    def runs(self, local_id: str | None = None, *, active: bool = False) -> list[RunRecord]:
        """Every run (or one; or those ``active``: neither refused nor finished), oldest
        first."""
        query = (
            "SELECT r.local_id, r.stand, r.body, r.server_id, r.next_seq, r.acknowledged, "
            "(SELECT COUNT(*) FROM batches b WHERE b.local_id = r.local_id), "
            "r.finish_queued, r.finished, r.refused, r.refused_what, "
            "(SELECT COUNT(*) FROM rejects j WHERE j.local_id = r.local_id), r.created "
            "FROM runs r"
        )
        args: tuple[str, ...] = ()
        if local_id is not None:
            query += " WHERE r.local_id = ?"
            args = (local_id,)
        elif active:
            query += " WHERE r.refused IS NULL AND r.finished = 0"
        out = []
        for row in self._db.execute(query + " ORDER BY r.created, r.local_id", args):
            out.append(
                RunRecord(
                    local_id=row[0],
                    stand=row[1],
                    title=str(json.loads(row[2]).get("title", "")),
                    server_id=row[3],
                    batches=row[4],
                    acknowledged=row[5],
                    pending=row[6],
                    finish_queued=bool(row[7]),
                    finished=bool(row[8]),
                    refused=None if row[9] is None else json.loads(row[9]),
                    refused_what=row[10],
                    rejects=row[11],
                    created=row[12],
                )
            )
        if local_id is not None and not out:
            raise UnknownRun(f"no run {local_id} in the spool {self.path}")
        return out

    def run_by_key(self, idempotency_key: str) -> str | None:
        """The local id of the run opened with ``idempotency_key``, if the spool has one."""
        row = self._db.execute(
            "SELECT local_id FROM runs WHERE idempotency_key = ? ORDER BY created LIMIT 1",
            (idempotency_key,),
        ).fetchone()
        return None if row is None else str(row[0])

    # --- the header lines of followed files (rigclient.agent) ---------------------------

    def keep_header(self, cursor: Cursor, start: int, text: str) -> None:
        """A header line met in the file of ``cursor`` at byte ``start`` (line
        ``cursor.line``): the rows after it are read by it."""
        with self._write("keep a header line") as db:
            db.execute(
                "INSERT OR REPLACE INTO headers VALUES (?, ?, ?, ?, ?, ?)",
                (cursor.key, cursor.device, cursor.inode, start, cursor.line, text),
            )

    def header_before(self, cursor: Cursor) -> tuple[int, str] | None:
        """The line number and text of the last header kept before ``cursor``'s position
        in its file, if any."""
        row = self._db.execute(
            "SELECT line, text FROM headers WHERE key = ? AND device = ? AND inode = ? "
            "AND start < ? ORDER BY start DESC LIMIT 1",
            (cursor.key, cursor.device, cursor.inode, cursor.position),
        ).fetchone()
        return None if row is None else (int(row[0]), str(row[1]))

    def forget_headers(self, key: str) -> None:
        """The file of ``key`` was rotated, truncated or finished."""
        with self._write("forget a file's header lines") as db:
            db.execute("DELETE FROM headers WHERE key = ?", (key,))

    def rejects(self, local_id: str) -> list[Reject]:
        rows = self._db.execute(
            "SELECT file, line, col, message FROM rejects WHERE local_id = ? ORDER BY rowid",
            (local_id,),
        )
        return [Reject(*row) for row in rows]


def _translate(exc: BaseException, what: str) -> SpoolError:
    """A sqlite3 or OS error as the spool's own: a full disk (or a file size limit) is
    :class:`SpoolFull`."""
    text = str(exc)
    name = getattr(exc, "sqlite_errorname", "")
    if name in _NO_ROOM or getattr(exc, "errno", None) in (errno.ENOSPC, errno.EFBIG):
        return SpoolFull(
            f"could not {what}: no room on the disk ({name or text}: the disk is full or the "
            "spool's file may not grow); nothing was spooled"
        )
    return SpoolError(f"could not {what}: {text}; nothing was spooled")
