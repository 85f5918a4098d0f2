"""The journal: one SQLite database (WAL mode) holding the run catalogue and the batches.

Tables::

    meta(key, value)            "clean_shutdown": "1" after HDF5Store.close(), "0" while open
    runs(id, stand, operator, state, created, ended, run, batches, rows, key_results,
         results, file_final)   the catalogue: filters are columns, ``run`` the full Run JSON,
                                ``file_final`` 1 once the run file is final and fsynced
    batches(n, run_id, seq, grp, rows, group_rows, digest)
                                every batch ever stored, in order (n); kept for ever, so a
                                retried seq gets its first receipt
    payloads(n, data)           the readings of a batch until its run file is final: the
                                columns as raw little-endian float64 (see _encode)

A batch is durable once its transaction commits. In WAL mode ``synchronous=NORMAL`` makes a
commit survive the process being killed (kill -9, a crash of Python or of the library):
the WAL is written before COMMIT returns, only its fsync waits for the next checkpoint.
``synchronous=FULL`` fsyncs the WAL at every commit, so a commit also survives a power
loss or a kernel crash, at the price of one fsync per batch.
"""

from __future__ import annotations

import json
import sqlite3
import struct
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from rigserver.storage._checks import Batch, StoredBatch
from rigserver.storage._time import iso
from rigserver.storage.errors import RunExists, RunNotFound, StorageUnavailable
from schemas.runs import Run, RunPage, RunQuery

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
CREATE TABLE IF NOT EXISTS batches (
    n INTEGER PRIMARY KEY,
    run_id TEXT NOT NULL,
    seq INTEGER NOT NULL,
    grp TEXT NOT NULL,
    rows INTEGER NOT NULL,
    group_rows INTEGER NOT NULL,
    digest BLOB NOT NULL,
    UNIQUE (run_id, seq)
);
CREATE TABLE IF NOT EXISTS payloads (n INTEGER PRIMARY KEY, data BLOB NOT NULL);
"""

_HEADER = struct.Struct("<I")
_COLUMN = struct.Struct("<HQ")


def _encode(columns: dict[str, NDArray[np.float64]]) -> bytes:
    """Channel count, then (name length, row count, name) per channel, then the values."""
    head = [_HEADER.pack(len(columns))]
    for name, values in columns.items():
        raw = name.encode()
        head.append(_COLUMN.pack(len(raw), len(values)) + raw)
    return b"".join([*head, *(v.data for v in columns.values())])


def _decode(data: bytes) -> dict[str, NDArray[np.float64]]:
    (count,) = _HEADER.unpack_from(data, 0)
    at = _HEADER.size
    names: list[tuple[str, int]] = []
    for _ in range(count):
        size, rows = _COLUMN.unpack_from(data, at)
        at += _COLUMN.size
        names.append((data[at : at + size].decode(), rows))
        at += size
    out: dict[str, NDArray[np.float64]] = {}
    for name, rows in names:
        out[name] = np.frombuffer(data, dtype="<f8", count=rows, offset=at)
        at += 8 * rows
    return out


@dataclass(frozen=True, slots=True)
class CatalogueEntry:
    """A run as the catalogue has it, with whether its run file is final."""

    run: Run
    file_final: bool


class Journal:
    """The catalogue and the batches; not thread-safe (the store serialises the calls).

    Every method commits its own transaction; a failure rolls it back and raises the
    sqlite3 error (the store translates it).
    """

    def __init__(self, path: Path, *, synchronous: Synchronous = "normal") -> None:
        self.path = path
        self._db = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
        try:
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute(f"PRAGMA synchronous={synchronous.upper()}")
            self._db.execute("PRAGMA journal_size_limit=67108864")
            # Debian's SQLite zeroes freed pages; dropping a finished run's readings would
            # then rewrite them all (seconds for a 50-million-reading run)
            self._db.execute("PRAGMA secure_delete=OFF")
            self._db.executescript(_SCHEMA)
        except BaseException:
            self._db.close()
            raise

    def close(self) -> None:
        self._db.close()

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

    def insert_run(self, run: Run, *, file_final: bool = False, results: str | None = None) -> None:
        """A new catalogue entry; ``RunExists`` if the id is taken."""
        try:
            self._write(
                [
                    (
                        "INSERT INTO runs (id, stand, operator, state, created, ended, run, "
                        "batches, rows, key_results, results, file_final) "
                        "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                        (
                            run.id,
                            run.stand.value,
                            run.operator,
                            run.state.value,
                            iso(run.created),
                            None if run.ended is None else iso(run.ended),
                            run.model_dump_json(),
                            run.batches,
                            json.dumps(run.rows),
                            json.dumps(run.key_results),
                            results,
                            int(file_final),
                        ),
                    )
                ]
            )
        except sqlite3.IntegrityError as exc:
            raise RunExists(f"a run with id {run.id} is stored already") from exc

    _RUN_COLUMNS = "run, batches, rows, file_final"

    @staticmethod
    def _entry(row: tuple[str, int, str, int]) -> CatalogueEntry:
        run = Run.model_validate_json(row[0])
        run = run.model_copy(update={"batches": row[1], "rows": json.loads(row[2])})
        return CatalogueEntry(run=run, file_final=bool(row[3]))

    def entry(self, run_id: str) -> CatalogueEntry:
        """The run's catalogue entry; ``RunNotFound``."""
        row = self._db.execute(
            f"SELECT {self._RUN_COLUMNS} FROM runs WHERE id = ?", (run_id,)
        ).fetchone()
        if row is None:
            raise RunNotFound(f"no run with id {run_id}")
        return self._entry(row)

    def unfinished(self) -> list[CatalogueEntry]:
        """Runs whose file is not final: the open ones and any whose end did not complete."""
        rows = self._db.execute(
            f"SELECT {self._RUN_COLUMNS} FROM runs WHERE file_final = 0 ORDER BY created"
        ).fetchall()
        return [self._entry(r) for r in rows]

    def list_runs(self, query: RunQuery) -> RunPage:
        """Runs matching ``query`` (``since <= created < until``), newest first."""
        where: list[str] = []
        params: list[object] = []
        for column, value in (
            ("stand", query.stand),
            ("operator", query.operator),
            ("state", query.state),
        ):
            if value is not None:
                where.append(f"{column} = ?")
                params.append(str(value))
        if query.since is not None:
            where.append("created >= ?")
            params.append(iso(query.since))
        if query.until is not None:
            where.append("created < ?")
            params.append(iso(query.until))
        sql_where = f" WHERE {' AND '.join(where)}" if where else ""
        total = self._db.execute(f"SELECT COUNT(*) FROM runs{sql_where}", params).fetchone()[0]
        rows = self._db.execute(
            f"SELECT {self._RUN_COLUMNS} FROM runs{sql_where} "
            "ORDER BY created DESC, id DESC LIMIT ? OFFSET ?",
            [*params, query.limit, query.offset],
        ).fetchall()
        return RunPage(total=total, runs=[self._entry(r).run for r in rows])

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

    def results(self, run_id: str) -> str | None:
        row = self._db.execute("SELECT results FROM runs WHERE id = ?", (run_id,)).fetchone()
        if row is None:
            raise RunNotFound(f"no run with id {run_id}")
        return None if row[0] is None else str(row[0])

    def mark_final(self, run_id: str) -> None:
        """The run file is final and fsynced: drop the run's payloads, keep the receipts."""
        self._write(
            [
                (
                    "DELETE FROM payloads WHERE n IN (SELECT n FROM batches WHERE run_id = ?)",
                    (run_id,),
                ),
                ("UPDATE runs SET file_final = 1 WHERE id = ?", (run_id,)),
            ]
        )

    # --- batches ----------------------------------------------------------------------

    def stored_batch(self, run_id: str, seq: int) -> StoredBatch | None:
        row = self._db.execute(
            "SELECT grp, rows, group_rows, digest FROM batches WHERE run_id = ? AND seq = ?",
            (run_id, seq),
        ).fetchone()
        return None if row is None else StoredBatch(row[0], row[1], row[2], bytes(row[3]))

    def add_batch(
        self, run: Run, seq: int, batch: Batch, group_rows: int, rows: dict[str, int]
    ) -> StoredBatch | None:
        """Store a batch and the run's new counters (``rows`` per group) in one commit.

        Returns ``None``, or the batch stored before under ``seq`` (then nothing changes).
        """
        db = self._db
        db.execute("BEGIN IMMEDIATE")
        try:
            try:
                n = db.execute(
                    "INSERT INTO batches (run_id, seq, grp, rows, group_rows, digest) "
                    "VALUES (?, ?, ?, ?, ?, ?)",
                    (run.id, seq, batch.group, batch.rows, group_rows, batch.digest),
                ).lastrowid
            except sqlite3.IntegrityError:
                db.execute("ROLLBACK")
                return self.stored_batch(run.id, seq)
            db.execute("INSERT INTO payloads (n, data) VALUES (?, ?)", (n, _encode(batch.columns)))
            db.execute(
                "UPDATE runs SET batches = batches + 1, rows = ? WHERE id = ?",
                (json.dumps(rows), run.id),
            )
            db.execute("COMMIT")
        except BaseException:
            if db.in_transaction:
                db.execute("ROLLBACK")
            raise
        return None

    def payloads(self, run_id: str) -> Iterator[tuple[str, dict[str, NDArray[np.float64]]]]:
        """The run's batches in the order stored, as (group, columns as posted)."""
        order = self._db.execute(
            "SELECT n, grp FROM batches WHERE run_id = ? ORDER BY n", (run_id,)
        ).fetchall()
        for n, group in order:
            row = self._db.execute("SELECT data FROM payloads WHERE n = ?", (n,)).fetchone()
            if row is None:
                raise StorageUnavailable(
                    f"the readings of batch {n} of run {run_id} are no longer in the journal"
                )
            yield group, _decode(row[0])
