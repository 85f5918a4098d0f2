"""The students' sketches in the cluster's PostgreSQL database, for every worker alike: the
table of :mod:`rigserver.storage.sketches` (``rig_sketches``, the image ``bytea``)."""

from __future__ import annotations

from rigserver.storage.cluster.tables import PostgresDatabase
from rigserver.storage.sketches import SketchStore

_SCHEMA = """
CREATE TABLE IF NOT EXISTS rig_sketches (
    run_id TEXT NOT NULL,
    item BIGINT NOT NULL,
    version BIGINT NOT NULL,
    image BYTEA NOT NULL,
    media_type TEXT NOT NULL,
    width BIGINT NOT NULL,
    height BIGINT NOT NULL,
    sha256 TEXT NOT NULL,
    author TEXT NOT NULL,
    written TEXT NOT NULL,
    PRIMARY KEY (run_id, item, version)
);
"""


class PostgresSketches(SketchStore):
    """The sketches on PostgreSQL (``url``): an upload that met another worker's version is
    tried again."""

    def __init__(self, url: str, *, pool_size: int = 2) -> None:
        super().__init__(PostgresDatabase(url, _SCHEMA, "sketches", pool_size), "rig_sketches")
