"""Series of runs in the cluster's PostgreSQL database, for every worker alike: the tables
of :mod:`rigserver.storage.series` (``rig_series``, ``rig_series_members``)."""

from __future__ import annotations

import psycopg
import psycopg_pool

from rigserver.storage._failures import failures_as
from rigserver.storage._time import iso, now
from rigserver.storage.cluster.postgres import PG_FAILURES
from rigserver.storage.errors import MemberExists, MemberNotFound, SeriesNotFound
from rigserver.storage.series import check_room, new_series, series_of
from schemas.series import SERIES_RUNS_LIMIT, Series, SeriesCreate

_SCHEMA = """
CREATE TABLE IF NOT EXISTS rig_series (
    id TEXT PRIMARY KEY,
    name TEXT NOT NULL,
    purpose TEXT NOT NULL,
    factor TEXT,
    notes TEXT NOT NULL,
    created TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS rig_series_members (
    n BIGSERIAL PRIMARY KEY,
    series_id TEXT NOT NULL REFERENCES rig_series(id),
    run_id TEXT NOT NULL,
    level TEXT,
    added TEXT NOT NULL,
    stand TEXT,
    UNIQUE (series_id, run_id)
);
ALTER TABLE rig_series_members ADD COLUMN IF NOT EXISTS stand TEXT;
"""


class PostgresSeries:
    """The :class:`~rigserver.storage.series.SeriesStore` on PostgreSQL (``url``)."""

    def __init__(self, url: str, *, pool_size: int = 2) -> None:
        with failures_as("opening the series tables", PG_FAILURES):
            self._pool = psycopg_pool.ConnectionPool(
                url, min_size=1, max_size=pool_size, open=True, kwargs={"autocommit": True}
            )
            with self._pool.connection() as conn:
                conn.execute(_SCHEMA)

    def create(self, body: SeriesCreate) -> Series:
        series = new_series(body)
        with failures_as("storing a series", PG_FAILURES), self._pool.connection() as conn:
            conn.execute(
                "INSERT INTO rig_series VALUES (%s, %s, %s, %s, %s, %s)",
                (
                    series.id,
                    series.name,
                    series.purpose.value,
                    series.factor,
                    series.notes,
                    iso(series.created),
                ),
            )
        return series

    def get(self, series_id: str) -> Series:
        with failures_as(f"reading series {series_id}", PG_FAILURES):
            return self._get(series_id)

    def list(self) -> list[Series]:
        with failures_as("listing the series", PG_FAILURES), self._pool.connection() as conn:
            ids = [r[0] for r in conn.execute("SELECT id FROM rig_series ORDER BY created DESC")]
        return [self.get(i) for i in ids]

    def add(
        self,
        series_id: str,
        run_id: str,
        level: str | None,
        *,
        stand: str,
        limit: int = SERIES_RUNS_LIMIT,
    ) -> Series:
        with failures_as(f"adding a run to series {series_id}", PG_FAILURES):
            try:
                with self._pool.connection() as conn, conn.transaction():
                    # the series' row locked: the adds to one series, from any worker, one
                    # at a time from here to the commit
                    found = conn.execute(
                        "SELECT 1 FROM rig_series WHERE id = %s FOR UPDATE", (series_id,)
                    ).fetchone()
                    if found is None:
                        raise SeriesNotFound(f"no series {series_id}")
                    row = conn.execute(
                        "SELECT COUNT(*) FROM rig_series_members WHERE series_id = %s",
                        (series_id,),
                    ).fetchone()
                    other = conn.execute(
                        "SELECT run_id, stand FROM rig_series_members WHERE series_id = %s "
                        "AND stand IS NOT NULL AND stand <> %s LIMIT 1",
                        (series_id, stand),
                    ).fetchone()
                    check_room(series_id, run_id, stand, row[0] if row else 0, other, limit)
                    conn.execute(
                        "INSERT INTO rig_series_members (series_id, run_id, level, added, stand) "
                        "VALUES (%s, %s, %s, %s, %s)",
                        (series_id, run_id, level, iso(now()), stand),
                    )
            except psycopg.errors.UniqueViolation:
                raise MemberExists(f"run {run_id} is in series {series_id} already") from None
            return self._get(series_id)

    def remove(self, series_id: str, run_id: str) -> Series:
        with failures_as(f"taking a run out of series {series_id}", PG_FAILURES):
            self._get(series_id)
            with self._pool.connection() as conn:
                gone = conn.execute(
                    "DELETE FROM rig_series_members WHERE series_id = %s AND run_id = %s",
                    (series_id, run_id),
                ).rowcount
            if not gone:
                raise MemberNotFound(f"run {run_id} is not in series {series_id}")
            return self._get(series_id)

    def close(self) -> None:
        self._pool.close()

    def _get(self, series_id: str) -> Series:
        with self._pool.connection() as conn:
            row = conn.execute(
                "SELECT id, name, purpose, factor, notes, created FROM rig_series WHERE id = %s",
                (series_id,),
            ).fetchone()
            members = conn.execute(
                "SELECT run_id, level, added FROM rig_series_members "
                "WHERE series_id = %s ORDER BY n",
                (series_id,),
            ).fetchall()
        return series_of(series_id, row, members)
