"""Series of runs: which runs a series groups, at which level of its factor.

A series holds references to runs, not readings, so it keeps its own small SQLite database
(WAL mode) beside the journal: ``series.sqlite`` in the data directory, or in memory for
tests. Tables::

    series(id, name, purpose, factor, notes, created)
    members(series_id, run_id, level, added, n)   n orders the runs as they joined

A run may belong to several series; that it exists, and that it is of the series' stand, is
the API's to check (the run store knows the runs).
"""

from __future__ import annotations

import sqlite3
import threading
from datetime import datetime
from pathlib import Path
from typing import Protocol

from rigserver.storage._time import as_utc, iso, now
from rigserver.storage.errors import (
    MemberExists,
    MemberNotFound,
    SeriesNotFound,
    StorageUnavailable,
)
from schemas.series import Series, SeriesCreate, SeriesMember, new_series_id

_SCHEMA = """
CREATE TABLE IF NOT EXISTS series (
    id TEXT PRIMARY KEY,
    name TEXT NOT NULL,
    purpose TEXT NOT NULL,
    factor TEXT,
    notes TEXT NOT NULL,
    created TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS members (
    n INTEGER PRIMARY KEY AUTOINCREMENT,
    series_id TEXT NOT NULL REFERENCES series(id),
    run_id TEXT NOT NULL,
    level TEXT,
    added TEXT NOT NULL,
    UNIQUE (series_id, run_id)
);
"""


class SeriesStore(Protocol):
    def create(self, body: SeriesCreate) -> Series:
        """Store a new, empty series."""
        ...

    def get(self, series_id: str) -> Series:
        """The series and its members; raises ``SeriesNotFound``."""
        ...

    def list(self) -> list[Series]:
        """Every series, newest first."""
        ...

    def add(self, series_id: str, run_id: str, level: str | None) -> Series:
        """Add a run (``MemberExists`` if it is a member already)."""
        ...

    def remove(self, series_id: str, run_id: str) -> Series:
        """Take a run out (``MemberNotFound`` if it is not a member)."""
        ...

    def close(self) -> None: ...


class SqliteSeries:
    """The series in one SQLite database (``path``), or in memory (``":memory:"``)."""

    def __init__(self, path: Path | str) -> None:
        try:
            self._db = sqlite3.connect(str(path), isolation_level=None, check_same_thread=False)
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute("PRAGMA foreign_keys=ON")
            self._db.executescript(_SCHEMA)
        except sqlite3.Error as exc:
            raise StorageUnavailable(f"cannot open the series database: {exc}") from exc
        self._lock = threading.Lock()

    def create(self, body: SeriesCreate) -> Series:
        series = Series(
            id=new_series_id(),
            name=body.name,
            purpose=body.purpose,
            factor=body.factor,
            notes=body.notes,
            created=now(),
        )
        with self._lock, self._db:
            self._db.execute(
                "INSERT INTO series VALUES (?, ?, ?, ?, ?, ?)",
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
        with self._lock:
            return self._get(series_id)

    def list(self) -> list[Series]:
        with self._lock:
            ids = [r[0] for r in self._db.execute("SELECT id FROM series ORDER BY created DESC")]
            return [self._get(i) for i in ids]

    def add(self, series_id: str, run_id: str, level: str | None) -> Series:
        with self._lock:
            self._get(series_id)
            try:
                with self._db:
                    self._db.execute(
                        "INSERT INTO members (series_id, run_id, level, added) VALUES (?, ?, ?, ?)",
                        (series_id, run_id, level, iso(now())),
                    )
            except sqlite3.IntegrityError:
                raise MemberExists(f"run {run_id} is in series {series_id} already") from None
            return self._get(series_id)

    def remove(self, series_id: str, run_id: str) -> Series:
        with self._lock:
            self._get(series_id)
            with self._db:
                gone = self._db.execute(
                    "DELETE FROM members WHERE series_id = ? AND run_id = ?", (series_id, run_id)
                ).rowcount
            if not gone:
                raise MemberNotFound(f"run {run_id} is not in series {series_id}")
            return self._get(series_id)

    def close(self) -> None:
        with self._lock:
            self._db.close()

    def _get(self, series_id: str) -> Series:
        row = self._db.execute(
            "SELECT id, name, purpose, factor, notes, created FROM series WHERE id = ?",
            (series_id,),
        ).fetchone()
        if row is None:
            raise SeriesNotFound(f"no series {series_id}")
        members = [
            SeriesMember(run_id=run_id, level=level, added=as_utc(datetime.fromisoformat(added)))
            for run_id, level, added in self._db.execute(
                "SELECT run_id, level, added FROM members WHERE series_id = ? ORDER BY n",
                (series_id,),
            )
        ]
        return Series(
            id=row[0],
            name=row[1],
            purpose=row[2],
            factor=row[3],
            notes=row[4],
            created=as_utc(datetime.fromisoformat(row[5])),
            members=members,
        )
