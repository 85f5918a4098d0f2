"""The small stores beside the runs (the students' words, their sketches) opened alike: a
SQLite database in WAL mode, or a pool of the cluster's PostgreSQL, its tables created."""

from __future__ import annotations

import sqlite3
from pathlib import Path

import psycopg_pool

from rigserver.storage._failures import failures_as
from rigserver.storage.errors import StorageUnavailable
from rigserver.storage.postgres import PG_FAILURES


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


def postgres_tables(
    url: str, schema: str, what: str, pool_size: int
) -> psycopg_pool.ConnectionPool:
    """A pool of connections to ``url`` (autocommit), the tables of ``schema`` created."""
    with failures_as(f"opening the {what} table", PG_FAILURES):
        pool = psycopg_pool.ConnectionPool(
            url, min_size=1, max_size=pool_size, open=True, kwargs={"autocommit": True}
        )
        with pool.connection() as conn:
            conn.execute(schema)
    return pool
