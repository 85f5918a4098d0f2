"""The report renders of one service: a bounded pool of their own, shared fairly between keys.

Rendering a report is CPU-bound Python (the plots, then WeasyPrint's layout: seconds for a
PDF). Done in the service's threads it held the GIL from ingest and cheap reads: 8 clients
of one read key looping on a report raised the p99 of ``/api/v1/stands`` from 8 ms to
0.9 s, and 48 PDFs at once made ``POST /runs`` take 8.8 s (issue 22, item 9). So renders run
in a pool of their own: ``workers`` processes (the reports of ended runs, read from their
final files) and as many threads (those of open runs, whose readings only the store has).

Admission: at most ``queue`` renders are admitted at once (running or waiting), and one
key (its fingerprint; a caller without a key by its address) at most its ``share`` of them;
a request that would start one more is answered 503 with ``Retry-After``. A render asked
for again while it runs is joined, not started twice. Each report is rendered once per
version (:mod:`rigserver.api.report_files`); afterwards it is a file, served without the
pool. Renders in the background (a finished run's reports) take a free place or none.

A failed render is logged in one line, without the renderer's own messages
(:func:`~rigserver.api.report_jobs.quiet_renderer_logs`). A render process that ends
abruptly (killed for memory, or by a signal to the whole process group as the server
stops) breaks its executor for good: the next render starts a new one.
"""

from __future__ import annotations

import contextlib
import logging
import multiprocessing
import threading
from collections.abc import Callable
from concurrent.futures import Executor, Future, ProcessPoolExecutor, ThreadPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass

from rigserver.api.places import Busy, FairPlaces
from rigserver.api.report_jobs import (
    Job,
    quiet_renderer_logs,
    render_job,
    render_process_started,
    warm_up,
)

log = logging.getLogger("rigserver")

#: The key of the renders a finished run starts by itself.
BACKGROUND = "(background)"


@dataclass(frozen=True, slots=True)
class Admission:
    """How many renders are admitted now, in all and per key."""

    renders: int
    by_key: dict[str, int]


class RenderPool:
    """Bounded, fair report renders (see the module docstring)."""

    def __init__(
        self, *, workers: int, queue: int, share: float, retry_after: int, processes: bool
    ) -> None:
        self.workers = workers
        self._places = FairPlaces(
            queue=queue,
            share=share,
            retry_after=retry_after,
            busy=Busy(
                "Reports are being rendered",
                "the server renders at most {queue} reports at once and all places are taken",
                "one key may have at most {per_key} reports rendered at once",
                note=" (a report rendered once is kept)",
            ),
        )
        self._use_processes = processes
        self._lock = threading.Lock()
        self._flights: dict[str, Future[None]] = {}
        self._threads = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="reports")
        self._processes: ProcessPoolExecutor | None = None
        quiet_renderer_logs()

    @property
    def admitted(self) -> Admission:
        held = self._places.held
        return Admission(sum(held.values()), held)

    def render(self, name: str, key: str, job: Job, *, in_process: bool) -> Future[None]:
        """Render ``job`` (named ``name``: its first target) for the caller ``key``; joins a
        render of ``name`` under way. 503 beyond the pool's or the key's share."""
        future = self._admit(name, key, job, in_process=in_process, background=False)
        assert future is not None
        return future

    def render_later(self, name: str, job: Job, *, in_process: bool) -> Future[None] | None:
        """Start ``job`` in the background if there is room (None if there is not)."""
        return self._admit(name, BACKGROUND, job, in_process=in_process, background=True)

    def soon(self, what: str, task: Callable[[], None]) -> None:
        """Run ``task`` (scheduling background renders) in the pool's threads, off the
        caller's request; a failure is logged in one line."""

        def run() -> None:
            try:
                task()
            except Exception as exc:
                log.error("%s failed: %s: %s", what, type(exc).__name__, exc)

        with contextlib.suppress(RuntimeError):  # the pool is closed: the server stops
            self._threads.submit(run)

    def warm_up(self) -> None:
        """Start the render process now and load the renderer in it, so that the first
        report of an ended run does not wait for that (threads need nothing: the service
        loads the renderer at the first render of an open run)."""
        if not self._use_processes:
            return
        with self._lock:
            if self._processes is not None:  # started already, by a render
                return
            executor = self._executor(in_process=False)
        try:
            task = executor.submit(warm_up)
        except (RuntimeError, BrokenProcessPool):  # closed meanwhile: the server stops
            return
        task.add_done_callback(lambda done: self._warmed(done, executor))

    def close(self) -> None:
        """Stop taking renders; those under way finish (a process pool's workers exit)."""
        self._threads.shutdown(wait=False, cancel_futures=True)
        with self._lock:
            processes, self._processes = self._processes, None
        if processes is not None:
            processes.shutdown(wait=True, cancel_futures=True)

    def _admit(
        self, name: str, key: str, job: Job, *, in_process: bool, background: bool
    ) -> Future[None] | None:
        with self._lock:
            flight = self._flights.get(name)
            if flight is not None:
                return flight
            refusal = self._places.claim(key)
            if refusal is not None:
                if background:
                    return None
                raise refusal
            flight = self._flights[name] = Future()
            executor = self._executor(in_process)
        try:
            try:
                task = executor.submit(render_job, job)
            except BrokenProcessPool:  # its process ended since: a new one takes the job
                self._drop(executor)
                with self._lock:
                    executor = self._executor(in_process)
                task = executor.submit(render_job, job)
        except BaseException:
            self._release(name, key)
            raise
        task.add_done_callback(lambda done: self._finished(name, key, done, flight, executor))
        return flight

    def _executor(self, in_process: bool) -> Executor:
        """The threads (an open run's job), or the processes, started when first needed
        (locked)."""
        if in_process or not self._use_processes:
            return self._threads
        if self._processes is None:
            self._processes = ProcessPoolExecutor(
                max_workers=self.workers,
                mp_context=multiprocessing.get_context("spawn"),
                initializer=render_process_started,
            )
        return self._processes

    def _finished(
        self, name: str, key: str, done: Future[None], flight: Future[None], executor: Executor
    ) -> None:
        self._release(name, key)
        exc = done.exception() if not done.cancelled() else RuntimeError("render cancelled")
        if exc is None:
            flight.set_result(None)
            return
        if isinstance(exc, BrokenProcessPool):
            self._drop(executor)
            log.warning("rendering %s stopped: its render process ended abruptly", name)
        else:
            log.error("rendering %s failed: %s: %s", name, type(exc).__name__, exc)
        flight.set_exception(exc)

    def _warmed(self, done: Future[None], executor: Executor) -> None:
        """A process that ended while warming up (the server stopping) is dropped quietly:
        the next render starts another; another failure is logged in one line."""
        exc = done.exception() if not done.cancelled() else None
        if isinstance(exc, BrokenProcessPool):
            self._drop(executor)
        elif exc is not None:
            log.warning("loading the report renderer failed: %s: %s", type(exc).__name__, exc)

    def _drop(self, executor: Executor) -> None:
        """Forget a broken process executor: the next render of an ended run starts another."""
        with self._lock:
            if self._processes is executor:
                self._processes = None
        executor.shutdown(wait=False, cancel_futures=True)

    def _release(self, name: str, key: str) -> None:
        with self._lock:
            self._flights.pop(name, None)
            self._places.release(key)
