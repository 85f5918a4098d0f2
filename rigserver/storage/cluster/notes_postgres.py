"""The student's own words in the cluster's PostgreSQL database, for every worker alike: the
table of :mod:`rigserver.storage.notes` (``rig_notes``)."""

from __future__ import annotations

import psycopg

from rigserver.storage._failures import failures_as
from rigserver.storage._time import iso, now
from rigserver.storage.cluster.postgres import PG_FAILURES
from rigserver.storage.cluster.tables import postgres_tables
from rigserver.storage.notes import notes_of
from schemas.student_notes import StudentNotes, StudentNotesWrite

_SCHEMA = """
CREATE TABLE IF NOT EXISTS rig_notes (
    run_id TEXT NOT NULL,
    version BIGINT NOT NULL,
    body TEXT NOT NULL,
    author TEXT NOT NULL,
    written TEXT NOT NULL,
    PRIMARY KEY (run_id, version)
);
"""
#: Writes of one run's words, from any worker, that met another's version: tried again.
_RETRIES = 5


class PostgresNotes:
    """The :class:`~rigserver.storage.notes.NotesStore` on PostgreSQL (``url``)."""

    def __init__(self, url: str, *, pool_size: int = 2) -> None:
        self._pool = postgres_tables(url, _SCHEMA, "notes", pool_size)

    def get(self, run_id: str) -> StudentNotes:
        with (
            failures_as(f"reading the notes of run {run_id}", PG_FAILURES),
            self._pool.connection() as conn,
        ):
            row = conn.execute(
                "SELECT version, body, author, written FROM rig_notes WHERE run_id = %s "
                "ORDER BY version DESC LIMIT 1",
                (run_id,),
            ).fetchone()
        return notes_of(row)

    def put(self, run_id: str, notes: StudentNotesWrite, *, by: str) -> StudentNotes:
        body, written = notes.model_dump_json(), iso(now())
        with failures_as(f"storing the notes of run {run_id}", PG_FAILURES):
            for attempt in range(_RETRIES):
                try:
                    with self._pool.connection() as conn:
                        row = conn.execute(
                            "INSERT INTO rig_notes SELECT %s, COALESCE(MAX(version), 0) + 1, "
                            "%s, %s, %s FROM rig_notes WHERE run_id = %s RETURNING version",
                            (run_id, body, by, written, run_id),
                        ).fetchone()
                    break
                except psycopg.errors.UniqueViolation:
                    if attempt == _RETRIES - 1:
                        raise
        assert row is not None
        return notes_of((row[0], body, by, written))

    def history(self, run_id: str) -> list[StudentNotes]:
        with (
            failures_as(f"reading the notes of run {run_id}", PG_FAILURES),
            self._pool.connection() as conn,
        ):
            rows = conn.execute(
                "SELECT version, body, author, written FROM rig_notes WHERE run_id = %s "
                "ORDER BY version",
                (run_id,),
            ).fetchall()
        return [notes_of(row) for row in rows]

    def close(self) -> None:
        self._pool.close()
