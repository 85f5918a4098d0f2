"""Live streams of the embedded store are woken by the batch, not by polling (issue 25 item 3)."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from rigserver.api.app import create_app
from rigserver.api.deps import Services
from rigserver.api.routes import live
from rigserver.api.settings import Settings
from rigserver.storage import HDF5Store
from schemas.runs import Run, RunState
from schemas.stands import StandKind, configure_stands
from tests.analysis.conftest import make_run

#: How soon a stored batch must reach a waiting stream: far below the 0.5 s of the polling
#: it replaces (what is left is a thread hop and a catalogue look-up)
PROMPT_SECONDS = 0.3
#: An idle stream watched this long (three of the old polls)
IDLE_SECONDS = 1.5


def _friction(rows: int) -> dict[str, Any]:
    t = np.arange(rows) * 1e-3
    return {
        "time": t,
        "load": np.full(rows, 300.0),
        "speed": np.full(rows, 1000.0),
        "friction_moment": np.full(rows, 2.5),
        "revolutions": t / 60.0,
    }


@pytest.fixture
def service(tmp_path: Path) -> Iterator[tuple[HDF5Store, Services, Run]]:
    """The service's parts over an embedded store, and an open SMTs-2 run in it."""
    store = HDF5Store(tmp_path / "data")
    app = create_app(Settings(data_dir=tmp_path), store, [], configure_stands())
    run = store.create_run(
        make_run(StandKind.SMTS2).model_copy(update={"id": "20261126T000000Z-0000beef"})
    )
    try:
        yield store, app.state.services, run
    finally:
        app.state.services.reports.close()
        store.close()


def test_an_idle_stream_reads_nothing_and_a_batch_wakes_it(
    service: tuple[HDF5Store, Services, Run], monkeypatch: pytest.MonkeyPatch
) -> None:
    store, services, run = service
    looked_up: list[float] = []
    real_get_run = store.get_run

    def counting(run_id: str) -> Any:
        looked_up.append(time.monotonic())
        return real_get_run(run_id)

    monkeypatch.setattr(store, "get_run", counting)

    async def watch() -> tuple[str, float, str]:
        stream = live._stream(services, run.id, "friction", 0)
        assert (await anext(stream)).startswith("retry:")
        event = asyncio.ensure_future(anext(stream))
        await asyncio.sleep(IDLE_SECONDS)
        assert not event.done()
        idle_lookups = len(looked_up)
        stored = time.monotonic()
        await asyncio.to_thread(store.append, run.id, 0, "friction", _friction(10))
        rows = await asyncio.wait_for(event, 5)
        latency = time.monotonic() - stored
        await asyncio.to_thread(store.end_run, run.id, RunState.FINISHED)
        end = await asyncio.wait_for(anext(stream), 5)
        assert idle_lookups == 1, "the idle stream read the catalogue again"
        return rows, latency, end

    rows, latency, end = asyncio.run(watch())
    assert rows.startswith("event: rows\nid: 10\n")
    assert latency < PROMPT_SECONDS
    assert end.startswith("event: end\n") and '"state":"finished"' in end


def test_a_stopping_server_wakes_its_idle_streams(
    service: tuple[HDF5Store, Services, Run],
) -> None:
    _, services, run = service

    async def watch() -> float:
        stream = live._stream(services, run.id, "friction", 0)
        await anext(stream)
        ending = asyncio.ensure_future(anext(stream, None))
        await asyncio.sleep(0.2)
        asked = time.monotonic()
        services.stop()
        assert await asyncio.wait_for(ending, 5) is None
        return time.monotonic() - asked

    assert asyncio.run(watch()) < PROMPT_SECONDS


def test_a_correction_wakes_the_stream_and_is_told_as_an_event(
    service: tuple[HDF5Store, Services, Run],
) -> None:
    store, services, run = service
    store.append(run.id, 0, "friction", _friction(10))

    async def watch() -> tuple[str, float]:
        stream = live._stream(services, run.id, "friction", 0)
        await anext(stream)  # retry
        await anext(stream)  # the rows stored
        event = asyncio.ensure_future(anext(stream))
        await asyncio.sleep(0.2)
        made = time.monotonic()
        fix = {"friction_moment": 2.75}
        await asyncio.to_thread(store.correct_reading, run.id, "friction", 4, fix, "misread", "k")
        told = await asyncio.wait_for(event, 5)
        return told, time.monotonic() - made

    told, latency = asyncio.run(watch())
    assert told.startswith("event: corrected\n")
    assert '"row":4' in told and '"was":2.5' in told and '"now":2.75' in told
    assert '"reason":"misread"' in told
    assert latency < PROMPT_SECONDS
