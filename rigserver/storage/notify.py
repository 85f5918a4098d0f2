"""Appends across processes: PostgreSQL LISTEN/NOTIFY woken into asyncio waiters.

Every commit that stores batches (or ends a run) sends ``NOTIFY rig_runs, '<run id>
<batch count>'`` in its transaction, so it is delivered once committed and only then. Each
worker has one listener thread on a connection of its own; it wakes the coroutines
waiting on that run (the live streams) in their event loops. A notification lost while
the listener reconnects costs a waiter its timeout, nothing more: waiters read the
catalogue when woken either way.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import threading
from typing import Any

import psycopg

log = logging.getLogger(__name__)

CHANNEL = "rig_runs"
#: Seconds between checks of the stop flag, and before reconnecting after a failure
_WAKE_SECONDS = 1.0
#: Runs whose last batch count is kept (emptied beyond)
_KEPT = 4096


def notify(conn: psycopg.Connection[Any], run_id: str, batches: int) -> None:
    """Queue the notification in the connection's open transaction."""
    conn.execute("SELECT pg_notify(%s, %s)", (CHANNEL, f"{run_id} {batches}"))


class Appends:
    """The runs' batch counts as notified, and the coroutines waiting for them to grow."""

    def __init__(self, url: str) -> None:
        self._url = url
        self._lock = threading.Lock()
        self._batches: dict[str, int] = {}
        self._waiters: dict[str, list[tuple[asyncio.AbstractEventLoop, asyncio.Future[None]]]]
        self._waiters = {}
        self._stop = threading.Event()
        #: Set while the listener is listening
        self.listening = threading.Event()
        self._thread = threading.Thread(target=self._listen, name="rig-notify", daemon=True)
        self._thread.start()

    def close(self) -> None:
        self._stop.set()
        self._thread.join()

    async def wait(self, run_id: str, batches: int, timeout: float) -> bool:
        """Until the run has more than ``batches`` batches (or has ended): True if notified
        of it, False after ``timeout`` seconds."""
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

    def _woken(self, payload: str) -> None:
        run_id, _, count = payload.rpartition(" ")
        with self._lock:
            if len(self._batches) > _KEPT:
                self._batches.clear()
            self._batches[run_id] = int(count)
            waiting = self._waiters.pop(run_id, [])
        for loop, future in waiting:
            loop.call_soon_threadsafe(_resolve, future)

    def _listen(self) -> None:
        while not self._stop.is_set():
            try:
                with psycopg.connect(self._url, autocommit=True, connect_timeout=5) as conn:
                    conn.execute(f"LISTEN {CHANNEL}")
                    self.listening.set()
                    while not self._stop.is_set():
                        for note in conn.notifies(timeout=_WAKE_SECONDS):
                            self._woken(note.payload)
            except (psycopg.Error, OSError, ValueError) as exc:
                self.listening.clear()
                log.warning("listening for appends failed (reconnecting): %s", exc)
                self._stop.wait(_WAKE_SECONDS)


def _resolve(future: asyncio.Future[None]) -> None:
    if not future.done():
        future.set_result(None)
