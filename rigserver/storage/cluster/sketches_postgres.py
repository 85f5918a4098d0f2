"""The students' sketches in the cluster's PostgreSQL database, for every worker alike: the
table of :mod:`rigserver.storage.sketches` (``rig_sketches``, the image ``bytea``)."""

from __future__ import annotations

import hashlib

import psycopg

from rigserver.storage._failures import failures_as
from rigserver.storage._time import iso, now
from rigserver.storage.cluster.postgres import PG_FAILURES
from rigserver.storage.cluster.tables import postgres_tables
from rigserver.storage.sketches import COLUMNS, latest_query, sketch_of
from schemas.sketches import Sketch

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
#: Uploads of one item's sketch, from any worker, that met another's version: tried again.
_RETRIES = 5


class PostgresSketches:
    """The :class:`~rigserver.storage.sketches.SketchStore` on PostgreSQL (``url``)."""

    def __init__(self, url: str, *, pool_size: int = 2) -> None:
        self._pool = postgres_tables(url, _SCHEMA, "sketches", pool_size)

    def put(
        self,
        run_id: str,
        item: int,
        image: bytes,
        *,
        media_type: str,
        size: tuple[int, int],
        by: str,
    ) -> Sketch:
        written, digest = iso(now()), hashlib.sha256(image).hexdigest()
        record = (run_id, item, image, media_type, *size, digest, by, written)
        with failures_as(f"storing a sketch of run {run_id}", PG_FAILURES):
            for attempt in range(_RETRIES):
                try:
                    with self._pool.connection() as conn:
                        row = conn.execute(
                            "INSERT INTO rig_sketches SELECT %s, %s, "
                            "COALESCE(MAX(version), 0) + 1, %s, %s, %s, %s, %s, %s, %s "
                            "FROM rig_sketches WHERE run_id = %s AND item = %s RETURNING version",
                            (*record, run_id, item),
                        ).fetchone()
                    break
                except psycopg.errors.UniqueViolation:
                    if attempt == _RETRIES - 1:
                        raise
        assert row is not None
        return sketch_of((item, row[0], media_type, *size, len(image), digest, by, written))

    def latest(self, run_id: str) -> list[Sketch]:
        with (
            failures_as(f"reading the sketches of run {run_id}", PG_FAILURES),
            self._pool.connection() as conn,
        ):
            rows = conn.execute(latest_query("rig_sketches", "%s", _COLUMNS), (run_id,)).fetchall()
        return [sketch_of(row) for row in rows]

    def history(self, run_id: str) -> list[Sketch]:
        with (
            failures_as(f"reading the sketches of run {run_id}", PG_FAILURES),
            self._pool.connection() as conn,
        ):
            rows = conn.execute(
                f"SELECT {_COLUMNS} FROM rig_sketches WHERE run_id = %s ORDER BY item, version",
                (run_id,),
            ).fetchall()
        return [sketch_of(row) for row in rows]

    def image(
        self, run_id: str, item: int, version: int | None = None
    ) -> tuple[Sketch, bytes] | None:
        which = "" if version is None else " AND version = %s"
        with (
            failures_as(f"reading a sketch of run {run_id}", PG_FAILURES),
            self._pool.connection() as conn,
        ):
            row = conn.execute(
                f"SELECT {_COLUMNS}, image FROM rig_sketches WHERE run_id = %s AND item = %s"
                f"{which} ORDER BY version DESC LIMIT 1",
                (run_id, item) if version is None else (run_id, item, version),
            ).fetchone()
        return None if row is None else (sketch_of(row[:-1]), bytes(row[-1]))

    def close(self) -> None:
        self._pool.close()


#: :data:`~rigserver.storage.sketches.COLUMNS` in PostgreSQL's words.
_COLUMNS = COLUMNS.replace("length(", "octet_length(")
