"""The :class:`~rigserver.storage.base.RunStore` methods that follow from a store's others,
the same for every store."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
from numpy.typing import NDArray

from rigserver.storage._checks import channel_group, channel_names
from rigserver.storage.base import Columns, NewBatch, RunStore
from schemas.readings import BatchReceipt


class Derived:
    """:meth:`RunStore.append`, :meth:`RunStore.iter_chunks` and
    :meth:`RunStore.readings_version` of a store: one batch stored as its
    :meth:`~RunStore.append_many` stores it, the readings read in its :meth:`~RunStore.read`
    slices, the version counted in its catalogue entry (:meth:`~RunStore.get_run`)."""

    def append(self: RunStore, run_id: str, seq: int, group: str, columns: Columns) -> BatchReceipt:
        """Store one batch as :meth:`append_many` does; raise what refuses it."""
        (outcome,) = self.append_many([NewBatch(run_id, seq, group, columns)])
        if isinstance(outcome, Exception):
            raise outcome
        return outcome

    def iter_chunks(
        self: RunStore,
        run_id: str,
        group: str,
        channels: list[str] | None = None,
        rows: int = 1 << 20,
    ) -> Iterator[dict[str, NDArray[np.float64]]]:
        """The rows stored when called, in consecutive :meth:`read` slices of at most ``rows``
        rows."""
        if rows < 1:
            raise ValueError(f"rows must be >= 1, not {rows}")
        run = self.get_run(run_id)
        channel_names(channel_group(run.stand, group), channels)
        total = run.rows.get(group, 0)
        return (
            self.read(run_id, group, channels, start, min(start + rows, total))
            for start in range(0, total, rows)
        )

    def readings_version(self: RunStore, run_id: str) -> int:
        """The run's batches and corrections in its catalogue entry, as every process sharing
        the store sees them once committed."""
        run = self.get_run(run_id)
        return run.batches + run.corrections
