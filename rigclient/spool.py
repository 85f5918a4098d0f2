"""The durable spool of a lab PC: runs, their batches until the server has them, file cursors.

One SQLite database in WAL mode (``spool.sqlite`` in the spool directory) with
``synchronous=FULL``: a commit returns after the write-ahead log is fsync'd, so a batch
that :meth:`Spool.append` returned for survives a kill -9 of the agent and a power cut.
Tables:

``runs``      one per opened run: the opening body (and its checksum), its Idempotency-Key,
              the server's id once the opening is delivered, the next seq, batches
              acknowledged, whether the finish is queued and delivered, the server's problem
              if it refused something (a 422), the damage found in the spool, when the
              operator dropped it, and the last failed try (what, since when, how often).
``batches``   the batches not yet acknowledged, as npz bytes, by ``(run, seq)``, each with a
              checksum of its run, seq, group, rows and bytes written with it and checked
              before it is sent; deleted in the transaction that counts their
              acknowledgement.
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

A spool of an older rigclient (``PRAGMA user_version`` 0) is brought up to date when it is
opened: the new columns are added (its batches have no checksum: their npz archive's own
CRC-32s are checked instead), and a refusal other than a 422 that the older rigclient
recorded is lifted, so the run is tried again.

One process at a time delivers a spool: see :mod:`rigclient.lock`.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
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

from rigclient.errors import SpoolDamaged, SpoolError, SpoolFull, SpoolUnreadable, UnknownRun
from rigclient.http import npz_bytes
from rigclient.jsontext import loads_json

FILENAME = "spool.sqlite"
#: The spool's layout (``PRAGMA user_version``): 0 the first rigclient's, 1 with checksums,
#: drops and the last failed try.
SCHEMA_VERSION = 1
#: SQLite's answers to a write that found no room (ENOSPC; EFBIG past a file size limit).
_NO_ROOM = ("SQLITE_FULL", "SQLITE_IOERR_WRITE")
#: SQLite's answers that say nothing of the file's state: busy, locked, out of reach.
_NOT_DAMAGE = (
    "SQLITE_BUSY",
    "SQLITE_LOCKED",
    "SQLITE_CANTOPEN",
    "SQLITE_PERM",
    "SQLITE_READONLY",
    "SQLITE_IOERR",
    "SQLITE_FULL",
    "SQLITE_INTERRUPT",
    "SQLITE_AUTH",
)

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
    created REAL NOT NULL,
    source TEXT,
    body_checksum TEXT,
    damaged TEXT,
    dropped REAL,
    last_error TEXT,
    last_status INTEGER,
    failing_since REAL,
    failed_at REAL,
    tries INTEGER NOT NULL DEFAULT 0
);
CREATE TABLE IF NOT EXISTS batches (
    local_id TEXT NOT NULL,
    seq INTEGER NOT NULL,
    grp TEXT NOT NULL,
    rows INTEGER NOT NULL,
    payload BLOB NOT NULL,
    created REAL NOT NULL,
    checksum TEXT,
    damaged TEXT,
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
#: Columns added since version 0, for the migration of an older spool.
_ADDED = {
    "runs": (
        ("source", "TEXT"),
        ("body_checksum", "TEXT"),
        ("damaged", "TEXT"),
        ("dropped", "REAL"),
        ("last_error", "TEXT"),
        ("last_status", "INTEGER"),
        ("failing_since", "REAL"),
        ("failed_at", "REAL"),
        ("tries", "INTEGER NOT NULL DEFAULT 0"),
    ),
    "batches": (("checksum", "TEXT"), ("damaged", "TEXT")),
}

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


def batch_checksum(local_id: str, seq: int, group: str, rows: int, payload: bytes) -> str:
    """The checksum written with a batch: BLAKE2b of its run, seq, group, rows and bytes
    (a flipped bit in any of them, or a batch moved to another seq, no longer matches)."""
    digest = hashlib.blake2b(digest_size=16, person=b"rigclient-batch")
    for part in (local_id.encode(), str(seq).encode(), group.encode(), str(rows).encode()):
        digest.update(len(part).to_bytes(4, "big"))
        digest.update(part)
    digest.update(payload)
    return "b2:" + digest.hexdigest()


def text_checksum(text: str) -> str:
    """The checksum written with a run's opening body."""
    return "b2:" + hashlib.blake2b(text.encode(), digest_size=16).hexdigest()


