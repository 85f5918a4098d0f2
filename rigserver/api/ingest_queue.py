"""The bounded ingest queue: admission of batch posts, and group commits.

Admission bounds what the service holds for ingest: at most ``max_batches`` posts at once
(from reading the body to the answer) and ``max_bytes`` of their bodies, counted as the
bytes that have arrived: a body that declares 64 MiB and trickles in a byte now and then
holds what has come, not what it promised. A post beyond either is answered 503 with
``Retry-After``, before its body is read when it cannot fit (the bodies in plus its
``Content-Length``), or as soon as its arriving bytes overflow the queue; so a burst of lab
PCs makes them wait instead of growing the server's memory.

Admission is fair across API keys: one key holds at most its ``share`` of the posts and of
the bytes (its posts' declared sizes, and the bytes of its bodies that have arrived), and
counts against the queue's bytes for at most that share: a body larger than its key's share
is admitted when the key holds nothing else, and the other keys keep the rest of the queue
while it arrives. So one lab PC's slow, stuck or huge uploads (each held until the body
arrives or its time is up, :mod:`rigserver.api.body_limit`) never refuse another stand's
posts. Its post beyond the share is answered 503 with ``Retry-After`` too.

Small batches (single readings, a few rows) are stored on the event loop in groups: every
small batch that arrives while the loop is busy joins the next group, stored with one
journal commit (:meth:`RunStore.append_many`) once the loop has nothing else ready, so a
busy server commits many batches at once and an idle one each at once. A thread hop per
post would cost more than storing a single reading. Large batches are stored in a worker
thread, one per commit. Either way a batch is acknowledged only once its commit returned.

A run's lock is held while the run is finished or aborted; ingest never waits for it: a
batch of such a run is answered 503 with ``Retry-After`` (after the end its retry meets
409; if the end failed, the retry is stored).
"""

from __future__ import annotations

import asyncio
import logging
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from fastapi.concurrency import run_in_threadpool

from rigserver.api.problems import ApiProblem
from rigserver.storage.base import NewBatch, RunStore
from schemas.readings import BatchReceipt

log = logging.getLogger("rigserver")

Outcome = BatchReceipt | Exception
_Pending = list[tuple[NewBatch, "asyncio.Future[Outcome]"]]


class _Held:
    """What one API key holds: its posts, their bodies' declared bytes and arrived bytes."""

    __slots__ = ("arrived", "declared", "posts")

    def __init__(self) -> None:
        self.posts = self.declared = self.arrived = 0


class Place:
    """A post's place in the queue (:meth:`IngestQueue.admit`): the bytes of its body that
    have arrived."""

    __slots__ = ("bytes", "key", "queue")

    def __init__(self, queue: IngestQueue, key: str) -> None:
        self.queue = queue
        self.key = key
        self.bytes = 0

    def arrived(self, size: int) -> None:
        """``size`` more bytes of the body are in; 503 (ApiProblem) if they overflow the
        key's share or the queue: the post is refused, its body read no further."""
        self.queue.arrive(self, size)


