"""Appends across processes: PostgreSQL LISTEN/NOTIFY woken into asyncio waiters.

Every commit that stores batches (or ends a run) sends ``NOTIFY rig_runs, '<run id>
<batch count>'`` in its transaction, so it is delivered once committed and only then. Each
worker has one listener thread on a connection of its own; it wakes the coroutines
waiting on that run (the live streams) in their event loops. A notification lost while
the listener reconnects costs a waiter its timeout, nothing more: waiters read the
catalogue when woken either way.
"""

from __future__ import annotations

import logging
import threading
from typing import Any

import psycopg

from rigserver.storage.waiters import AppendWaiters

log = logging.getLogger(__name__)

CHANNEL = "rig_runs"
#: Seconds between checks of the stop flag, and before reconnecting after a failure
_WAKE_SECONDS = 1.0


def notify(conn: psycopg.Connection[Any], run_id: str, batches: int) -> None:
    """Queue the notification in the connection's open transaction."""
    conn.execute("SELECT pg_notify(%s, %s)", (CHANNEL, f"{run_id} {batches}"))


class Appends(AppendWaiters):
    """The runs' batch counts as notified, and the coroutines waiting for them to grow."""

    def __init__(self, url: str) -> None:
        super().__init__()
        self._url = url
        self._stop = threading.Event()
        #: Set while the listener is listening
        self.listening = threading.Event()
        self._thread = threading.Thread(target=self._listen, name="rig-notify", daemon=True)
        self._thread.start()

    def close(self) -> None:
        self._stop.set()
        self._thread.join()

    def _woken(self, payload: str) -> None:
        run_id, _, count = payload.rpartition(" ")
        self.woken(run_id, int(count))

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