@dataclass(frozen=True, slots=True)
class Pending:
    """A batch to deliver: the run's local and server ids, seq, group, npz payload, rows
    and the checksum written with it (None in a spool of an older rigclient)."""

    local_id: str
    server_id: str
    seq: int
    group: str
    payload: bytes
    rows: int = 0
    checksum: str | None = None

    def damage(self) -> str | None:
        """Why the batch cannot be sent as spooled, or None when it is intact: its bytes
        against its checksum; a batch without one (an older spool) by reading its npz
        archive back, which checks the archive's own CRC-32s."""
        if self.checksum is not None:
            found = batch_checksum(self.local_id, self.seq, self.group, self.rows, self.payload)
            if found != self.checksum:
                return (
                    "its bytes no longer match the checksum written with it (the spool's file "
                    "was damaged on the disk)"
                )
            return None
        try:
            columns_of(self.payload)
        except Exception as exc:  # a damaged archive fails in many ways (zip, zlib, npy)
            return f"its npz archive does not read back ({type(exc).__name__}: {exc})"
        return None


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
    rows_pending: int = 0
    damaged: str | None = None
    dropped: float | None = None
    last_error: str | None = None
    last_status: int | None = None
    failing_since: float | None = None
    tries: int = 0
    source: str | None = None
    failed_at: float | None = None

    @property
    def state(self) -> str:
        """``dropped`` (by the operator), ``refused`` (the server's 422), ``damaged`` (in the
        spool), ``delivered`` (finished on the server), ``finishing``, ``open``."""
        if self.dropped is not None:
            return "dropped"
        if self.refused is not None:
            return "refused"
        if self.damaged is not None:
            return "damaged"
        if self.finished:
            return "delivered"
        return "finishing" if self.finish_queued else "open"

    @property
    def stopped(self) -> bool:
        """Its delivery stopped until the operator acts (``rigclient retry`` or ``drop``):
        refused by the server, or damaged in the spool."""
        return self.dropped is None and (self.refused is not None or self.damaged is not None)

    @property
    def done(self) -> bool:
        """Nothing left to deliver: finished on the server, dropped, or opened, acknowledged
        and not asked to finish yet."""
        if self.dropped is not None:
            return True
        if self.finish_queued:
            return self.finished
        return self.server_id is not None and self.pending == 0

    @property
    def name(self) -> str:
        """The run as the operator knows it: the server's id, else the local one."""
        return self.server_id or self.local_id


@dataclass(frozen=True, slots=True)
class Requeued:
    """What ``rigclient retry`` did to a run: batches and rows queued again, what had
    stopped it, and the batches still damaged."""

    batches: int
    rows: int
    was: str
    still_damaged: tuple[int, ...] = ()


@dataclass(frozen=True, slots=True)
class Dropped:
    """What ``rigclient drop`` took out of the spool: batches, rows, and the queued finish."""

    batches: int
    rows: int
    finish: bool


def amount(batches: int, rows: int) -> str:
    """Batches and their rows for a message: ``3 batches (9 rows)``, ``1 batch (1 row)``."""
    return f"{batches} batch{'' if batches == 1 else 'es'} ({rows} row{'' if rows == 1 else 's'})"


def columns_of(payload: bytes) -> dict[str, np.ndarray[Any, np.dtype[np.float64]]]:
    """The columns of a spooled batch."""
    with np.load(io.BytesIO(payload)) as npz:
        return {name: np.asarray(npz[name], dtype=np.float64) for name in npz.files}


