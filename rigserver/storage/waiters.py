"""Coroutines waiting for a run's next batch, woken from any thread.

A store tells :meth:`AppendWaiters.woken` each run whose batch count grew (or that ended):
the embedded stores in the process that stored the batch, the cluster's listener when
PostgreSQL notifies it (:mod:`~rigserver.storage.cluster.notify`). The live streams wait
here instead of polling the catalogue, so a viewer whose run is idle costs a parked
coroutine and nothing else.
"""

from __future__ import annotations

import asyncio
import contextlib
import sys
import threading

#: Runs whose last batch count is kept (emptied beyond)
_KEPT = 4096
#: The count of a run that has ended: more than any it had
_ENDED = sys.maxsize


class AppendWaiters:
    """The runs' batch counts as last told, and the coroutines waiting for them to grow."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._batches: dict[str, int] = {}
        self._waiters: dict[str, list[tuple[asyncio.AbstractEventLoop, asyncio.Future[None]]]]
        self._waiters = {}

    async def wait(self, run_id: str, batches: int, timeout: float) -> bool:
        """Until the run has more than ``batches`` batches (or has ended, or :meth:`wake_all`):
        True if told so, False after ``timeout`` seconds."""
        loop = asyncio.get_running_loop()
        future: asyncio.Future[None] = loop.create_future()
        with self._lock:
            if self._batches.get(run_id, -1) > batches:
                return True
            self._waiters.setdefault(run_id, []).append((loop, future))
        try:
            await asyncio.wait_for(future, timeout)
        except TimeoutError:
            return False
        finally:
            with self._lock:
                waiting = self._waiters.get(run_id, [])
                with contextlib.suppress(ValueError):
                    waiting.remove((loop, future))
                if not waiting:
                    self._waiters.pop(run_id, None)
        return True

    def woken(self, run_id: str, batches: int) -> None:
        """The run now has ``batches`` batches, or has ended: wake its waiters."""
        with self._lock:
            if len(self._batches) > _KEPT:
                self._batches.clear()
            self._batches[run_id] = max(batches, self._batches.get(run_id, -1))
            waiting = self._waiters.pop(run_id, [])
        _resolve_all(waiting)

    def ended(self, run_id: str) -> None:
        """The run has ended: wake its waiters (they read its state), and whoever waits for
        it later at once."""
        with self._lock:
            self._batches[run_id] = _ENDED
            waiting = self._waiters.pop(run_id, [])
        _resolve_all(waiting)

    def wake_all(self) -> None:
        """Wake every waiter (the server is stopping)."""
        with self._lock:
            waiting = [w for ws in self._waiters.values() for w in ws]
            self._waiters.clear()
        _resolve_all(waiting)


def _resolve_all(waiting: list[tuple[asyncio.AbstractEventLoop, asyncio.Future[None]]]) -> None:
    for loop, future in waiting:
        with contextlib.suppress(RuntimeError):  # a loop closed meanwhile
            loop.call_soon_threadsafe(_resolve, future)


def _resolve(future: asyncio.Future[None]) -> None:
    if not future.done():
        future.set_result(None)


class TellsInProcess:
    """The :class:`~rigserver.storage.base.LiveStore` side of a store whose batches are all
    stored in this process (the embedded store, the in-memory one): ``appends`` tells."""

    appends: AppendWaiters
    #: Told in process: no notification is lost
    appends_lossy = False

    def wake_waiters(self) -> None:
        """Wake every live stream waiting (the server is stopping)."""
        self.appends.wake_all()

    async def wait_for_appends(self, run_id: str, batches: int, timeout: float) -> bool:
        """Until a batch of the run beyond ``batches`` is committed or the run ends (told in
        this process); False after ``timeout`` seconds."""
        return await self.appends.wait(run_id, batches, timeout)
