"""The small stores beside the runs (the series, the students' words, their sketches): their
SQL written once, for a SQLite database (:class:`SqliteDatabase`, here) or the cluster's
PostgreSQL (:class:`~rigserver.storage.cluster.tables.PostgresDatabase`).

A store asks its :class:`Database` for a connection (one statement at a time) or a
transaction (its statements as one, no other writer's between them) and writes its SQL in
SQLite's words: ``?`` for a parameter. What a database cannot share is said by its hooks:
:attr:`Database.for_update` (what locks a row that a transaction reads) and :class:`Taken`
(raised for a row whose key another writer stored first).
"""

from __future__ import annotations

import sqlite3
import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import AbstractContextManager, contextmanager
from pathlib import Path
from typing import Any, Protocol, TypeVar

from rigserver.storage._failures import failures_as
from rigserver.storage.errors import StorageUnavailable

_T = TypeVar("_T")

#: Writes of a new version that met another writer's: tried again, this many times in all.
RETRIES = 5


class Taken(StorageUnavailable):
    """A row's key is taken: another writer stored it first (the store tries again, or says
    it could not store the row)."""


class Rows(Protocol):
    """What a statement gives back."""

    @property
    def rowcount(self) -> int: ...

    def fetchone(self) -> Any: ...

    def fetchall(self) -> list[Any]: ...


class Connection(Protocol):
    def execute(self, sql: str, parameters: Sequence[Any] = (), /) -> Rows:
        """Run one statement of SQLite's words (``?`` for a parameter)."""
        ...


class Database(Protocol):
    #: Appended to a query in a transaction, it locks the rows read until the commit.
    for_update: str

    def connection(self, doing: str) -> AbstractContextManager[Connection]:
        """A connection for statements each on its own; ``doing`` names the work in the
        errors."""
        ...

    def transaction(self, doing: str) -> AbstractContextManager[Connection]:
        """Statements committed together at the end of the block, or none of them; no other
        writer's can come between the rows it reads locked (:attr:`for_update`) and its
        writes. :class:`Taken` (all rolled back) for a row whose key is stored already."""
        ...

    def close(self) -> None: ...


def retried(database: Database, doing: str, write: Callable[[Connection], _T]) -> _T:
    """``write`` in a transaction, tried again while another writer stores its row's key
    first (a new version numbered as theirs): :data:`RETRIES` times in all, then the last
    :class:`Taken` raised (a ``StorageUnavailable``)."""
    attempt = 1
    while True:
        try:
            with database.transaction(doing) as db:
                return write(db)
        except Taken:
            if attempt == RETRIES:
                raise
            attempt += 1


def _sqlite_failures(doing: str) -> AbstractContextManager[None]:
    """SQLite's own failures (a locked, damaged, full or closed database) as storage errors
    naming what was being done: 503 or 507, not 500; a bug of ours stays one."""
    return failures_as(doing, (sqlite3.Error,))


class SqliteDatabase:
    """A SQLite database at ``path`` (``":memory:"``: in memory) in WAL mode, with foreign keys
    enforced and the tables of ``schema``; ``upgrade`` brings older tables to it, as part of
    opening. :class:`StorageUnavailable` naming ``what`` if it cannot be opened.

    One connection, used by one thread at a time; a transaction holds the write lock from
    its first statement (``BEGIN IMMEDIATE``), so no other connection writes between the
    rows it reads and its writes."""

    for_update = ""

    def __init__(
        self,
        path: Path | str,
        schema: str,
        what: str,
        upgrade: Callable[[sqlite3.Connection], None] | None = None,
    ) -> None:
        try:
            self._db = sqlite3.connect(str(path), isolation_level=None, check_same_thread=False)
            self._db.execute("PRAGMA journal_mode=WAL")
            self._db.execute("PRAGMA foreign_keys=ON")
            self._db.executescript(schema)
            if upgrade is not None:
                upgrade(self._db)
        except sqlite3.Error as exc:
            raise StorageUnavailable(f"cannot open the {what} database: {exc}") from exc
        self._lock = threading.Lock()

    @contextmanager
    def connection(self, doing: str) -> Iterator[Connection]:
        with self._lock, _sqlite_failures(doing), taken_when(sqlite3.IntegrityError, doing):
            yield self._db

    @contextmanager
    def transaction(self, doing: str) -> Iterator[Connection]:
        with self._lock, _sqlite_failures(doing), taken_when(sqlite3.IntegrityError, doing):
            self._db.execute("BEGIN IMMEDIATE")
            try:
                yield self._db
            except BaseException:
                self._db.execute("ROLLBACK")
                raise
            self._db.execute("COMMIT")

    def close(self) -> None:
        with self._lock:
            self._db.close()


@contextmanager
def taken_when(kind: type[Exception], doing: str) -> Iterator[None]:
    """:class:`Taken` for the database's ``kind`` of error (a key stored already) in the
    block, while ``doing``."""
    try:
        yield
    except kind as exc:
        raise Taken(f"storage failed while {doing}: {exc}") from exc
