"""The student's own words in the cluster's PostgreSQL database, for every worker alike: the
table of :mod:`rigserver.storage.notes` (``rig_notes``)."""

from __future__ import annotations

from rigserver.storage.cluster.tables import PostgresDatabase
from rigserver.storage.notes import NotesStore

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


class PostgresNotes(NotesStore):
    """The words on PostgreSQL (``url``): a write that met another worker's version is
    tried again."""

    def __init__(self, url: str, *, pool_size: int = 2) -> None:
        super().__init__(PostgresDatabase(url, _SCHEMA, "notes", pool_size), "rig_notes")
