"""The cluster's small stores beside the runs (the students' words, their sketches) opened
alike: a pool of PostgreSQL connections, their tables created."""

from __future__ import annotations

import psycopg_pool

from rigserver.storage._failures import failures_as
from rigserver.storage.cluster.postgres import PG_FAILURES


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
