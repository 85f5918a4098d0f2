"""Series of runs: which runs a series groups, at which level of its factor.

A series holds references to runs, not readings, so it keeps its own small SQLite database
(WAL mode) beside the journal: ``series.sqlite`` in the data directory, or in memory for
tests; a cluster keeps them in its PostgreSQL database (:mod:`.series_postgres`). Tables::

    series(id, name, purpose, factor, notes, created)
    members(series_id, run_id, level, added, n, stand)   n orders the runs as they joined

A run may belong to several series; that it exists is the API's to check (the run store
knows the runs), and the API names its stand. That a series holds runs of one stand, and
at most ``limit`` of them, is checked by :meth:`SeriesStore.add` in the transaction that
adds the run, so adds at once (threads of one server, or the workers of a cluster) never
mix two stands or pass the limit. A member stored by an older version has no stand (NULL):
the API checks the new run against such members' runs, whose stand never changes.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Sequence
from datetime import datetime
from pathlib import Path
from typing import Any

from rigserver.storage._tables import Connection, Database, SqliteDatabase, Taken
from rigserver.storage._time import as_utc, iso, now
from rigserver.storage.errors import (
    MemberExists,
    MemberNotFound,
    OtherStand,
    SeriesFull,
    SeriesNotFound,
)
from schemas.series import (
    SERIES_RUNS_LIMIT,
    Series,
    SeriesCreate,
    SeriesMember,
    new_series_id,
)

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
    stand TEXT,
    UNIQUE (series_id, run_id)
);
"""


class SeriesStore:
    """The series in the tables ``series`` and ``members`` of a :class:`Database`."""

    def __init__(self, database: Database, *, series: str, members: str) -> None:
        self._database = database
        self._series = series
        self._members = members

    def create(self, body: SeriesCreate) -> Series:
        """Store a new, empty series."""
        series = new_series(body)
        with self._database.connection("storing a series") as db:
            db.execute(
                f"INSERT INTO {self._series} VALUES (?, ?, ?, ?, ?, ?)",
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
        """The series and its members; raises ``SeriesNotFound``."""
        with self._database.connection(f"reading series {series_id}") as db:
            return self._get(db, series_id)

    def list(self) -> list[Series]:
        """Every series, newest first."""
        with self._database.connection("listing the series") as db:
            ids = db.execute(f"SELECT id FROM {self._series} ORDER BY created DESC").fetchall()
            return [self._get(db, i) for (i,) in ids]

    def add(
        self,
        series_id: str,
        run_id: str,
        level: str | None,
        *,
        stand: str,
        limit: int = SERIES_RUNS_LIMIT,
    ) -> Series:
        """Add the run, of the stand ``stand``, in one transaction with the checks:
        ``SeriesFull`` if the series holds ``limit`` runs, ``OtherStand`` if it holds a run
        of another stand, ``MemberExists`` if the run is a member already."""
        doing = f"adding a run to series {series_id}"
        try:
            with self._database.transaction(doing) as db:
                # the series' row locked: the adds to one series, from any thread or worker,
                # one at a time from here to the commit
                found = db.execute(
                    f"SELECT 1 FROM {self._series} WHERE id = ?{self._database.for_update}",
                    (series_id,),
                )
                if found.fetchone() is None:
                    raise SeriesNotFound(f"no series {series_id}")
                (count,) = db.execute(
                    f"SELECT COUNT(*) FROM {self._members} WHERE series_id = ?", (series_id,)
                ).fetchone()
                other = db.execute(
                    f"SELECT run_id, stand FROM {self._members} WHERE series_id = ? "
                    "AND stand IS NOT NULL AND stand != ? LIMIT 1",
                    (series_id, stand),
                ).fetchone()
                check_room(series_id, run_id, stand, count, other, limit)
                db.execute(
                    f"INSERT INTO {self._members} (series_id, run_id, level, added, stand) "
                    "VALUES (?, ?, ?, ?, ?)",
                    (series_id, run_id, level, iso(now()), stand),
                )
        except Taken:
            raise MemberExists(f"run {run_id} is in series {series_id} already") from None
        return self.get(series_id)

    def remove(self, series_id: str, run_id: str) -> Series:
        """Take a run out (``MemberNotFound`` if it is not a member)."""
        with self._database.connection(f"taking a run out of series {series_id}") as db:
            self._get(db, series_id)
            gone = db.execute(
                f"DELETE FROM {self._members} WHERE series_id = ? AND run_id = ?",
                (series_id, run_id),
            ).rowcount
            if not gone:
                raise MemberNotFound(f"run {run_id} is not in series {series_id}")
            return self._get(db, series_id)

    def close(self) -> None:
        self._database.close()

    def _get(self, db: Connection, series_id: str) -> Series:
        row = db.execute(
            f"SELECT id, name, purpose, factor, notes, created FROM {self._series} WHERE id = ?",
            (series_id,),
        ).fetchone()
        members = db.execute(
            f"SELECT run_id, level, added FROM {self._members} WHERE series_id = ? ORDER BY n",
            (series_id,),
        ).fetchall()
        return series_of(series_id, row, members)


class SqliteSeries(SeriesStore):
    """The series in one SQLite database (``path``), or in memory (``":memory:"``)."""

    def __init__(self, path: Path | str) -> None:
        database = SqliteDatabase(path, _SCHEMA, "series", _add_stand_column)
        super().__init__(database, series="series", members="members")


def _add_stand_column(db: sqlite3.Connection) -> None:
    """A members table made before the stand was kept gets the column (NULL in its rows)."""
    columns = {row[1] for row in db.execute("PRAGMA table_info(members)")}
    if "stand" not in columns:
        db.execute("ALTER TABLE members ADD COLUMN stand TEXT")


def check_room(
    series_id: str,
    run_id: str,
    stand: str,
    count: int,
    other: Sequence[Any] | None,
    limit: int,
) -> None:
    """``SeriesFull`` if the series holds ``count`` >= ``limit`` runs, ``OtherStand`` if it
    holds ``other`` (a member's ``(run_id, stand)``, of a stand not ``stand``)."""
    if count >= limit:
        raise SeriesFull(f"series {series_id} holds {count} runs, as many as a series may")
    if other is not None:
        raise OtherStand(
            f"series {series_id} holds {other[1]} runs (run {other[0]}); run {run_id} is a "
            f"{stand} run"
        )


def new_series(body: SeriesCreate) -> Series:
    return Series(
        id=new_series_id(),
        name=body.name,
        purpose=body.purpose,
        factor=body.factor,
        notes=body.notes,
        created=now(),
    )


def series_of(
    series_id: str, row: Sequence[Any] | None, members: Sequence[Sequence[Any]]
) -> Series:
    """The series of its row ``(id, name, purpose, factor, notes, created)`` and its members'
    rows ``(run_id, level, added)``; ``SeriesNotFound`` without a row. Times are ISO text."""
    if row is None:
        raise SeriesNotFound(f"no series {series_id}")
    return Series(
        id=row[0],
        name=row[1],
        purpose=row[2],
        factor=row[3],
        notes=row[4],
        created=as_utc(datetime.fromisoformat(row[5])),
        members=[
            SeriesMember(run_id=run_id, level=level, added=as_utc(datetime.fromisoformat(added)))
            for run_id, level, added in members
        ],
    )