class IngestQueue:
    """Admission and group commits of one service (see the module docstring).

    Parameters
    ----------
    store : RunStore
    run_lock : callable
        The lock of a run (held by whoever finishes or aborts it).
    max_batches : int
        Posts admitted at once.
    max_bytes : int
        Bytes of request bodies held at once, as they arrive.
    share : float
        The fraction of ``max_batches`` and ``max_bytes`` one API key may hold, 0 < share <= 1.
    retry_after : int
        Seconds in the ``Retry-After`` of a 503, s.
    """

    def __init__(
        self,
        store: RunStore,
        run_lock: Callable[[str], threading.Lock],
        *,
        max_batches: int,
        max_bytes: int,
        share: float = 1.0,
        retry_after: int,
    ) -> None:
        self._store = store
        self._run_lock = run_lock
        self.max_batches = max_batches
        self.max_bytes = max_bytes
        self.key_batches = max(1, int(max_batches * share))
        self.key_bytes = max(1, int(max_bytes * share))
        self.retry_after = retry_after
        self._admission = threading.Lock()
        self._admitted = 0
        #: bytes counted against max_bytes: per key, what has arrived, at most its share
        self._counted = 0
        #: API key -> what it holds (a key holding none is not kept)
        self._held: dict[str, _Held] = {}
        self._pending: dict[asyncio.AbstractEventLoop, _Pending] = {}
        #: when the last post was admitted (time.monotonic), or the queue made
        self._last_post = time.monotonic()

    # --- admission --------------------------------------------------------------------

    @property
    def admitted(self) -> tuple[int, int]:
        """Posts admitted now, and the bytes of their bodies counted against the queue."""
        with self._admission:
            return self._admitted, self._counted

    def quiet_for(self, seconds: float) -> bool:
        """Whether no post is held and none was admitted in the last ``seconds`` s."""
        with self._admission:
            return not self._admitted and time.monotonic() - self._last_post >= seconds

    @contextmanager
    def admit(self, size: int, key: str = "") -> Iterator[Place]:
        """Hold a place for a post of the API key ``key`` (its fingerprint) whose body
        declares ``size`` bytes (0 if chunked); 503 if there is none, or if the key holds
        its share. The body's bytes are counted as they arrive (:meth:`Place.arrived`)."""
        with self._admission:
            held = self._held.get(key) or _Held()
            if self._admitted >= self.max_batches or (
                self._counted and self._counted + min(size, self.key_bytes) > self.max_bytes
            ):
                raise self._queue_full()
            if held.posts >= self.key_batches or (
                held.posts and max(held.declared + size, held.arrived) > self.key_bytes
            ):
                raise self._share_used(held)
            self._admitted += 1
            self._last_post = time.monotonic()
            held.posts += 1
            held.declared += size
            self._held[key] = held
        place = Place(self, key)
        try:
            yield place
        finally:
            with self._admission:
                self._admitted -= 1
                held.posts -= 1
                held.declared -= size
                self._count(held, -place.bytes)
                if not held.posts:
                    del self._held[key]

    def arrive(self, place: Place, size: int) -> None:
        """``size`` more bytes of the body of ``place`` are in; 503 if they overflow the
        key's share (while it holds another post) or the queue (while another post is in)."""
        with self._admission:
            held = self._held[place.key]
            if held.posts > 1 and held.arrived + size > self.key_bytes:
                raise self._share_used(held)
            self._count(held, size)
            if self._counted > self.max_bytes and self._admitted > 1:
                self._count(held, -size)
                raise self._queue_full()
            place.bytes += size

    def _count(self, held: _Held, size: int) -> None:
        """``size`` bytes more (or fewer) of the key ``held`` in: counted up to its share."""
        counted = min(held.arrived, self.key_bytes)
        held.arrived += size
        self._counted += min(held.arrived, self.key_bytes) - counted

    def _queue_full(self) -> ApiProblem:
        return self._full(
            "Ingest queue full",
            f"the server holds {self._admitted} batches ({self._counted} bytes) and takes "
            f"at most {self.max_batches} ({self.max_bytes} bytes) at once",
        )

    def _share_used(self, held: _Held) -> ApiProblem:
        if self.key_bytes >= self.max_bytes:  # a key's share is the whole queue
            return self._queue_full()
        return self._full(
            "Ingest share used",
            f"this key's uploads hold {held.posts} batches "
            f"({max(held.declared, held.arrived)} bytes) and one key may hold "
            f"{self.key_batches} ({self.key_bytes} bytes) at once",
        )

    def _full(self, title: str, detail: str) -> ApiProblem:
        return ApiProblem(
            503,
            title,
            f"{detail}; retry in {self.retry_after} s",
            headers={"Retry-After": str(self.retry_after)},
        )

    # --- storing ----------------------------------------------------------------------

    async def store(self, batch: NewBatch, *, small: bool) -> BatchReceipt:
        """Store ``batch``: its receipt once it is durable, or the exception that refused
        it. ``small`` batches join the event loop's next group commit."""
        if small:
            loop = asyncio.get_running_loop()
            future: asyncio.Future[Outcome] = loop.create_future()
            pending = self._pending.setdefault(loop, [])
            pending.append((batch, future))
            if len(pending) == 1:
                loop.call_soon(self._commit_pending, loop)
            outcome = await future
        else:
            (outcome,) = await run_in_threadpool(self._write, [batch])
        if isinstance(outcome, Exception):
            raise outcome
        return outcome

    def _commit_pending(self, loop: asyncio.AbstractEventLoop) -> None:
        pending = self._pending.pop(loop, [])
        outcomes = self._write([batch for batch, _ in pending])
        for (_, future), outcome in zip(pending, outcomes, strict=True):
            if not future.done():  # a post whose client went away is cancelled
                future.set_result(outcome)

    def _write(self, batches: list[NewBatch]) -> list[Outcome]:
        """Store the batches with one commit; one outcome per batch, never an exception."""
        outcomes: list[Outcome | None] = [None] * len(batches)
        locked: dict[str, threading.Lock] = {}
        ready: list[int] = []
        try:
            for i, batch in enumerate(batches):
                if batch.run_id not in locked:
                    lock = self._run_lock(batch.run_id)
                    if not lock.acquire(blocking=False):
                        outcomes[i] = self._run_busy(batch.run_id)
                        continue
                    locked[batch.run_id] = lock
                ready.append(i)
            stored = self._store.append_many([batches[i] for i in ready])
            for i, outcome in zip(ready, stored, strict=True):
                outcomes[i] = outcome
        except Exception as exc:  # a bug: answer every post all the same
            log.exception("storing %d batches failed", len(batches))
            return [exc] * len(batches)
        finally:
            for lock in locked.values():
                lock.release()
        return [o for o in outcomes if o is not None]

    def _run_busy(self, run_id: str) -> ApiProblem:
        return ApiProblem(
            503,
            "Run is being ended",
            f"run {run_id} is being finished or aborted; retry in {self.retry_after} s",
            headers={"Retry-After": str(self.retry_after)},
        )