def new_local_id() -> str:
    """A local run id: ``local-`` UTC time and 32 random bits (the server's id comes later)."""
    return f"local-{datetime.now(UTC):%Y%m%dT%H%M%S}Z-{secrets.token_hex(4)}"


def damaged_text(path: Path, exc: BaseException) -> str:
    """What the operator is told of a spool SQLite cannot read, and what saves it."""
    why = str(exc) if not isinstance(exc, UnicodeDecodeError) else "text that is not UTF-8"
    return (
        f"the spool is damaged: SQLite cannot read {path} ({why}). `rigclient salvage "
        f"--spool {path.parent}` keeps what can still be read (the runs, their batches not yet "
        "delivered, the refused lines) in a new spool, which `rigclient send` then delivers, "
        f"and moves the damaged file aside as {path.name}.damaged-<time> with the rest"
    )


def is_damage(exc: BaseException) -> bool:
    """Whether a sqlite3 error (or a text read back) says the file is damaged, rather than
    full, busy or out of reach."""
    if isinstance(exc, UnicodeDecodeError):
        return True
    name = str(getattr(exc, "sqlite_errorname", ""))
    if name in _NO_ROOM or getattr(exc, "errno", None) in (errno.ENOSPC, errno.EFBIG):
        return False
    misuse = isinstance(exc, sqlite3.ProgrammingError | sqlite3.InterfaceError)  # ours
    return (
        isinstance(exc, sqlite3.DatabaseError) and not misuse and not name.startswith(_NOT_DAMAGE)
    )


class _Rows:
    """A statement's rows, read at once."""

    def __init__(self, rows: list[Any], rowcount: int = -1) -> None:
        self._rows = rows
        self.rowcount = rowcount  # rows a statement changed

    def fetchone(self) -> Any:
        return self._rows[0] if self._rows else None

    def fetchall(self) -> list[Any]:
        return self._rows

    def __iter__(self) -> Iterator[Any]:
        return iter(self._rows)


class _Connection:
    """The spool's connection: each statement's rows read at once, and an error that says
    the file is damaged raised as :class:`SpoolUnreadable` (the others as they are, for
    :func:`_translate`)."""

    def __init__(self, db: sqlite3.Connection, path: Path) -> None:
        self.db, self.path = db, path

    @property
    def in_transaction(self) -> bool:
        return self.db.in_transaction

    def execute(self, sql: str, args: Any = ()) -> _Rows:
        try:
            cursor = self.db.execute(sql, args)
            return _Rows(cursor.fetchall(), cursor.rowcount)
        except (sqlite3.Error, UnicodeDecodeError) as exc:
            if is_damage(exc):
                raise SpoolUnreadable(damaged_text(self.path, exc)) from exc
            raise

    def close(self) -> None:
        self.db.close()


