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
import threading
from collections.abc import Sequence
from datetime import datetime
from pathlib import Path
from typing import Any, Protocol

from rigserver.storage._tables import sqlite_database
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


def latest_query(table: str, placeholder: str, columns: str = COLUMNS) -> str:
    """The query of the latest version of each item of a run (the run id its one
    ``placeholder``)."""
    return (
        f"SELECT {columns} FROM {table} s WHERE run_id = {placeholder} AND version = "
        f"(SELECT MAX(version) FROM {table} WHERE run_id = s.run_id AND item = s.item) "
        "ORDER BY item"
    )


class SketchStore(Protocol):
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
        ...

    def latest(self, run_id: str) -> list[Sketch]:
        """The latest version of each item's sketch, by item."""
        ...

    def history(self, run_id: str) -> list[Sketch]:
        """Every version of every item's sketch, by item, the first first."""
        ...

    def image(
        self, run_id: str, item: int, version: int | None = None
    ) -> tuple[Sketch, bytes] | None:
        """A version of the item's sketch and its image (the latest without ``version``);
        None if there is none."""
        ...

    def close(self) -> None: ...


class SqliteSketches:
    """The sketches in one SQLite database (``path``), or in memory (``":memory:"``)."""

    def __init__(self, path: Path | str) -> None:
        self._db = sqlite_database(path, _SCHEMA, "sketches")
        self._lock = threading.Lock()

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
        with self._lock:
            # IMMEDIATE: the write lock from the read of the last version to the insert
            self._db.execute("BEGIN IMMEDIATE")
            try:
                (last,) = self._db.execute(
                    "SELECT COALESCE(MAX(version), 0) FROM sketches WHERE run_id = ? AND item = ?",
                    (run_id, item),
                ).fetchone()
                self._db.execute(
                    "INSERT INTO sketches VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                    (run_id, item, last + 1, image, media_type, *size, digest, by, written),
                )
            except BaseException:
                self._db.execute("ROLLBACK")
                raise
            self._db.execute("COMMIT")
        return sketch_of((item, last + 1, media_type, *size, len(image), digest, by, written))

    def latest(self, run_id: str) -> list[Sketch]:
        with self._lock:
            rows = self._db.execute(latest_query("sketches", "?"), (run_id,)).fetchall()
        return [sketch_of(row) for row in rows]

    def history(self, run_id: str) -> list[Sketch]:
        with self._lock:
            rows = self._db.execute(
                f"SELECT {COLUMNS} FROM sketches WHERE run_id = ? ORDER BY item, version",
                (run_id,),
            ).fetchall()
        return [sketch_of(row) for row in rows]

    def image(
        self, run_id: str, item: int, version: int | None = None
    ) -> tuple[Sketch, bytes] | None:
        with self._lock:
            row = self._db.execute(
                f"SELECT {COLUMNS}, image FROM sketches WHERE run_id = ? AND item = ? "
                "AND (? IS NULL OR version = ?) ORDER BY version DESC LIMIT 1",
                (run_id, item, version, version),
            ).fetchone()
        return None if row is None else (sketch_of(row[:-1]), bytes(row[-1]))

    def close(self) -> None:
        with self._lock:
            self._db.close()


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
