"""What only the PostgreSQL store has: two stores (two workers) on one database, and the
run files it materialises from the journal."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from pathlib import Path

import numpy as np
import pytest

from rigserver.storage import NewBatch, PostgresStore, RunNotOpen, StorageUnavailable
from rigserver.storage.base import Columns
from schemas.runs import RunState
from tests.storage.conftest import friction, make_run


@pytest.fixture
def workers(tmp_path: Path, postgres_url: str) -> Iterator[tuple[PostgresStore, PostgresStore]]:
    """Two stores sharing the database and the files directory, as two workers do."""
    a = PostgresStore(postgres_url, files_dir=tmp_path / "files")
    b = PostgresStore(postgres_url, files_dir=tmp_path / "files")
    yield a, b
    a.close()
    b.close()


def test_each_worker_sees_what_the_other_stored(workers: tuple[PostgresStore, ...]) -> None:
    a, b = workers
    run = a.create_run(make_run())
    a.append(run.id, 0, "friction", friction(0, 5))
    b.append(run.id, 1, "friction", friction(5, 5))
    assert b.append(run.id, 0, "friction", friction(0, 5)).duplicate  # a's batch, retried
    for store in workers:
        got = store.get_run(run.id)
        assert (got.batches, got.rows["friction"]) == (2, 10)
        np.testing.assert_array_equal(store.read(run.id, "friction")["time"], 0.5 * np.arange(10))
    assert a.readings_version(run.id) == b.readings_version(run.id) == 2
    b.end_run(run.id, RunState.FINISHED)
    with pytest.raises(RunNotOpen):
        a.end_run(run.id, RunState.ABORTED)
    with pytest.raises(RunNotOpen):
        a.append(run.id, 2, "friction", friction(10, 5))


def test_the_last_values_a_batch_is_checked_against_are_the_other_workers_too(
    workers: tuple[PostgresStore, ...],
) -> None:
    """Worker a caches the last values it stored; b stores after it; a's next check must
    see b's values, not its cache (the cache is keyed by the run's batch count)."""
    a, b = workers
    run = a.create_run(make_run())
    seen: list[dict[str, float]] = []

    def remember(columns: Columns, last: Mapping[str, float]) -> None:
        seen.append(dict(last))

    def post(store: PostgresStore, seq: int, start: int) -> None:
        (outcome,) = store.append_many(
            [NewBatch(run.id, seq, "friction", friction(start, 5), remember)]
        )
        assert not isinstance(outcome, Exception), outcome

    post(a, 0, 0)
    post(a, 1, 5)  # a's cache now holds row 9's values
    post(b, 2, 10)
    post(a, 3, 15)
    # friction(k) has time 0.5 k: the last row before each batch was 4, 9, 14
    assert [s.get("time") for s in seen] == [None, 0.5 * 4, 0.5 * 9, 0.5 * 14]


def test_an_ended_runs_file_is_materialised_once_and_read(
    workers: tuple[PostgresStore, ...], tmp_path: Path
) -> None:
    a, b = workers
    run = a.create_run(make_run())
    a.append(run.id, 0, "friction", friction(0, 7))
    a.append(run.id, 1, "measurements", {"pin_mass_before": np.array([2.0])})
    a.end_run(run.id, RunState.FINISHED)
    path = tmp_path / "files" / "runs" / f"{run.id}.h5"
    assert b.run_file(run.id) == path  # made by the worker that ended the run
    from_file = b.read(run.id, "friction", None, 2, 6)
    path.unlink()  # gone (e.g. not shared): the journal answers the same
    from_journal = b.read(run.id, "friction", None, 2, 6)
    for name, values in friction(2, 4).items():
        np.testing.assert_array_equal(from_file[name], values)
        np.testing.assert_array_equal(from_journal[name], values)
    assert b.run_file(run.id) == path and path.exists()


def test_a_database_that_is_gone_is_unavailable(tmp_path: Path) -> None:
    """No server on the socket: opening the store fails as StorageUnavailable (a 503)."""
    url = f"postgresql:///rig?host={tmp_path}&port=1&user=rig&connect_timeout=1"
    with pytest.raises(StorageUnavailable, match="opening the database"):
        PostgresStore(url, files_dir=tmp_path / "files")
