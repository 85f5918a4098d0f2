"""The bridge from a stored run to its stand's analysis: the store seen as the run's readings."""

from __future__ import annotations

import asyncio
from collections.abc import Iterator
from concurrent.futures import Future
from typing import Any

import numpy as np
from fastapi.concurrency import run_in_threadpool
from numpy.typing import NDArray

from rigserver.analysis import AnalysisResult, Readings, analyse
from rigserver.api.deps import Services
from rigserver.api.results_cache import Computed
from rigserver.storage.corrections import CorrectedReadings
from rigserver.storage.errors import RunNotFound
from schemas.runs import Run, RunState
from schemas.stands import MEASUREMENTS


class StoredReadings(CorrectedReadings):
    """One run's readings in the store, as the analysis asks for them: as corrected (the
    corrections applied, the struck rows left out), or as typed if ``original``."""

    def __init__(self, services: Services, run: Run, *, original: bool = False) -> None:
        fixes = [] if original or not run.corrections else services.store.corrections(run.id)
        super().__init__(_StoreRows(services, run), fixes)


class _StoreRows:
    """One run's readings as the store keeps them (as typed)."""

    def __init__(self, services: Services, run: Run) -> None:
        self._store = services.store
        self._run = run

    def rows(self, group: str) -> int:
        return self._run.rows.get(group, 0)

    def read(self, group: str, channels: list[str] | None = None) -> dict[str, NDArray[np.float64]]:
        if self.rows(group) == 0:
            return {}
        return self._store.read(self._run.id, group, channels)

    def iter_chunks(
        self, group: str, channels: list[str] | None = None, rows: int = 1 << 20
    ) -> Iterator[dict[str, NDArray[np.float64]]]:
        if self.rows(group) == 0:
            return iter(())
        return self._store.iter_chunks(self._run.id, group, channels, rows)

    def measurements(self) -> dict[str, float]:
        if self.rows(MEASUREMENTS) == 0:
            return {}
        return self._store.last_values(self._run.id, MEASUREMENTS)


def compute_results(services: Services, run: Run) -> AnalysisResult:
    """The stand's results on what the run holds now (all of it once finished)."""
    return analyse(run, StoredReadings(services, run), lambda run_id: _lookup(services, run_id))


def _lookup(services: Services, run_id: str) -> tuple[Run, Readings] | None:
    """Another run of the store and its readings (the profilometer runs a run names)."""
    try:
        other = services.store.get_run(run_id)
    except RunNotFound:
        return None
    return other, StoredReadings(services, other)


def stored_results(services: Services, run: Run) -> dict[str, Any] | None:
    """The results stored when the run finished; None for a run that has not."""
    return services.store.results(run.id) if run.state is RunState.FINISHED else None


def submit_results(services: Services, run: Run) -> Future[Computed]:
    """The results on what has arrived: cached, shared or started (rigserver.api.results_cache);
    503 when the server computes as many runs' results as it may."""
    return services.results.submit(run, lambda: compute_results(services, run))


def results_payload(services: Services, run: Run) -> dict[str, Any]:
    """The results stored when the run finished, or those on what has arrived (blocks)."""
    stored = stored_results(services, run)
    if stored is not None:
        return stored
    return submit_results(services, run).result().payload


async def results_payload_async(services: Services, run: Run) -> dict[str, Any]:
    """:func:`results_payload` that waits for a computation without holding a thread."""
    stored = await run_in_threadpool(stored_results, services, run)
    if stored is not None:
        return stored
    computed = await asyncio.wrap_future(submit_results(services, run))
    return computed.payload
