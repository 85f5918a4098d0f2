"""The small stores beside the runs (the students' words, their sketches) opened alike: a
SQLite database in WAL mode, its tables created (the cluster's: :mod:`.cluster.tables`)."""

from __future__ import annotations

import sqlite3
from pathlib import Path

from rigserver.storage.errors import StorageUnavailable


def sqlite_database(path: Path | str, schema: str, what: str) -> sqlite3.Connection:
    """The database at ``path`` (``":memory:"``: in memory) with the tables of ``schema``;
    :class:`StorageUnavailable` naming ``what`` if it cannot be opened."""
    try:
        db = sqlite3.connect(str(path), isolation_level=None, check_same_thread=False)
        db.execute("PRAGMA journal_mode=WAL")
        db.executescript(schema)
    except sqlite3.Error as exc:
        raise StorageUnavailable(f"cannot open the {what} database: {exc}") from exc
    return db
