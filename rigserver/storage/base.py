"""The narrow interface every run store implements: the embedded store (SQLite and HDF5 on
local disk, :mod:`rigserver.storage.embedded`), a cluster's (PostgreSQL, with HSDS for the
run arrays, :mod:`rigserver.storage.cluster`) and the in-memory store of the tests.

A store keeps runs (metadata as :class:`schemas.runs.Run`) and their readings, as columns
per channel group. :meth:`RunStore.append` returns only once the batch is durable, and is
idempotent per ``(run_id, seq)``; :meth:`RunStore.append_many` stores several batches with
one commit (group commit).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from schemas.corrections import CorrectedRow, Correction
from schemas.readings import BatchReceipt
from schemas.runs import Run, RunPage, RunQuery, RunState

if TYPE_CHECKING:
    from rigserver.storage._checks import StoredBatch

Columns = Mapping[str, NDArray[np.float64]]
#: Called with a batch's columns (float64) and the last stored value of each channel of its
#: group, just before the batch is stored; raises to refuse the batch.
BatchCheck = Callable[[Columns, Mapping[str, float]], None]


@dataclass(frozen=True, slots=True)
class NewBatch:
    """One batch for :meth:`RunStore.append_many`.

    ``check`` is not called for a retry (a ``seq`` stored before), which is answered with
    its first receipt; it sees the last values left by the batches before it in the call.
    """

    run_id: str
    seq: int
    group: str
    columns: Mapping[str, ArrayLike]
    check: BatchCheck | None = None


class LiveStore(Protocol):
    """What a live stream (``/runs/{id}/live``) waits on: the store tells when a batch of a
    run is stored or the run ends. Every run store is one: the embedded and in-memory stores
    tell in process (:mod:`rigserver.storage.waiters`), a cluster's by PostgreSQL's
    LISTEN/NOTIFY (:mod:`rigserver.storage.cluster.notify`)."""

    #: A notification may be lost (a cluster's listener reconnecting): a stream then reads
    #: the catalogue again now and then instead of trusting the silence.
    appends_lossy: bool

    async def wait_for_appends(self, run_id: str, batches: int, timeout: float) -> bool:
        """Until the run has more than ``batches`` batches stored or has ended: True when
        told, False after ``timeout`` seconds."""
        ...

    def wake_waiters(self) -> None:
        """Wake every stream waiting (the server is stopping)."""
        ...


class RunStore(LiveStore, Protocol):
    def create_run(self, run: Run, key: str | None = None) -> Run:
        """Store a new open run; raises ``RunExists`` if the id is taken.

        ``key`` is the client's Idempotency-Key: if a run was opened with it before, that
        run is returned and nothing is stored (``KeyReused`` if ``run`` asks for another
        stand, operator, title, specimen, plan, notes or configuration)."""
        ...

    def get_run(self, run_id: str) -> Run:
        """The run's metadata, state and row counts; raises ``RunNotFound``."""
        ...

    def list_runs(self, query: RunQuery) -> RunPage:
        """Runs matching the query, newest first, from the catalogue."""
        ...

    def append(self, run_id: str, seq: int, group: str, columns: Columns) -> BatchReceipt:
        """Store one checked batch durably; the same ``seq`` again returns the first receipt
        with ``duplicate=True`` (``SequenceConflict`` if its content differs)."""
        ...

    def append_many(self, batches: Sequence[NewBatch]) -> list[BatchReceipt | Exception]:
        """Store the batches in order, durably, with one commit; one outcome per batch: its
        receipt, or the exception that refused it (the others are stored all the same)."""
        ...

    def receipt(self, run_id: str, seq: int) -> BatchReceipt | None:
        """The receipt of the batch stored under ``seq`` (``duplicate=True``), or ``None``."""
        ...

    def last_values(self, run_id: str, group: str) -> dict[str, float]:
        """The last stored value of each channel of ``group`` (empty if none)."""
        ...

    def read(
        self,
        run_id: str,
        group: str,
        channels: list[str] | None = None,
        start: int = 0,
        stop: int | None = None,
    ) -> dict[str, NDArray[np.float64]]:
        """Rows ``start:stop`` of the group's channels (all channels if ``None``)."""
        ...

    def iter_chunks(
        self, run_id: str, group: str, channels: list[str] | None = None, rows: int = 1 << 20
    ) -> Iterator[dict[str, NDArray[np.float64]]]:
        """The group's channels in consecutive slices of at most ``rows`` rows."""
        ...

    def set_results(
        self, run_id: str, results: Mapping[str, Any], key_results: Mapping[str, float]
    ) -> None:
        """Store the analysis results (JSON-able, with units) and the headline figures."""
        ...

    def results(self, run_id: str) -> dict[str, Any] | None:
        """The results stored by :meth:`set_results`, or ``None``."""
        ...

    def correct_reading(
        self,
        run_id: str,
        group: str,
        index: int,
        values: Mapping[str, float],
        reason: str,
        by: str,
    ) -> CorrectedRow:
        """Correct cells of row ``index`` (as stored, from 0) of ``group``: each cell's value
        before and after, ``reason`` and ``by`` (the key's name) are kept beside the values
        as typed, durably before this returns; the row as it now reads. Checked as a post
        is (the channels' limits in the run's units, a known channel, the index in range,
        a reason of 1-500 characters): ``CorrectionRefused`` naming the field; a row that
        already reads so stores nothing. Any state of the run (its results are the
        caller's to compute again). ``RunNotFound``."""
        ...

    def strike_reading(
        self, run_id: str, group: str, index: int, reason: str, by: str
    ) -> CorrectedRow:
        """Strike row ``index`` of ``group`` out of the corrected readings, kept as typed
        (as :meth:`correct_reading`; a row struck out before stores nothing)."""
        ...

    def corrections(self, run_id: str) -> list[Correction]:
        """The run's corrections in the order made; ``RunNotFound``."""
        ...

    def end_run(self, run_id: str, state: RunState) -> Run:
        """Finish or abort an open run: the run file is finalized; no more readings."""
        ...

    def run_file(self, run_id: str) -> Path:
        """Path of a consistent HDF5 file of the run (a snapshot for an open run)."""
        ...

    def import_run(
        self,
        run: Run,
        key: str | None,
        results: Mapping[str, Any] | None,
        batches: Iterable[tuple[int, StoredBatch, Mapping[str, NDArray[np.float64]]]],
        corrections: Sequence[Correction] = (),
    ) -> bool:
        """Store a run made elsewhere whole, all or nothing: its catalogue entry as it is
        (state, times, counters, results), its batches (seq, receipt, every channel of
        the group) in the order given and its corrections; False, and nothing stored, if
        its id is taken. An exception raised by ``batches`` stores nothing."""
        ...

    def readings_version(self, run_id: str) -> int:
        """A number that grows whenever a batch or a correction of the run is stored, by any
        process sharing the store (the run's batches and corrections; a retry changes
        nothing): a results cache keyed by it sees that it is stale. ``RunNotFound``."""
        ...

    def close(self) -> None:
        """Flush and release everything; the store can be opened again later."""
        ...
