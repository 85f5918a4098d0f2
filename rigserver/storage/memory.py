"""MemoryStore: the run store in memory, for tests of the API and the analysis.

It makes the same checks and gives the same receipts as :class:`HDF5Store` (both use
:mod:`rigserver.storage._checks`), and :meth:`MemoryStore.run_file` writes a real run file
(:mod:`rigserver.storage.runfile`) into a temporary directory. Nothing survives the process.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import threading
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rigserver.storage._checks import (
    StoredBatch,
    channel_group,
    channel_names,
    check,
    last_finite,
    new_run,
    padded,
    posted,
    reopened,
    retry_receipt,
    stored_receipt,
)
from rigserver.storage._derived import Derived
from rigserver.storage._results import CheckedResults, check_results
from rigserver.storage._time import as_utc, now
from rigserver.storage.base import NewBatch
from rigserver.storage.corrections import (
    RowEdit,
    RowEdits,
    corrected_row,
    corrected_run,
    new_corrections,
)
from rigserver.storage.errors import RunExists, RunNotFound, RunNotOpen
from rigserver.storage.runfile import write_file
from rigserver.storage.waiters import AppendWaiters, TellsInProcess
from schemas.corrections import CorrectedRow, Correction
from schemas.readings import BatchReceipt
from schemas.runs import Run, RunPage, RunQuery, RunState


@dataclass(slots=True)
class _Run:
    run: Run
    batches: dict[int, StoredBatch] = field(default_factory=dict)
    #: group -> channel -> the values, in parts (joined when read)
    columns: dict[str, dict[str, list[NDArray[np.float64]]]] = field(default_factory=dict)
    results: CheckedResults | None = None
    corrections: list[Correction] = field(default_factory=list)

    def values(self, group: str, channel: str) -> NDArray[np.float64]:
        parts = self.columns.get(group, {}).get(channel)
        if not parts:
            return np.empty(0)
        if len(parts) > 1:
            parts[:] = [np.concatenate(parts)]
        return parts[0]


class MemoryStore(Derived, RowEdits, TellsInProcess):
    """The :class:`~rigserver.storage.base.RunStore` protocol in memory; thread-safe."""

    def __init__(self) -> None:
        self._lock = threading.RLock()
        self._runs: dict[str, _Run] = {}
        #: Idempotency-Key -> the run opened with it
        self._keys: dict[str, str] = {}
        self._dir: Path | None = None
        #: the live streams waiting for a run's next batch
        self.appends = AppendWaiters()

    def _get(self, run_id: str) -> _Run:
        found = self._runs.get(run_id)
        if found is None:
            raise RunNotFound(f"no run with id {run_id}")
        return found

    def create_run(self, run: Run, key: str | None = None) -> Run:
        stored = new_run(run)
        with self._lock:
            if key is not None and key in self._keys:
                return reopened(self._get(self._keys[key]).run, stored, key).model_copy(deep=True)
            if run.id in self._runs:
                raise RunExists(f"a run with id {run.id} is stored already")
            self._runs[run.id] = _Run(stored)
            if key is not None:
                self._keys[key] = run.id
            return stored.model_copy(deep=True)

    def get_run(self, run_id: str) -> Run:
        with self._lock:
            return self._get(run_id).run.model_copy(deep=True)

    def list_runs(self, query: RunQuery) -> RunPage:
        """Runs matching the query, newest first (``since <= created < until``)."""
        with self._lock:
            runs = [r.run for r in self._runs.values() if _matches(r.run, query)]
        runs.sort(key=lambda r: (as_utc(r.created), r.id), reverse=True)
        page = runs[query.offset : query.offset + query.limit]
        return RunPage(total=len(runs), runs=[r.model_copy(deep=True) for r in page])

    def append_many(self, batches: Sequence[NewBatch]) -> list[BatchReceipt | Exception]:
        outcomes: list[BatchReceipt | Exception] = []
        with self._lock:
            for nb in batches:
                try:
                    outcomes.append(self._append(nb))
                except Exception as exc:
                    outcomes.append(exc)
            grown = {
                o.run_id: self._runs[o.run_id].run.batches
                for o in outcomes
                if isinstance(o, BatchReceipt) and not o.duplicate
            }
        for run_id, count in grown.items():
            self.appends.woken(run_id, count)
        return outcomes

    def _append(self, nb: NewBatch) -> BatchReceipt:
        run_id, seq, group = nb.run_id, nb.seq, nb.group
        batch = posted(nb)
        stored_run = self._get(run_id)
        stored = stored_run.batches.get(seq)
        if stored is not None:
            return retry_receipt(run_id, seq, stored, batch)
        run = stored_run.run
        if run.state is not RunState.OPEN:
            raise RunNotOpen(f"run {run_id} is {run.state.value}: it takes no more readings")
        if nb.check is not None:
            nb.check(batch.columns, self.last_values(run_id, group))
        decl = check(run.stand, batch)
        group_rows = run.rows.get(group, 0) + batch.rows
        stored = StoredBatch(group, batch.rows, group_rows, batch.digest)
        stored_run.batches[seq] = stored
        channels = stored_run.columns.setdefault(group, {})
        for name, values in padded(decl, batch.columns, batch.rows).items():
            channels.setdefault(name, []).append(values)
        run.rows = {**run.rows, group: group_rows}
        run.batches += 1
        return stored_receipt(run_id, seq, stored, duplicate=False)

    def receipt(self, run_id: str, seq: int) -> BatchReceipt | None:
        with self._lock:
            stored = self._get(run_id).batches.get(seq)
        return None if stored is None else stored_receipt(run_id, seq, stored, duplicate=True)

    def last_values(self, run_id: str, group: str) -> dict[str, float]:
        with self._lock:
            stored_run = self._get(run_id)
            decl = channel_group(stored_run.run.stand, group)
            found: dict[str, float] = {}
            for ch in decl.channels:
                for part in reversed(stored_run.columns.get(group, {}).get(ch.name, [])):
                    value = last_finite(part)
                    if value is not None:
                        found[ch.name] = value
                        break
            return found

    def read(
        self,
        run_id: str,
        group: str,
        channels: list[str] | None = None,
        start: int = 0,
        stop: int | None = None,
    ) -> dict[str, NDArray[np.float64]]:
        with self._lock:
            stored_run = self._get(run_id)
            names = channel_names(channel_group(stored_run.run.stand, group), channels)
            lo, hi, _ = slice(start, stop).indices(stored_run.run.rows.get(group, 0))
            return {n: stored_run.values(group, n)[lo:hi].copy() for n in names}

    def corrections(self, run_id: str) -> list[Correction]:
        with self._lock:
            return list(self._get(run_id).corrections)

    def _edit(self, run_id: str, edit: RowEdit) -> CorrectedRow:
        group, index = edit.group, edit.index
        with self._lock:
            stored_run = self._get(run_id)
            run = stored_run.run

            def read(lo: int, hi: int) -> dict[str, NDArray[np.float64]]:
                return self.read(run_id, group, None, lo, hi)

            earlier = stored_run.corrections
            new = new_corrections(run, edit, now(), read, earlier)
            stored_run.corrections = every = [*earlier, *new]
            if new:
                stored_run.run = run = corrected_run(run, every)
            row = read(index, index + 1)
        if new:  # the live streams tell their viewers
            self.appends.woken(run_id, run.batches)
        return corrected_row(run_id, group, index, row, every)

    def set_results(
        self, run_id: str, results: Mapping[str, Any], key_results: Mapping[str, float]
    ) -> None:
        checked = check_results(results, key_results)
        with self._lock:
            stored_run = self._get(run_id)
            stored_run.results = checked
            stored_run.run.key_results = dict(checked.key_results)

    def results(self, run_id: str) -> dict[str, Any] | None:
        with self._lock:
            checked = self._get(run_id).results
        return None if checked is None else dict(json.loads(checked.text))

    def end_run(self, run_id: str, state: RunState) -> Run:
        if state is RunState.OPEN:
            raise ValueError("a run can end as finished or aborted, not open")
        with self._lock:
            stored_run = self._get(run_id)
            run = stored_run.run
            if run.state is not RunState.OPEN:
                raise RunNotOpen(f"run {run_id} is already {run.state.value}")
            run.state = state
            run.ended = now()
            ended = run.model_copy(deep=True)
        self.appends.ended(run_id)
        return ended

    def import_run(
        self,
        run: Run,
        key: str | None,
        results: Mapping[str, Any] | None,
        batches: Iterable[tuple[int, StoredBatch, Mapping[str, NDArray[np.float64]]]],
        corrections: Sequence[Correction] = (),
    ) -> bool:
        """Store a run made elsewhere whole (:meth:`RunStore.import_run`): gathered first,
        then put in the store at once."""
        checked = None if results is None else check_results(results, run.key_results)
        imported = _Run(run.model_copy(deep=True), results=checked, corrections=[*corrections])
        for seq, stored, columns in batches:
            imported.batches[seq] = stored
            group = imported.columns.setdefault(stored.group, {})
            for name, values in columns.items():
                group.setdefault(name, []).append(np.array(values, dtype=np.float64))
        with self._lock:
            if run.id in self._runs:
                return False
            self._runs[run.id] = imported
            if key is not None:
                self._keys[key] = run.id
        return True

    def run_file(self, run_id: str) -> Path:
        """A run file written now into this store's temporary directory."""
        with self._lock:
            stored_run = self._get(run_id)
            run = stored_run.run.model_copy(deep=True)
            groups = {
                g: {n: stored_run.values(g, n) for n in channels}
                for g, channels in stored_run.columns.items()
            }
            if self._dir is None:
                self._dir = Path(tempfile.mkdtemp(prefix="rig-memory-store-"))
            path = self._dir / f"{run_id}.h5"
            written = path.with_name(f"{run_id}.{threading.get_ident()}.tmp")
            batches = [(g, cols, run.rows[g]) for g, cols in groups.items()]
            final = run.state is not RunState.OPEN
            write_file(
                written,
                run,
                batches,
                stored_run.results,
                final=final,
                corrections=list(stored_run.corrections),
            )
            os.replace(written, path)  # a reader of the file before keeps reading it whole
            return path

    def close(self) -> None:
        """Remove the files :meth:`run_file` wrote; the runs stay (in memory)."""
        with self._lock:
            if self._dir is not None:
                shutil.rmtree(self._dir, ignore_errors=True)
                self._dir = None


def _matches(run: Run, query: RunQuery) -> bool:
    return (
        (query.stand is None or run.stand is query.stand)
        and (query.operator is None or run.operator == query.operator)
        and (query.state is None or run.state is query.state)
        and (query.since is None or as_utc(run.created) >= as_utc(query.since))
        and (query.until is None or as_utc(run.created) < as_utc(query.until))
    )
