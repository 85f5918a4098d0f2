"""The narrow interface every run store implements (HDF5 on local disk, in memory, HSDS).

A store keeps runs (metadata as :class:`schemas.runs.Run`) and their readings, as columns
per channel group. :meth:`RunStore.append` returns only once the batch is durable, and is
idempotent per ``(run_id, seq)``.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from schemas.readings import BatchReceipt
from schemas.runs import Run, RunPage, RunQuery, RunState

Columns = Mapping[str, NDArray[np.float64]]


class RunStore(Protocol):
    def create_run(self, run: Run) -> Run:
        """Store a new open run; raises ``RunExists`` if the id is taken."""
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

    def end_run(self, run_id: str, state: RunState) -> Run:
        """Finish or abort an open run: the run file is finalized; no more readings."""
        ...

    def run_file(self, run_id: str) -> Path:
        """Path of a consistent HDF5 file of the run (a snapshot for an open run)."""
        ...

    def close(self) -> None:
        """Flush and release everything; the store can be opened again later."""
        ...
