"""Results of runs: computed once per readings version, shared, and bounded (issue 14).

An open run's results are a function of its readings, and the catalogue counts the batches
stored for each run: ``readings_version(run)`` (that count and the rows per group) names
what a computation saw. The cache keeps the last results of the ``runs`` most recently
asked-for runs with their version and hands them out while the run's version is the same,
so a run's live page polling every few seconds costs a catalogue look-up, not an analysis.
Another process that shares the catalogue (several servers in front of one store) sees the
version change with the next batch and so never serves stale results.

Computations run on a pool of ``workers`` threads (off the event loop), one per (run,
version): concurrent requests for the same results wait for that one. When every worker
is busy with other runs, a request that would start one more is answered 503 with
Retry-After, so a few read keys asking for many cold results cannot occupy the server.
Finishing a run (:meth:`ResultsCache.for_finish`) is not admitted that way: it takes the
cached results when they are current, joins a computation under way, or computes in its
own thread (the run's lock keeps it to one finish).
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

from rigserver.analysis import AnalysisResult
from rigserver.api.problems import ApiProblem
from schemas.runs import Run

#: What a computation of a run's results saw: its batches stored, its corrections of them
#: and rows per group.
Version = tuple[int, int, tuple[tuple[str, int], ...]]


def readings_version(run: Run) -> Version:
    """The version of ``run``'s readings, from its catalogue entry: it changes with every
    batch stored (measurements included) and every correction."""
    return run.batches, run.corrections, tuple(sorted(run.rows.items()))


@dataclass(frozen=True)
class Computed:
    """A run's results at one readings version, with their wire payload made once."""

    version: Version
    result: AnalysisResult
    payload: dict[str, Any] = field(repr=False)

    @property
    def key_results(self) -> dict[str, float]:
        return self.result.key_results


class ResultsCache:
    """Results by run and readings version; one computation per version; ``workers`` at once."""

    def __init__(self, *, workers: int, runs: int, retry_after: int) -> None:
        self.workers = workers
        self._runs = runs
        self._retry_after = retry_after
        self._pool = ThreadPoolExecutor(max_workers=workers, thread_name_prefix="results")
        self._lock = threading.Lock()
        self._done: OrderedDict[str, Computed] = OrderedDict()
        self._flights: dict[tuple[str, Version], Future[Computed]] = {}

    def submit(self, run: Run, compute: Callable[[], AnalysisResult]) -> Future[Computed]:
        """The results of ``run`` as they are now: done when cached, else the computation
        of this version (started here if none is under way). 503 when every worker is busy.
        """
        version = readings_version(run)
        with self._lock:
            found = self._current(run.id, version)
            if found is not None:
                return found
            if len(self._flights) >= self.workers:
                raise ApiProblem(
                    503,
                    "Results are being computed",
                    f"the server computes the results of {self.workers} runs at once and "
                    f"all are busy; retry in {self._retry_after} s",
                    headers={"Retry-After": str(self._retry_after)},
                )
            flight: Future[Computed] = Future()
            self._flights[(run.id, version)] = flight
        self._pool.submit(self._fly, run.id, version, compute, flight)
        return flight

    def for_finish(self, run: Run, compute: Callable[[], AnalysisResult]) -> Computed:
        """The results a finish stores: cached if current, else the computation under way,
        else computed now, in the caller's thread (no admission limit: one per run)."""
        version = readings_version(run)
        with self._lock:
            found = self._current(run.id, version)
            flight = found
            if flight is None:
                flight = Future()
                self._flights[(run.id, version)] = flight
                mine = True
            else:
                mine = False
        if mine:
            self._fly(run.id, version, compute, flight)
        return flight.result()

    def close(self) -> None:
        """Stop taking computations; those under way finish in their threads."""
        self._pool.shutdown(wait=False, cancel_futures=True)

    def _current(self, run_id: str, version: Version) -> Future[Computed] | None:
        """A done future with the cached results, or the flight of this version (locked)."""
        cached = self._done.get(run_id)
        if cached is not None and cached.version == version:
            self._done.move_to_end(run_id)
            done: Future[Computed] = Future()
            done.set_result(cached)
            return done
        return self._flights.get((run_id, version))

    def _fly(
        self,
        run_id: str,
        version: Version,
        compute: Callable[[], AnalysisResult],
        flight: Future[Computed],
    ) -> None:
        try:
            result = compute()
            computed = Computed(version, result, result.payload)
        except BaseException as exc:
            with self._lock:
                del self._flights[(run_id, version)]
            flight.set_exception(exc)
            if not isinstance(exc, Exception):
                raise
            return
        with self._lock:
            del self._flights[(run_id, version)]
            cached = self._done.get(run_id)
            if cached is None or cached.version[0] <= version[0]:
                self._done[run_id] = computed
                self._done.move_to_end(run_id)
                while len(self._done) > self._runs:
                    self._done.popitem(last=False)
        flight.set_result(computed)