class Spool:
    """The spool in ``directory`` (made if missing; brought up to date if an older rigclient
    wrote it). One connection: calls from several threads take a lock
    (:class:`rigclient.Client` holds one); the sender has its own."""

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
            connection = sqlite3.connect(
                self.path, timeout=30.0, isolation_level=None, check_same_thread=False
            )
            self._db = _Connection(connection, self.path)
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute("PRAGMA synchronous=FULL")
            connection.executescript(_SCHEMA)
            connection.executescript(_FILE_SCHEMA)
            self._migrate()
        except (OSError, sqlite3.Error, UnicodeDecodeError) as exc:
            if hasattr(self, "_db"):
                self._db.close()
            raise _translate(exc, f"open the spool {self.path}", self.path) from exc
        except SpoolError:
            self._db.close()
            raise

    def close(self) -> None:
        self._db.close()

    def __enter__(self) -> Spool:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _migrate(self) -> None:
        """Bring a spool of an older rigclient up to date (see the module's notes)."""
        if self._db.execute("PRAGMA user_version").fetchone()[0] >= SCHEMA_VERSION:
            return
        with self._write(f"bring the spool {self.path} up to date") as db:
            if db.execute("PRAGMA user_version").fetchone()[0] >= SCHEMA_VERSION:
                return  # another process did it meanwhile
            for table, columns in _ADDED.items():
                have = {row[1] for row in db.execute(f"PRAGMA table_info({table})")}
                for name, declared in columns:
                    if name not in have:
                        db.execute(f"ALTER TABLE {table} ADD COLUMN {name} {declared}")
            for local_id, refused, what in db.execute(
                "SELECT local_id, refused, refused_what FROM runs WHERE refused IS NOT NULL"
            ).fetchall():
                try:
                    problem = loads_json(refused)
                    status = int(problem.get("status"))
                except (TypeError, ValueError, AttributeError):
                    problem, status = {}, 0
                if status == 422:
                    continue
                note = (
                    f"an older rigclient stopped the run at its {what} on: {status} "
                    f"{problem.get('title', '')}: {str(problem.get('detail', ''))[:200]}; tried "
                    "again (only the API's 422 stops a run now)"
                )
                db.execute(
                    "UPDATE runs SET refused = NULL, refused_what = NULL, last_error = ?, "
                    "last_status = ? WHERE local_id = ?",
                    (note, status or None, local_id),
                )
            db.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")

    @contextmanager
    def _write(self, what: str) -> Iterator[_Connection]:
        """One immediate transaction; sqlite3 errors translated, nothing committed on error."""
        try:
            self._db.execute("BEGIN IMMEDIATE")
        except sqlite3.Error as exc:
            raise _translate(exc, what, self.path) from exc
        try:
            yield self._db
            self._db.execute("COMMIT")
        except BaseException as exc:
            if self._db.in_transaction:
                with contextlib.suppress(sqlite3.Error, SpoolError):
                    self._db.execute("ROLLBACK")
            if isinstance(exc, sqlite3.Error):
                raise _translate(exc, what, self.path) from exc
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
        text = json.dumps(dict(body))
        with self._write("open a run in the spool") as db:
            db.execute(
                "INSERT INTO runs (local_id, stand, body, idempotency_key, created, source, "
                "body_checksum) VALUES (?, ?, ?, ?, ?, ?, ?)",
                (
                    local_id,
                    stand,
                    text,
                    key,
                    now,
                    None if cursor is None else cursor.key,
                    text_checksum(text),
                ),
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
        """The server refused ``what`` of the run (its 422): its delivery stops, the batch
        stays."""
        with self._write(f"record a refusal of run {local_id}") as db:
            db.execute(
                "UPDATE runs SET refused = ?, refused_what = ?, last_error = NULL, "
                "last_status = NULL, failing_since = NULL, tries = 0 WHERE local_id = ?",
                (json.dumps(dict(problem)), what, local_id),
            )

    def damaged(self, local_id: str, seq: int | None, reason: str) -> None:
        """A batch (``seq``; None: the opening) was found damaged in the spool: kept, never
        sent; the run's delivery stops there."""
        with self._write(f"record damage in run {local_id}") as db:
            if seq is not None:
                db.execute(
                    "UPDATE batches SET damaged = ? WHERE local_id = ? AND seq = ?",
                    (reason, local_id, seq),
                )
            db.execute("UPDATE runs SET damaged = ? WHERE local_id = ?", (reason, local_id))

    def failed(self, local_id: str, reason: str, status: int | None) -> None:
        """A try for the run failed and will be made again: what, since when, how often
        (``rigclient status`` shows it)."""
        now = time.time()
        with self._write(f"record a failed try of run {local_id}") as db:
            db.execute(
                "UPDATE runs SET last_error = ?, last_status = ?, tries = tries + 1, "
                "failing_since = COALESCE(failing_since, ?), failed_at = ? WHERE local_id = ?",
                (reason, status, now, now, local_id),
            )

    def recovered(self, local_id: str) -> None:
        """A try for the run succeeded after failures: forget them."""
        with self._write(f"record a delivery of run {local_id}") as db:
            db.execute(
                "UPDATE runs SET last_error = NULL, last_status = NULL, failing_since = NULL, "
                "failed_at = NULL, tries = 0 WHERE local_id = ? AND "
                "(last_error IS NOT NULL OR tries > 0)",
                (local_id,),
            )

    def retry(self, local_id: str) -> Requeued:
        """Queue a run again that a refusal or damage stopped (``rigclient retry``): the
        refusal is lifted, the damaged batches checked again (those intact now are queued,
        the others stay damaged), the failed tries forgotten."""
        (record,) = self.runs(local_id)
        if record.dropped is not None:
            raise SpoolError(f"run {record.name} was dropped: nothing of it is left to send")
        with self._write(f"queue run {local_id} again") as db:
            still: list[int] = []
            for batch in self._batches(db, local_id, damaged=True):
                if batch.damage() is None:
                    db.execute(
                        "UPDATE batches SET damaged = NULL WHERE local_id = ? AND seq = ?",
                        (local_id, batch.seq),
                    )
                else:
                    still.append(batch.seq)
            body_ok = self._body_damage(db, local_id) is None
            db.execute(
                "UPDATE runs SET refused = NULL, refused_what = NULL, damaged = ?, "
                "last_error = NULL, last_status = NULL, failing_since = NULL, tries = 0 "
                "WHERE local_id = ?",
                (None if not still and body_ok else record.damaged, local_id),
            )
        return Requeued(record.pending, record.rows_pending, _stopped_by(record), tuple(still))

    def drop(self, local_id: str, *, damaged_only: bool = False) -> Dropped:
        """Take what is pending of a run out of the spool (``rigclient drop``): its batches
        and its queued finish; the run is kept as ``dropped``, and the file it followed is
        forgotten (a new agent on it opens a new run). ``damaged_only``: only the damaged
        batches, and the run goes on without them."""
        (record,) = self.runs(local_id)
        with self._write(f"drop what is pending of run {local_id}") as db:
            where = "local_id = ?" + (" AND damaged IS NOT NULL" if damaged_only else "")
            batches, rows = db.execute(
                f"SELECT COUNT(*), COALESCE(SUM(rows), 0) FROM batches WHERE {where}",
                (local_id,),
            ).fetchone()
            db.execute(f"DELETE FROM batches WHERE {where}", (local_id,))
            if damaged_only:
                if self._body_damage(db, local_id) is None:
                    db.execute("UPDATE runs SET damaged = NULL WHERE local_id = ?", (local_id,))
                return Dropped(int(batches), int(rows), False)
            db.execute(
                "UPDATE runs SET dropped = ?, last_error = NULL, failing_since = NULL "
                "WHERE local_id = ?",
                (time.time(), local_id),
            )
            db.execute("DELETE FROM sources WHERE local_id = ?", (local_id,))
        return Dropped(int(batches), int(rows), record.finish_queued and not record.finished)

    def _require_open(self, db: _Connection, local_id: str) -> None:
        row = db.execute(
            "SELECT finish_queued, dropped FROM runs WHERE local_id = ?", (local_id,)
        ).fetchone()
        if row is None:
            raise UnknownRun(f"no run {local_id} in the spool {self.path}")
        if row[1] is not None:
            raise SpoolError(f"run {local_id} was dropped (`rigclient drop`): it takes no more")
        if row[0]:
            raise SpoolError(f"run {local_id} is finished: it takes no more batches")

    def _check_limits(self, db: _Connection, now: float) -> None:
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
        db: _Connection,
        local_id: str,
        group: str,
        columns: Mapping[str, ArrayLike],
        now: float,
    ) -> int:
        payload = npz_bytes(columns)
        rows = int(max((np.size(v) for v in columns.values()), default=0))
        (seq,) = db.execute(
            "UPDATE runs SET next_seq = next_seq + 1 WHERE local_id = ? RETURNING next_seq - 1",
            (local_id,),
        ).fetchone()
        db.execute(
            "INSERT INTO batches (local_id, seq, grp, rows, payload, created, checksum) "
            "VALUES (?, ?, ?, ?, ?, ?, ?)",
            (
                local_id,
                seq,
                group,
                rows,
                payload,
                now,
                batch_checksum(local_id, int(seq), group, rows, payload),
            ),
        )
        return int(seq)

    def _move(self, db: _Connection, local_id: str, c: Cursor) -> None:
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

    def undelivered(self, key: str) -> str | None:
        """A run spooled from the source ``key`` whose finish is queued and not delivered
        (nor dropped): the local id of the newest, or None."""
        row = self._db.execute(
            "SELECT local_id FROM runs WHERE source = ? AND finish_queued = 1 AND finished = 0 "
            "AND dropped IS NULL ORDER BY created DESC LIMIT 1",
            (key,),
        ).fetchone()
        return None if row is None else str(row[0])

    def opening(self, local_id: str) -> tuple[dict[str, Any], str]:
        """The body and Idempotency-Key of the run's opening; :class:`SpoolDamaged` if the
        body no longer matches its checksum."""
        damage = self._body_damage(self._db, local_id)
        if damage is not None:
            raise SpoolDamaged(damage)
        row = self._db.execute(
            "SELECT body, idempotency_key FROM runs WHERE local_id = ?", (local_id,)
        ).fetchone()
        try:
            return loads_json(row[0]), str(row[1])
        except ValueError as exc:
            raise SpoolDamaged(
                f"the opening of run {local_id} in {self.path} cannot be read: {exc}"
            ) from None

    def _body_damage(self, db: _Connection, local_id: str) -> str | None:
        row = db.execute(
            "SELECT body, body_checksum FROM runs WHERE local_id = ?", (local_id,)
        ).fetchone()
        if row is None:
            raise UnknownRun(f"no run {local_id} in the spool {self.path}")
        body, checksum = row
        if checksum is not None and (not isinstance(body, str) or text_checksum(body) != checksum):
            return (
                f"the opening of run {local_id} in {self.path} no longer matches the checksum "
                "written with it (the spool's file was damaged on the disk)"
            )
        return None

    def next_batch(self, local_id: str, seq: int = 0) -> Pending | None:
        """The run's first batch not acknowledged from ``seq`` on."""
        row = self._db.execute(
            "SELECT b.local_id, r.server_id, b.seq, b.grp, b.payload, b.rows, b.checksum "
            "FROM batches b JOIN runs r USING (local_id) WHERE b.local_id = ? AND "
            "b.seq >= ? ORDER BY b.seq LIMIT 1",
            (local_id, seq),
        ).fetchone()
        return None if row is None else Pending(*row)

    def _batches(self, db: _Connection, local_id: str, *, damaged: bool = False) -> list[Pending]:
        rows = db.execute(
            "SELECT b.local_id, r.server_id, b.seq, b.grp, b.payload, b.rows, b.checksum "
            "FROM batches b JOIN runs r USING (local_id) WHERE b.local_id = ?"
            + (" AND b.damaged IS NOT NULL" if damaged else "")
            + " ORDER BY b.seq",
            (local_id,),
        ).fetchall()
        return [Pending(*row) for row in rows]

    def damaged_batches(self, local_id: str) -> list[tuple[int, int, str]]:
        """The run's damaged batches: seq, rows, why."""
        rows = self._db.execute(
            "SELECT seq, rows, damaged FROM batches WHERE local_id = ? AND damaged IS NOT NULL "
            "ORDER BY seq",
            (local_id,),
        )
        return [(int(a), int(b), str(c)) for a, b, c in rows]

    def find(self, name: str) -> str:
        """The local id of the run ``name`` (its local id or the server's)."""
        row = self._db.execute(
            "SELECT local_id FROM runs WHERE local_id = ? OR server_id = ? "
            "ORDER BY created DESC LIMIT 1",
            (name, name),
        ).fetchone()
        if row is None:
            raise UnknownRun(f"no run {name} in the spool {self.path} (`rigclient status`)")
        return str(row[0])

    def runs(self, local_id: str | None = None, *, active: bool = False) -> list[RunRecord]:
        """Every run (or one; or those ``active``: neither refused, damaged, dropped nor
        finished), oldest first."""
        query = (
            "SELECT r.local_id, r.stand, r.body, r.server_id, r.next_seq, r.acknowledged, "
            "(SELECT COUNT(*) FROM batches b WHERE b.local_id = r.local_id), "
            "r.finish_queued, r.finished, r.refused, r.refused_what, "
            "(SELECT COUNT(*) FROM rejects j WHERE j.local_id = r.local_id), r.created, "
            "(SELECT COALESCE(SUM(b.rows), 0) FROM batches b WHERE b.local_id = r.local_id), "
            "r.damaged, r.dropped, r.last_error, r.last_status, r.failing_since, r.tries, "
            "r.source, r.failed_at FROM runs r"
        )
        args: tuple[str, ...] = ()
        if local_id is not None:
            query += " WHERE r.local_id = ?"
            args = (local_id,)
        elif active:
            query += (
                " WHERE r.refused IS NULL AND r.damaged IS NULL AND r.dropped IS NULL "
                "AND r.finished = 0"
            )
        out = []
        for row in self._db.execute(query + " ORDER BY r.created, r.local_id", args):
            out.append(
                RunRecord(
                    local_id=row[0],
                    stand=row[1],
                    title=_title(row[2]),
                    server_id=row[3],
                    batches=row[4],
                    acknowledged=row[5],
                    pending=row[6],
                    finish_queued=bool(row[7]),
                    finished=bool(row[8]),
                    refused=None if row[9] is None else _problem(row[9]),
                    refused_what=row[10],
                    rejects=row[11],
                    created=row[12],
                    rows_pending=row[13],
                    damaged=row[14],
                    dropped=row[15],
                    last_error=row[16],
                    last_status=row[17],
                    failing_since=row[18],
                    tries=row[19],
                    source=row[20],
                    failed_at=row[21],
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


def _title(body: str) -> str:
    """The title of a run's opening body (a damaged body has none)."""
    try:
        return str(loads_json(body).get("title", ""))
    except (TypeError, ValueError, AttributeError):
        return "(the opening is damaged)"


def _problem(text: str) -> dict[str, Any]:
    try:
        found = loads_json(text)
    except ValueError:
        found = None
    return found if isinstance(found, dict) else {"status": None, "detail": str(text)[:200]}


def _stopped_by(record: RunRecord) -> str:
    """What stopped a run, for the operator."""
    if record.refused is not None:
        return (
            f"refused at its {record.refused_what}: {record.refused.get('status')} "
            f"{record.refused.get('title', '')}: {record.refused.get('detail')}"
        )
    if record.damaged is not None:
        return f"damaged in the spool: {record.damaged}"
    if record.last_error is not None:
        return f"waiting after {record.tries} failed tries: {record.last_error}"
    return "not stopped"


def _translate(exc: BaseException, what: str, path: Path) -> SpoolError:
    """A sqlite3 or OS error as the spool's own: a full disk (or a file size limit) is
    :class:`SpoolFull`, a damaged file :class:`SpoolUnreadable`."""
    if is_damage(exc):
        return SpoolUnreadable(damaged_text(path, exc))
    text = str(exc)
    name = getattr(exc, "sqlite_errorname", "")
    if name in _NO_ROOM or getattr(exc, "errno", None) in (errno.ENOSPC, errno.EFBIG):
        return SpoolFull(
            f"could not {what}: no room on the disk ({name or text}: the disk is full or the "
            "spool's file may not grow); nothing was spooled"
        )
    return SpoolError(f"could not {what}: {text}; nothing was spooled")
