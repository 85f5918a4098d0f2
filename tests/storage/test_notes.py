"""The store of the student's own words, embedded (SQLite) and in the cluster's PostgreSQL:
the same behaviour, every version kept with who wrote it and when."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from datetime import UTC, datetime
from pathlib import Path

import pytest

from rigserver.storage.cluster.notes_postgres import PostgresNotes
from rigserver.storage.notes import NotesStore, SqliteNotes
from schemas.student_notes import StudentNotesWrite
from tests.postgres import postgres_server, postgres_url, sqlite_or_postgres  # noqa: F401 (fixtures)

RUN_A = "20261125T120000Z-0000000a"
RUN_B = "20261125T120000Z-0000000b"
FIRST = StudentNotesWrite(
    group="MT-31", students=["А. Иванова", "B. Petrov"], conclusions="f ≈ 0,4"
)
SECOND = StudentNotesWrite(group="MT-31", students=["А. Иванова"], conclusions="wear <\n\nx & y")


@pytest.fixture(params=["sqlite", "postgres"])
def notes(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[NotesStore]:
    yield from sqlite_or_postgres(
        request, lambda: SqliteNotes(tmp_path / "notes.sqlite"), PostgresNotes, "rig_notes"
    )


def test_a_run_without_words_has_the_empty_version_0(notes: NotesStore) -> None:
    found = notes.get(RUN_A)
    assert found.version == 0 and found.empty and found.by is None and found.written is None
    assert notes.history(RUN_A) == []


def test_each_write_is_a_new_version_with_its_author(notes: NotesStore) -> None:
    before = datetime.now(UTC)
    one = notes.put(RUN_A, FIRST, by="lab PC")
    two = notes.put(RUN_A, SECOND, by="instructor")
    assert (one.version, one.by, two.version, two.by) == (1, "lab PC", 2, "instructor")
    assert one.written is not None and before <= one.written <= datetime.now(UTC)
    got = notes.get(RUN_A)
    assert got == two
    assert (
        StudentNotesWrite.model_validate(
            got.model_dump(include={"group", "students", "conclusions"})
        )
        == SECOND
    )
    assert notes.history(RUN_A) == [one, two]
    assert notes.get(RUN_B).version == 0  # another run's words are its own


def test_writes_at_once_each_get_a_version_of_their_own(notes: NotesStore) -> None:
    """Writers at once (threads of one server, or the workers of a cluster) read the same
    last version: each write gets one of its own all the same (tried again where another
    took it first), none lost."""
    writers = 4
    start = threading.Barrier(writers)

    def write(n: int) -> int:
        start.wait()
        return notes.put(RUN_A, FIRST, by=f"writer {n}").version

    with ThreadPoolExecutor(writers) as pool:
        versions = sorted(pool.map(write, range(writers)))
    assert versions == [1, 2, 3, 4]
    history = notes.history(RUN_A)
    assert [h.version for h in history] == versions
    assert sorted(h.by for h in history if h.by) == [f"writer {n}" for n in range(writers)]


def test_the_words_outlive_the_database_connection(tmp_path: Path) -> None:
    store = SqliteNotes(tmp_path / "notes.sqlite")
    written = store.put(RUN_A, FIRST, by="lab PC")
    store.close()
    again = SqliteNotes(tmp_path / "notes.sqlite")
    try:
        assert again.get(RUN_A) == written
    finally:
        again.close()
