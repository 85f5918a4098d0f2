"""The store of the students' sketches, embedded (SQLite) and in the cluster's PostgreSQL:
the same behaviour, every version kept with its image, who uploaded it and when."""

from __future__ import annotations

import hashlib
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

import pytest

from rigserver.storage.cluster.sketches_postgres import PostgresSketches
from rigserver.storage.sketches import SketchStore, SqliteSketches
from tests.postgres import postgres_server, postgres_url, sqlite_or_postgres  # noqa: F401 (fixtures)

RUN_A = "20261125T120000Z-0000000a"
RUN_B = "20261125T120000Z-0000000b"
#: Not images: the store keeps bytes as given (the API checks them at the door).
FIRST, SECOND = b"\x89PNG first\x00\xff", b"\xff\xd8\xff second"


@pytest.fixture(params=["sqlite", "postgres"])
def sketches(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[SketchStore]:
    yield from sqlite_or_postgres(
        request,
        lambda: SqliteSketches(tmp_path / "sketches.sqlite"),
        PostgresSketches,
        "rig_sketches",
    )


def test_a_run_without_sketches_has_none(sketches: SketchStore) -> None:
    assert sketches.latest(RUN_A) == [] and sketches.history(RUN_A) == []
    assert sketches.image(RUN_A, 4) is None


def test_a_replaced_sketch_stays_readable_by_its_version(sketches: SketchStore) -> None:
    before = datetime.now(UTC)
    one = sketches.put(RUN_A, 4, FIRST, media_type="image/png", size=(3, 2), by="lab PC")
    other = sketches.put(RUN_A, 5, FIRST, media_type="image/png", size=(3, 2), by="lab PC")
    two = sketches.put(RUN_A, 4, SECOND, media_type="image/jpeg", size=(5, 7), by="instructor")
    assert (one.version, other.version, two.version) == (1, 1, 2)
    assert (two.media_type, two.width, two.height, two.size) == ("image/jpeg", 5, 7, len(SECOND))
    assert two.sha256 == hashlib.sha256(SECOND).hexdigest() and two.by == "instructor"
    assert before <= one.written <= two.written <= datetime.now(UTC)
    assert sketches.latest(RUN_A) == [two, other]
    assert sketches.history(RUN_A) == [one, two, other]
    assert sketches.image(RUN_A, 4) == (two, SECOND)
    assert sketches.image(RUN_A, 4, 1) == (one, FIRST)
    assert sketches.image(RUN_A, 4, 3) is None
    assert sketches.latest(RUN_B) == []  # another run's sketches are its own


def test_the_sketches_outlive_the_database_connection(tmp_path: Path) -> None:
    store = SqliteSketches(tmp_path / "sketches.sqlite")
    kept = store.put(RUN_A, 4, FIRST, media_type="image/png", size=(3, 2), by="lab PC")
    store.close()
    again = SqliteSketches(tmp_path / "sketches.sqlite")
    try:
        assert again.image(RUN_A, 4) == (kept, FIRST)
    finally:
        again.close()
