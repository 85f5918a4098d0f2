"""The students' sketches on runs (:class:`~schemas.sketches.Sketch`), every version kept:
the image as uploaded, who uploaded it (the API key's name) and when.

Like the students' words (:mod:`.notes`) they live beside the runs, not in a run's file
(which keeps what the stand measured): ``sketches.sqlite`` in the data directory (WAL mode),
or in memory for tests; a cluster keeps them in its PostgreSQL database
(:mod:`.cluster.sketches_postgres`). One table::

    sketches(run_id, item, version, image, media_type, width, height, sha256, author, written)

The latest version of an item is its sketch; a replaced one stays, readable by its version.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from datetime import datetime
from pathlib import Path
from typing import Any

from rigserver.storage._tables import Connection, Database, SqliteDatabase, retried
from rigserver.storage._time import as_utc, iso, now
from schemas.sketches import Sketch

_SCHEMA = """
CREATE TABLE IF NOT EXISTS sketches (
    run_id TEXT NOT NULL,
    item INTEGER NOT NULL,
    version INTEGER NOT NULL,
    image BLOB NOT NULL,
    media_type TEXT NOT NULL,
    width INTEGER NOT NULL,
    height INTEGER NOT NULL,
    sha256 TEXT NOT NULL,
    author TEXT NOT NULL,
    written TEXT NOT NULL,
    PRIMARY KEY (run_id, item, version)
);
"""
#: The columns of a sketch's record (:func:`sketch_of`), after ``item, version``.
COLUMNS = "item, version, media_type, width, height, length(image), sha256, author, written"


class SketchStore:
    """The sketches in the table ``table`` of a :class:`Database`."""

    def __init__(self, database: Database, table: str) -> None:
        self._database = database
        self._table = table

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
        """Store a new version of the sketch of ``item`` (``size``: width, height in
        pixels), uploaded by ``by``."""
        written, digest = iso(now()), hashlib.sha256(image).hexdigest()

        def write(db: Connection) -> int:
            (last,) = db.execute(
                f"SELECT COALESCE(MAX(version), 0) FROM {self._table} "
                "WHERE run_id = ? AND item = ?",
                (run_id, item),
            ).fetchone()
            db.execute(
                f"INSERT INTO {self._table} VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (run_id, item, last + 1, image, media_type, *size, digest, by, written),
            )
            return int(last) + 1

        version = retried(self._database, f"storing a sketch of run {run_id}", write)
        return sketch_of((item, version, media_type, *size, len(image), digest, by, written))

    def latest(self, run_id: str) -> list[Sketch]:
        """The latest version of each item's sketch, by item."""
        with self._database.connection(f"reading the sketches of run {run_id}") as db:
            rows = db.execute(
                f"SELECT {COLUMNS} FROM {self._table} s WHERE run_id = ? AND version = "
                f"(SELECT MAX(version) FROM {self._table} "
                "WHERE run_id = s.run_id AND item = s.item) ORDER BY item",
                (run_id,),
            ).fetchall()
        return [sketch_of(row) for row in rows]

    def history(self, run_id: str) -> list[Sketch]:
        """Every version of every item's sketch, by item, the first first."""
        with self._database.connection(f"reading the sketches of run {run_id}") as db:
            rows = db.execute(
                f"SELECT {COLUMNS} FROM {self._table} WHERE run_id = ? ORDER BY item, version",
                (run_id,),
            ).fetchall()
        return [sketch_of(row) for row in rows]

    def image(
        self, run_id: str, item: int, version: int | None = None
    ) -> tuple[Sketch, bytes] | None:
        """A version of the item's sketch and its image (the latest without ``version``);
        None if there is none."""
        which = "" if version is None else " AND version = ?"
        with self._database.connection(f"reading a sketch of run {run_id}") as db:
            row = db.execute(
                f"SELECT {COLUMNS}, image FROM {self._table} WHERE run_id = ? AND item = ?"
                f"{which} ORDER BY version DESC LIMIT 1",
                (run_id, item) if version is None else (run_id, item, version),
            ).fetchone()
        return None if row is None else (sketch_of(row[:-1]), bytes(row[-1]))

    def close(self) -> None:
        self._database.close()


class SqliteSketches(SketchStore):
    """The sketches in one SQLite database (``path``), or in memory (``":memory:"``)."""

    def __init__(self, path: Path | str) -> None:
        super().__init__(SqliteDatabase(path, _SCHEMA, "sketches"), "sketches")


def sketch_of(row: Sequence[Any]) -> Sketch:
    """The record of a row of :data:`COLUMNS`."""
    item, version, media_type, width, height, size, digest, by, written = row
    return Sketch(
        item=item,
        version=version,
        media_type=media_type,
        width=width,
        height=height,
        size=size,
        sha256=digest,
        by=by,
        written=as_utc(datetime.fromisoformat(written)),
    )
