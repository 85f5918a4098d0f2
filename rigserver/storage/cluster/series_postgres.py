"""Series of runs in the cluster's PostgreSQL database, for every worker alike: the tables
of :mod:`rigserver.storage.series` (``rig_series``, ``rig_series_members``)."""

from __future__ import annotations

from rigserver.storage.cluster.tables import PostgresDatabase
from rigserver.storage.series import SeriesStore

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


class PostgresSeries(SeriesStore):
    """The series on PostgreSQL (``url``)."""

    def __init__(self, url: str, *, pool_size: int = 2) -> None:
        database = PostgresDatabase(url, _SCHEMA, "series", pool_size)
        super().__init__(database, series="rig_series", members="rig_series_members")
