"""The journal: one SQLite database (WAL mode) holding the run catalogue and the batches.

Tables::

    meta(key, value)            "clean_shutdown": "1" after HDF5Store.close(), "0" while open
    run_keys(key, run_id)       the Idempotency-Key each run was opened with, if any
    runs(id, stand, operator, state, created, ended, run, batches, rows, key_results,
         results, file_final)   the catalogue: filters are columns, ``run`` the full Run JSON,
                                ``file_final`` 1 once the run file is final and fsynced
    batches(n, run_id, seq, grp, rows, group_rows, digest, at, size)
                                every batch ever stored, in order (n); kept for ever, so a
                                retried seq gets its first receipt; ``at`` and ``size``
                                place its readings in the run's payload file
    corrections(run_id, n, body)
                                every correction of a run's readings (body: the
                                schemas.corrections.Correction as JSON), kept for ever:
                                committed before it is acknowledged, then written to the
                                run file's /entry/corrections

The readings of a batch are appended to ``payloads/<run id>.bin`` beside the database
(:mod:`~rigserver.storage.embedded.payload_files`) before its transaction commits, and the file is
deleted once the run file is final. Appending to a file costs one write; a blob in SQLite
is written to the WAL, copied into the database at the checkpoint and freed page by page
when dropped, and the database never shrinks.

A batch is durable once its transaction commits. In WAL mode ``synchronous=NORMAL`` makes a
commit survive the process being killed (kill -9, a crash of Python or of the library):
the WAL and the payload are written before COMMIT returns, their fsync waits. With
``synchronous=FULL`` the payload files touched and the WAL are fsynced at every commit, so
a commit also survives a power loss or a kernel crash, at the price of fsyncs per commit.
"""

from __future__ import annotations

import json
import logging
import sqlite3
import threading
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from datetime import datetime
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from pydantic import ValidationError

from rigserver.storage._catalogue import ENTRY_COLUMNS, entry, run_filters
from rigserver.storage._checks import Batch, StoredBatch
from rigserver.storage._time import iso
from rigserver.storage.embedded.payload_files import PayloadFiles, aligned
from rigserver.storage.errors import RunDamaged, RunExists, RunNotFound, StorageUnavailable
from rigserver.storage.payloads import Payload, decode, encode
from schemas.corrections import Correction
from schemas.runs import Run, RunPage, RunQuery
from schemas.wire import unstorable

Synchronous = Literal["normal", "full"]

_SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS runs (
    id TEXT PRIMARY KEY,
    stand TEXT NOT NULL,
    operator TEXT NOT NULL,
    state TEXT NOT NULL,
    created TEXT NOT NULL,
    ended TEXT,
    run TEXT NOT NULL,
    batches INTEGER NOT NULL DEFAULT 0,
    rows TEXT NOT NULL DEFAULT '{}',
    key_results TEXT NOT NULL DEFAULT '{}',
    results TEXT,
    file_final INTEGER NOT NULL DEFAULT 0
);
CREATE INDEX IF NOT EXISTS runs_by_created ON runs (created, id);
CREATE INDEX IF NOT EXISTS runs_by_stand ON runs (stand, created);
CREATE INDEX IF NOT EXISTS runs_by_operator ON runs (operator, created);
CREATE INDEX IF NOT EXISTS runs_unfinished ON runs (file_final) WHERE file_final = 0;
CREATE TABLE IF NOT EXISTS run_keys (key TEXT PRIMARY KEY, run_id TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS batches (
    n INTEGER PRIMARY KEY,
    run_id TEXT NOT NULL,
    seq INTEGER NOT NULL,
    grp TEXT NOT NULL,
    rows INTEGER NOT NULL,
    group_rows INTEGER NOT NULL,
    digest BLOB NOT NULL,
    at INTEGER NOT NULL,
    size INTEGER NOT NULL,
    UNIQUE (run_id, seq)
);
CREATE TABLE IF NOT EXISTS corrections (
    run_id TEXT NOT NULL,
    n INTEGER NOT NULL,
    body TEXT NOT NULL,
    PRIMARY KEY (run_id, n)
);
"""

log = logging.getLogger(__name__)

#: Seconds between checkpoints of the WAL.
CHECKPOINT_SECONDS = 1.0
#: SQLite's largest integer; an offset past it lists nothing, as any offset past the end
_MAX_INTEGER = 2**63 - 1


@dataclass(frozen=True, slots=True)
class CatalogueEntry:
    """A run as the catalogue has it, with whether its run file is final."""

    run: Run
    file_final: bool


#: The columns of a catalogue row that :func:`catalogue_entry` and :func:`listed` read.
CATALOGUE_COLUMNS = "id, run, batches, rows, file_final, stand, operator, state, created"
Row = tuple[str, str, int, str, int, str, str, str, str]


def catalogue_entry(row: Row) -> CatalogueEntry:
    """The entry of a catalogue row (:data:`CATALOGUE_COLUMNS`); ``RunDamaged`` if the row
    holds what the service refuses today (e.g. a NaN that an older build stored as null, a
    NUL character)."""
    run_id = row[0]
    try:
        run = Run.model_validate_json(row[1])
        run = run.model_copy(update={"batches": row[2], "rows": json.loads(row[3])})
    except ValidationError as exc:
        first = exc.errors()[0]
        where = ".".join(str(p) for p in first["loc"]) or "run"
        raise RunDamaged(f"run {run_id} is damaged: {where}: {first['msg']}") from None
    except ValueError as exc:
        raise RunDamaged(f"run {run_id} is damaged: its row counts are not JSON ({exc})") from None
    found = unstorable(run.configuration, "configuration")
    if found is not None:
        raise RunDamaged(f"run {run_id} is damaged: {found}")
    return CatalogueEntry(run=run, file_final=bool(row[4]))


def listed(row: Row) -> Run | None:
    """The run of a catalogue row as the runs list shows it: a damaged one with its
    ``damage`` and what the row's own columns say; ``None`` (and a warning in the log) if
    even those are not a run's."""
    try:
        return catalogue_entry(row).run
    except RunDamaged as exc:
        damage = str(exc)
    try:
        return Run(
            id=row[0],
            stand=row[5],
            operator=row[6].replace("\x00", "\ufffd"),
            state=row[7],
            created=row[8],
            configuration={},
            damage=damage.replace("\x00", "\\x00"),
        )
    except ValidationError:
        log.warning("%s, and its catalogue columns too; left out of the list", damage)
        return None


class Journal:
    """The catalogue and the batches; not thread-safe (the store serialises the calls).

    Batches are added in a transaction of the caller (:meth:`begin`, :meth:`commit`: one
    commit for a group of batches); every other method commits its own. A failure rolls
    back and raises the sqlite3 error (the store translates it).
    """

    def __init__(self, path: Path, *, synchronous: Synchronous = "normal") -> None:
        self.path = path
        self._full = synchronous == "full"
        #: payload files written in the open transaction (fsynced before a full commit)
        self._dirty: set[str] = set()
        self._db = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
        try:
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute(f"PRAGMA synchronous={synchronous.upper()}")
            self._db.execute("PRAGMA journal_size_limit=67108864")
            # the WAL is checkpointed by a thread of its own (_Checkpointer), not inside
            # the commit that happens to fill it: a checkpoint copies and fsyncs megabytes
            self._db.execute("PRAGMA wal_autocheckpoint=0")
            # Debian's SQLite zeroes freed pages; dropping a finished run's readings would
            # then rewrite them all (seconds for a 50-million-reading run)
            self._db.execute("PRAGMA secure_delete=OFF")
            self._db.executescript(_SCHEMA)
            columns = {row[1] for row in self._db.execute("PRAGMA table_info(batches)")}
            if "at" not in columns:
                raise StorageUnavailable(
                    f"{path} was written by an older rigserver (readings inside SQLite); "
                    "move it away and the catalogue is rebuilt from the run files"
                )
        except BaseException:
            self._db.close()
            raise
        self._payloads = PayloadFiles(path.parent / "payloads")
        self._checkpointer = _Checkpointer(path)

    def close(self) -> None:
        self._checkpointer.stop()
        self._payloads.close()
        self._db.close()  # the last connection: SQLite checkpoints the WAL and removes it

    def _write(self, statements: list[tuple[str, tuple[object, ...]]]) -> None:
        db = self._db
        db.execute("BEGIN IMMEDIATE")
        try:
            for sql, params in statements:
                db.execute(sql, params)
            db.execute("COMMIT")
        except BaseException:
            if db.in_transaction:
                db.execute("ROLLBACK")
            raise

    # --- shutdown marker --------------------------------------------------------------

    def clean_shutdown(self) -> bool:
        """True if the last session closed cleanly (or the journal is new and empty)."""
        row = self._db.execute("SELECT value FROM meta WHERE key = 'clean_shutdown'").fetchone()
        if row is None:
            return bool(self._db.execute("SELECT COUNT(*) FROM runs").fetchone()[0] == 0)
        return bool(row[0] == "1")

    def set_clean_shutdown(self, clean: bool) -> None:
        self._write(
            [
                (
                    "INSERT OR REPLACE INTO meta (key, value) VALUES ('clean_shutdown', ?)",
                    ("1" if clean else "0",),
                )
            ]
        )

    # --- catalogue --------------------------------------------------------------------

    def insert_run(
        self,
        run: Run,
        *,
        file_final: bool = False,
        results: str | None = None,
        key: str | None = None,
        corrections: Iterable[Correction] = (),
    ) -> None:
        """A new catalogue entry (opened with the Idempotency-Key ``key``; an imported run
        with its ``corrections``); ``RunExists`` if the id or the key is taken."""
        keyed: list[tuple[str, tuple[object, ...]]] = []
        if key is not None:
            keyed.append(("INSERT INTO run_keys VALUES (?, ?)", (key, run.id)))
        keyed += [
            (
                "INSERT INTO corrections (run_id, n, body) VALUES (?, ?, ?)",
                (run.id, c.n, c.model_dump_json()),
            )
            for c in corrections
        ]
        try:
            self._write(
                [
                    *keyed,
                    (
                        f"INSERT INTO runs ({ENTRY_COLUMNS}, file_final) "
                        "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                        (*entry(run, results, iso), int(file_final)),
                    ),
                ]
            )
        except sqlite3.IntegrityError as exc:
            raise RunExists(f"a run with id {run.id} (or key) is stored already") from exc

    def run_for_key(self, key: str) -> str | None:
        """The run opened with the Idempotency-Key ``key``, if any."""
        row = self._db.execute("SELECT run_id FROM run_keys WHERE key = ?", (key,)).fetchone()
        return None if row is None else str(row[0])

    def entry(self, run_id: str) -> CatalogueEntry:
        """The run's catalogue entry; ``RunNotFound``, ``RunDamaged``."""
        row = self._db.execute(
            f"SELECT {CATALOGUE_COLUMNS} FROM runs WHERE id = ?", (run_id,)
        ).fetchone()
        if row is None:
            raise RunNotFound(f"no run with id {run_id}")
        return catalogue_entry(row)

    def unfinished(self) -> list[CatalogueEntry]:
        """Runs whose file is not final: the open ones and any whose end did not complete
        (a damaged one is left out, with a warning in the log)."""
        rows = self._db.execute(
            f"SELECT {CATALOGUE_COLUMNS} FROM runs WHERE file_final = 0 ORDER BY created"
        ).fetchall()
        found = []
        for row in rows:
            try:
                found.append(catalogue_entry(row))
            except RunDamaged as exc:
                log.warning("%s; it is left as it is (rigserver check)", exc)
        return found

    def list_runs(self, query: RunQuery) -> RunPage:
        """Runs matching ``query`` (``since <= created < until``), newest first; a damaged
        run is listed with what is wrong with it (:func:`listed`)."""
        found = run_filters(query)
        where = [f"{column} {op} ?" for column, op, _ in found]
        # times as the catalogue keeps them: ISO 8601 text in UTC, sortable
        params = [iso(v) if isinstance(v, datetime) else v for _, _, v in found]
        sql_where = f" WHERE {' AND '.join(where)}" if where else ""
        total = self._db.execute(f"SELECT COUNT(*) FROM runs{sql_where}", params).fetchone()[0]
        rows = self._db.execute(
            f"SELECT {CATALOGUE_COLUMNS} FROM runs{sql_where} "
            "ORDER BY created DESC, id DESC LIMIT ? OFFSET ?",
            [*params, query.limit, min(query.offset, _MAX_INTEGER)],
        ).fetchall()
        return RunPage(total=total, runs=[run for row in rows if (run := listed(row))])

    def delete_run(self, run_id: str, key: str | None) -> None:
        """Remove a run that never took a batch (its creation failed half way)."""
        self._write(
            [
                ("DELETE FROM runs WHERE id = ? AND batches = 0", (run_id,)),
                ("DELETE FROM run_keys WHERE run_id = ?", (run_id,)),
            ]
        )

    def end_run(self, run: Run) -> None:
        """Record the run's end (state, time, final metadata); its file is not final yet."""
        self._write(
            [
                (
                    "UPDATE runs SET state = ?, ended = ?, run = ?, file_final = 0 WHERE id = ?",
                    (
                        run.state.value,
                        None if run.ended is None else iso(run.ended),
                        run.model_dump_json(),
                        run.id,
                    ),
                )
            ]
        )

    def set_results(self, run: Run, results: str) -> None:
        self._write(
            [
                (
                    "UPDATE runs SET run = ?, key_results = ?, results = ? WHERE id = ?",
                    (run.model_dump_json(), json.dumps(run.key_results), results, run.id),
                )
            ]
        )

    def add_corrections(self, run: Run, corrections: Iterable[Correction]) -> None:
        """Store corrections and the run's metadata that counts them, in one commit."""
        self._write(
            [
                *(
                    (
                        "INSERT INTO corrections (run_id, n, body) VALUES (?, ?, ?)",
                        (run.id, c.n, c.model_dump_json()),
                    )
                    for c in corrections
                ),
                ("UPDATE runs SET run = ? WHERE id = ?", (run.model_dump_json(), run.id)),
            ]
        )

    def corrections(self, run_id: str) -> list[Correction]:
        """The run's corrections in order (none: an empty list)."""
        rows = self._db.execute(
            "SELECT body FROM corrections WHERE run_id = ? ORDER BY n", (run_id,)
        ).fetchall()
        return [Correction.model_validate_json(row[0]) for row in rows]

    def corrected_runs(self) -> dict[str, int]:
        """Run id -> its count of corrections, for every run that has any."""
        rows = self._db.execute("SELECT run_id, COUNT(*) FROM corrections GROUP BY run_id")
        return {str(r[0]): int(r[1]) for r in rows.fetchall()}

    def results(self, run_id: str) -> str | None:
        row = self._db.execute("SELECT results FROM runs WHERE id = ?", (run_id,)).fetchone()
        if row is None:
            raise RunNotFound(f"no run with id {run_id}")
        return None if row[0] is None else str(row[0])

    def mark_final(self, run_id: str) -> None:
        """The run file is final and fsynced: drop the run's payloads, keep the receipts."""
        self._write([("UPDATE runs SET file_final = 1 WHERE id = ?", (run_id,))])
        self.drop_payloads(run_id)

    def drop_payloads(self, run_id: str) -> None:
        self._payloads.drop(run_id)

    def final_runs_with_payloads(self) -> list[str]:
        """Runs whose payload file outlived their final run file (a crash in between)."""
        names = self._payloads.stored()
        final = {
            row[0]
            for row in self._db.execute("SELECT id FROM runs WHERE file_final = 1").fetchall()
        }
        return [n for n in names if n in final]

    # --- batches ----------------------------------------------------------------------

    def stored_batch(self, run_id: str, seq: int) -> StoredBatch | None:
        row = self._db.execute(
            "SELECT grp, rows, group_rows, digest FROM batches WHERE run_id = ? AND seq = ?",
            (run_id, seq),
        ).fetchone()
        return None if row is None else StoredBatch(row[0], row[1], row[2], bytes(row[3]))

    def stored_batches(self, run_id: str) -> list[tuple[int, StoredBatch]]:
        """Every batch of the run as (seq, what is remembered of it), in the order stored."""
        rows = self._db.execute(
            "SELECT seq, grp, rows, group_rows, digest FROM batches WHERE run_id = ? ORDER BY n",
            (run_id,),
        ).fetchall()
        return [(r[0], StoredBatch(r[1], r[2], r[3], bytes(r[4]))) for r in rows]

    def key_of(self, run_id: str) -> str | None:
        """The Idempotency-Key the run was opened with, if any."""
        row = self._db.execute("SELECT key FROM run_keys WHERE run_id = ?", (run_id,)).fetchone()
        return None if row is None else str(row[0])

    def max_seq(self, run_id: str) -> int:
        """The largest seq stored for the run (-1 if none)."""
        row = self._db.execute("SELECT MAX(seq) FROM batches WHERE run_id = ?", (run_id,))
        found = row.fetchone()[0]
        return -1 if found is None else int(found)

    def begin(self) -> None:
        """Open the transaction of a group of batches (:meth:`add_batch`, :meth:`set_counters`)."""
        self._db.execute("BEGIN IMMEDIATE")

    @property
    def in_transaction(self) -> bool:
        return self._db.in_transaction

    def commit(self) -> None:
        dirty, self._dirty = self._dirty, set()
        if self._full:
            for run_id in dirty:
                self._payloads.sync(run_id)
        self._db.execute("COMMIT")

    def rollback(self) -> None:
        """Roll back the open transaction, if SQLite has not done so itself (it does on
        SQLITE_FULL and some I/O errors)."""
        self._dirty.clear()
        if self._db.in_transaction:
            self._db.execute("ROLLBACK")

    def add_batch(
        self,
        run_id: str,
        seq: int,
        batch: Batch,
        group_rows: int,
        payload: Payload | None = None,
    ) -> StoredBatch | tuple[int, int]:
        """Add a batch to the transaction opened by :meth:`begin`; its readings
        (``payload``: :func:`payload_of`, made before the caller's lock, or made here) are
        appended to the run's payload file.

        Returns where they are in it (``at``, ``size``), or the batch stored before under
        ``seq`` (then nothing changes).
        """
        if not self._db.in_transaction:  # e.g. SQLite rolled the group back after a failure
            raise sqlite3.OperationalError("a batch is added inside a transaction only")
        if payload is None:
            payload = payload_of(batch)
        size = payload.size
        at = self._payloads.end(run_id, size, committed=lambda: self._committed_end(run_id))
        try:
            self._db.execute(
                "INSERT INTO batches (run_id, seq, grp, rows, group_rows, digest, at, size) "
                "VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (run_id, seq, batch.group, batch.rows, group_rows, batch.digest, at, size),
            )
        except sqlite3.IntegrityError:
            stored = self.stored_batch(run_id, seq)
            if stored is None:  # not the (run_id, seq) taken
                raise
            return stored
        self._dirty.add(run_id)
        self._payloads.append(run_id, payload)
        return at, size

    def _committed_end(self, run_id: str) -> int:
        """The end of the run's last committed batch in its payload file (0 if none)."""
        row = self._db.execute(
            "SELECT COALESCE(MAX(at + size), 0) FROM batches WHERE run_id = ?", (run_id,)
        ).fetchone()
        return int(row[0])

    def set_counters(self, runs: Iterable[Run]) -> None:
        """The runs' batch counts and rows per group, in the transaction of their batches."""
        self._db.executemany(
            "UPDATE runs SET batches = ?, rows = ? WHERE id = ?",
            ((run.batches, json.dumps(run.rows), run.id) for run in runs),
        )

    def payloads(self, run_id: str) -> Iterator[tuple[str, dict[str, NDArray[np.float64]]]]:
        """The run's batches in the order stored, as (group, columns as posted)."""
        order = self._db.execute(
            "SELECT grp, at, size FROM batches WHERE run_id = ? ORDER BY n", (run_id,)
        ).fetchall()
        if not order:
            return
        places = [(at, size) for _, at, size in order]
        for (group, _, _), data in zip(order, self._payloads.read(run_id, places), strict=True):
            yield group, decode(data)

    def payload_pieces(
        self, run_id: str, at: int, size: int, rows: int, first: int | None = None
    ) -> Iterator[dict[str, NDArray[np.float64]]]:
        """The columns of the run's batch at (``at``, ``size``) (``add_batch``'s place), in
        pieces of ``first`` rows, then ``rows`` (:meth:`PayloadFiles.pieces`)."""
        return self._payloads.pieces(run_id, at, size, rows, first)


def payload_of(batch: Batch) -> Payload:
    """The batch's readings as its run's payload file takes them (a large batch already in
    the aligned memory a direct write takes: the copy costs no time under a lock)."""
    return aligned(encode(batch.columns))


class _Checkpointer:
    """A thread that checkpoints the WAL into the database every second, without blocking
    the writer (PASSIVE), on a connection of its own."""

    def __init__(self, path: Path) -> None:
        self._db = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="rig-checkpoint", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        try:
            while not self._stop.wait(CHECKPOINT_SECONDS):
                try:
                    self._db.execute("PRAGMA wal_checkpoint(PASSIVE)")
                except sqlite3.Error as exc:  # e.g. the disk is full: the next one may pass
                    log.warning("checkpointing the journal failed: %s", exc)
        finally:
            self._db.close()

    def stop(self) -> None:
        self._stop.set()
        self._thread.join()
