"""Appends notified across connections (LISTEN/NOTIFY): a waiter on one store is woken
by what another store commits, and only then."""

from __future__ import annotations

import asyncio
from pathlib import Path

from rigserver.storage.cluster.postgres import PostgresStore
from schemas.runs import RunState
from tests.storage.conftest import friction, make_run


def test_a_commit_elsewhere_wakes_the_waiters_of_its_run(postgres_url: str, tmp_path: Path) -> None:
    with (
        PostgresStore(postgres_url, files_dir=tmp_path / "a") as a,
        PostgresStore(postgres_url, files_dir=tmp_path / "b") as b,
    ):
        run = a.create_run(make_run())
        other = a.create_run(make_run())

        async def scenario() -> None:
            assert await b.wait_for_appends(run.id, 0, 0.01) is False  # starts the listener
            assert b._appends is not None
            assert await asyncio.to_thread(b._appends.listening.wait, 10)
            waiter = asyncio.create_task(b.wait_for_appends(run.id, 0, 30))
            bystander = asyncio.create_task(b.wait_for_appends(other.id, 0, 0.5))
            await asyncio.sleep(0.05)
            assert not waiter.done()  # nothing committed yet
            await asyncio.to_thread(a.append, run.id, 0, "friction", friction(0, 5))
            assert await waiter is True  # woken by the notification, not the 30 s timeout
            assert await bystander is False  # another run's append wakes nobody here
            # ending the run wakes its waiters too (the batch count stays 1)
            ender = asyncio.create_task(b.wait_for_appends(run.id, 1, 30))
            await asyncio.sleep(0.05)
            await asyncio.to_thread(a.end_run, run.id, RunState.FINISHED)
            assert await ender is True

        asyncio.run(scenario())
