"""The student's own words on runs (:class:`~schemas.student_notes.StudentNotes`), every
version kept: who wrote it (the API key's name) and when.

The run stores keep what a stand measured and never change a run's metadata afterwards, so
the words live in a small store of their own beside the series: ``notes.sqlite`` in the data
directory (WAL mode), or in memory for tests; a cluster keeps them in its PostgreSQL
database (:mod:`.notes_postgres`). One table::

    notes(run_id, version, body, author, written)   body: the words as JSON; version 1, 2, ...

The latest version of a run is its words; the older ones are its history.
"""

from __future__ import annotations

from collections.abc import Sequence
from datetime import datetime
from pathlib import Path
from typing import Any

from rigserver.storage._tables import Connection, Database, SqliteDatabase, retried
from rigserver.storage._time import as_utc, iso, now
from schemas.student_notes import StudentNotes, StudentNotesWrite

_SCHEMA = """
CREATE TABLE IF NOT EXISTS notes (
    run_id TEXT NOT NULL,
    version INTEGER NOT NULL,
    body TEXT NOT NULL,
    author TEXT NOT NULL,
    written TEXT NOT NULL,
    PRIMARY KEY (run_id, version)
);
"""


class NotesStore:
    """The words in the table ``table`` of a :class:`Database`."""

    def __init__(self, database: Database, table: str) -> None:
        self._database = database
        self._table = table

    def get(self, run_id: str) -> StudentNotes:
        """The run's words as last written (empty, version 0, if never)."""
        last = self._versions(run_id, "version DESC LIMIT 1")
        return last[0] if last else StudentNotes()

    def put(self, run_id: str, notes: StudentNotesWrite, *, by: str) -> StudentNotes:
        """Store a new version of the run's words, written by ``by``."""
        body, written = notes.model_dump_json(), iso(now())

        def write(db: Connection) -> int:
            (last,) = db.execute(
                f"SELECT COALESCE(MAX(version), 0) FROM {self._table} WHERE run_id = ?",
                (run_id,),
            ).fetchone()
            db.execute(
                f"INSERT INTO {self._table} VALUES (?, ?, ?, ?, ?)",
                (run_id, last + 1, body, by, written),
            )
            return int(last) + 1

        version = retried(self._database, f"storing the notes of run {run_id}", write)
        return notes_of((version, body, by, written))

    def history(self, run_id: str) -> list[StudentNotes]:
        """Every version of the run's words, the first first."""
        return self._versions(run_id, "version")

    def close(self) -> None:
        self._database.close()

    def _versions(self, run_id: str, order: str) -> list[StudentNotes]:
        """The run's versions in the ``ORDER BY`` clause ``order``."""
        with self._database.connection(f"reading the notes of run {run_id}") as db:
            rows = db.execute(
                f"SELECT version, body, author, written FROM {self._table} WHERE run_id = ? "
                f"ORDER BY {order}",
                (run_id,),
            ).fetchall()
        return [notes_of(row) for row in rows]


class SqliteNotes(NotesStore):
    """The words in one SQLite database (``path``), or in memory (``":memory:"``)."""

    def __init__(self, path: Path | str) -> None:
        super().__init__(SqliteDatabase(path, _SCHEMA, "notes"), "notes")


def notes_of(row: Sequence[Any]) -> StudentNotes:
    """The words of a row ``(version, body, author, written)``."""
    version, body, by, written = row
    words = StudentNotesWrite.model_validate_json(body)
    return StudentNotes(
        **words.model_dump(),
        version=version,
        by=by,
        written=as_utc(datetime.fromisoformat(written)),
    )
