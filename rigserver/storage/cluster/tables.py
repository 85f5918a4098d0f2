"""The cluster's small stores beside the runs (the series, the students' words, their
sketches): the :class:`~rigserver.storage._tables.Database` they are written for, on the
cluster's PostgreSQL."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import Any

import psycopg
import psycopg_pool

from rigserver.storage._failures import failures_as
from rigserver.storage._tables import Connection, Rows, taken_when
from rigserver.storage.cluster.postgres import PG_FAILURES


class PostgresDatabase:
    """A pool of connections to ``url`` (autocommit, at most ``pool_size``), the tables of
    ``schema`` created; the database's failures raise ``StorageUnavailable``. A transaction
    locks the rows it reads ``FOR UPDATE``; the others wait for its commit."""

    for_update = " FOR UPDATE"

    def __init__(self, url: str, schema: str, what: str, pool_size: int) -> None:
        with failures_as(f"opening the {what} tables", PG_FAILURES):
            self._pool = psycopg_pool.ConnectionPool(
                url, min_size=1, max_size=pool_size, open=True, kwargs={"autocommit": True}
            )
            with self._pool.connection() as conn:
                conn.execute(schema)

    @contextmanager
    def connection(self, doing: str) -> Iterator[Connection]:
        with self._pooled(doing) as conn:
            yield _Qmarks(conn)

    @contextmanager
    def transaction(self, doing: str) -> Iterator[Connection]:
        with self._pooled(doing) as conn, conn.transaction():
            yield _Qmarks(conn)

    @contextmanager
    def _pooled(self, doing: str) -> Iterator[psycopg.Connection[Any]]:
        """A connection of the pool; the failures in the block translated (``doing``), a key
        stored already :class:`~rigserver.storage._tables.Taken`."""
        with (
            failures_as(doing, PG_FAILURES),
            taken_when(psycopg.errors.UniqueViolation, doing),
            self._pool.connection() as conn,
        ):
            yield conn

    def close(self) -> None:
        self._pool.close()


class _Qmarks:
    """A connection taking SQLite's ``?`` for a parameter (none of the SQL has another)."""

    def __init__(self, conn: psycopg.Connection[Any]) -> None:
        self._conn = conn

    def execute(self, sql: str, parameters: Sequence[Any] = (), /) -> Rows:
        return self._conn.execute(sql.replace("?", "%s"), parameters)
