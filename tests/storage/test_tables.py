"""The small stores' databases (rigserver/storage/_tables.py): a write that meets another
writer's key is tried again, a bounded number of times."""

from __future__ import annotations

from pathlib import Path

import pytest

from rigserver.storage._tables import RETRIES, Connection, SqliteDatabase, retried
from rigserver.storage.errors import StorageUnavailable

_SCHEMA = "CREATE TABLE IF NOT EXISTS kept (k INTEGER PRIMARY KEY, v TEXT NOT NULL);"


def test_a_write_whose_key_is_always_taken_gives_up_as_unavailable() -> None:
    database = SqliteDatabase(":memory:", _SCHEMA, "test")
    with database.connection("keeping the first") as db:
        db.execute("INSERT INTO kept VALUES (?, ?)", (1, "first"))
    tries: list[int] = []

    def write(db: Connection) -> None:
        tries.append(1)
        db.execute("INSERT INTO kept VALUES (?, ?)", (2, "second"))
        db.execute("INSERT INTO kept VALUES (?, ?)", (1, "again"))  # taken, every time

    with pytest.raises(StorageUnavailable, match="storing a value"):
        retried(database, "storing a value", write)
    assert len(tries) == RETRIES
    with database.connection("reading") as db:  # each try rolled back whole
        assert db.execute("SELECT k, v FROM kept").fetchall() == [(1, "first")]
    database.close()


def test_a_write_that_meets_a_taken_key_is_stored_on_the_next_try() -> None:
    database = SqliteDatabase(":memory:", _SCHEMA, "test")
    with database.connection("keeping the first") as db:
        db.execute("INSERT INTO kept VALUES (?, ?)", (1, "first"))
    keys = iter([1, 2])  # the first try's key as another writer took it

    def write(db: Connection) -> int:
        key = next(keys)
        db.execute("INSERT INTO kept VALUES (?, ?)", (key, "next"))
        return key

    assert retried(database, "storing a value", write) == 2
    with database.connection("reading") as db:
        assert db.execute("SELECT k, v FROM kept ORDER BY k").fetchall() == [
            (1, "first"),
            (2, "next"),
        ]
    database.close()


def test_sqlites_own_failure_is_a_storage_error_naming_what_was_done(tmp_path: Path) -> None:
    # a database that fails under the store (here: closed; in the lab: damaged, locked,
    # full) is answered 503 naming the work, not 500
    database = SqliteDatabase(tmp_path / "kept.sqlite", _SCHEMA, "test")
    database.close()
    reading = database.connection("reading the values")
    with pytest.raises(StorageUnavailable, match="reading the values"), reading as db:
        db.execute("SELECT k FROM kept")
    storing = database.transaction("storing a value")
    with pytest.raises(StorageUnavailable, match="storing a value"), storing as db:
        db.execute("INSERT INTO kept VALUES (?, ?)", (1, "x"))
