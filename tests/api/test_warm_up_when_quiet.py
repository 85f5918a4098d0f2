"""The report renderer is loaded once ingest has been quiet, not as the service starts:
loading it takes a core for 2-3 s, and binary batches posted meanwhile were stored at
three quarters of the rate (docs/speed.md, "Ingest, the seventh set")."""

from __future__ import annotations

import asyncio
import threading
from types import SimpleNamespace

import pytest

from rigserver.api import app as app_module
from rigserver.api import ingest_queue
from rigserver.api.ingest_queue import IngestQueue
from rigserver.storage.memory import MemoryStore


class _Clock:
    def __init__(self, now: float) -> None:
        self.now = now

    def monotonic(self) -> float:
        return self.now


def test_the_queue_is_quiet_once_no_post_has_been_admitted_for_the_time_asked(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    clock = _Clock(100.0)
    monkeypatch.setattr(ingest_queue, "time", clock)
    queue = IngestQueue(
        MemoryStore(), lambda run_id: threading.Lock(), max_batches=3, max_bytes=10, retry_after=1
    )
    clock.now = 101.9
    assert not queue.quiet_for(2.0)  # made 1.9 s ago: as a post would be
    clock.now = 102.0
    assert queue.quiet_for(2.0)
    clock.now = 103.0
    with queue.admit(4):
        clock.now = 110.0
        assert not queue.quiet_for(2.0)  # a post held (its body arriving) is no quiet
        assert not queue.quiet_for(0.0)
    assert queue.quiet_for(2.0)  # admitted at 103, 7 s ago, and let go
    with queue.admit(4):
        pass
    clock.now = 111.5
    assert not queue.quiet_for(2.0)  # admitted at 110
    clock.now = 112.0
    assert queue.quiet_for(2.0)


class _Reports:
    def __init__(self) -> None:
        self.warmed = 0

    def warm_up(self) -> None:
        self.warmed += 1


class _Ingest:
    """Quiet at the ``quiet_at``-th question (1-based), never if 0."""

    def __init__(self, quiet_at: int) -> None:
        self.quiet_at = quiet_at
        self.asked: list[float] = []

    def quiet_for(self, seconds: float) -> bool:
        self.asked.append(seconds)
        return len(self.asked) == self.quiet_at


def test_the_renderer_is_loaded_once_ingest_is_quiet_and_only_then(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(app_module, "WARM_UP_WHEN_QUIET_S", 0.004)
    services = SimpleNamespace(ingest=_Ingest(quiet_at=3), reports=_Reports())
    asyncio.run(app_module._warm_up_when_quiet(services))  # type: ignore[arg-type]
    assert services.ingest.asked == [0.004] * 3
    assert services.reports.warmed == 1


def test_a_service_that_stops_before_a_quiet_moment_never_loads_the_renderer(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(app_module, "WARM_UP_WHEN_QUIET_S", 0.004)
    services = SimpleNamespace(ingest=_Ingest(quiet_at=0), reports=_Reports())

    async def stopped_early() -> None:
        waiting = asyncio.create_task(app_module._warm_up_when_quiet(services))  # type: ignore[arg-type]
        await asyncio.sleep(0.05)
        assert not waiting.done()
        waiting.cancel()
        with pytest.raises(asyncio.CancelledError):
            await waiting

    asyncio.run(stopped_early())
    assert len(services.ingest.asked) >= 3
    assert services.reports.warmed == 0
