"""``rigserver migrate``: an embedded data directory moved into a cluster's PostgreSQL.

Each run goes over in one transaction (catalogue entry, results, Idempotency-Key and every
batch under its seq and digest, so a lab PC's retry of an old batch is still answered as
a duplicate), then is verified: the batch and row counts, and an XXH3-128 digest of every
channel group's values read back from the cluster against the same digest read from the
run's HDF5 file. A run already in the cluster is verified, not copied again: a migration
stopped at any moment is resumed by running it again. The embedded server must be stopped
(the data directory is opened, and locked, as a store).

A batch's readings are cut from the run file by its receipt's rows (``group_rows - rows``
to ``group_rows``), every channel of its group present (NaN where the batch had none, as
the file keeps them): what a read returns is the same.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xxhash
from numpy.typing import NDArray

from rigserver.storage._checks import StoredBatch, stand_groups
from rigserver.storage.base import RunStore
from rigserver.storage.cluster.postgres import PostgresStore
from rigserver.storage.embedded.hdf5 import HDF5Store
from schemas.runs import Run, RunQuery

#: Rows read from a run file at a time
_CHUNK_ROWS = 1 << 20
#: Runs listed at a time
_PAGE = 500


class MigrationMismatch(RuntimeError):
    """A run in the cluster differs from the one in the data directory."""


@dataclass(frozen=True, slots=True)
class Migrated:
    """What a migration did: runs copied, runs found there already (and verified)."""

    copied: int
    verified: int


def digest(store: RunStore, run: Run) -> str:
    """XXH3-128 of the run's readings: every group's channels, in declaration order."""
    h = xxhash.xxh3_128()
    for group in stand_groups(run.stand):
        h.update(group.name.encode() + b"\0")
        for chunk in store.iter_chunks(run.id, group.name, rows=_CHUNK_ROWS):
            for name, values in chunk.items():
                h.update(name.encode() + b"\0")
                h.update(np.ascontiguousarray(values, dtype="<f8").data)
    return h.hexdigest()


def _batches(
    source: HDF5Store, run: Run, history: list[tuple[int, StoredBatch]]
) -> Iterator[tuple[int, StoredBatch, dict[str, NDArray[np.float64]]]]:
    """The run's batches with their readings cut from its file, in the order stored."""
    cached: dict[str, tuple[int, dict[str, NDArray[np.float64]]]] = {}
    for seq, stored in history:
        start = stored.group_rows - stored.rows
        at, columns = cached.get(stored.group, (0, {}))
        length = len(next(iter(columns.values()))) if columns else 0
        if not (at <= start and stored.group_rows <= at + length):
            size = max(_CHUNK_ROWS, stored.rows)
            columns = source.read(run.id, stored.group, None, start, start + size)
            at = start
            cached[stored.group] = (at, columns)
        cut = {n: v[start - at : stored.group_rows - at] for n, v in columns.items()}
        yield seq, stored, cut


def _verify(source: HDF5Store, target: PostgresStore, run: Run) -> None:
    there = target.get_run(run.id)
    if (there.batches, there.rows, there.state) != (run.batches, run.rows, run.state):
        raise MigrationMismatch(
            f"run {run.id}: {there.batches} batches, rows {there.rows}, {there.state.value} in "
            f"the cluster; {run.batches}, {run.rows}, {run.state.value} in the data directory"
        )
    if digest(target, run) != digest(source, run):
        raise MigrationMismatch(f"run {run.id}: the readings in the cluster differ")
    if target.corrections(run.id) != source.corrections(run.id):
        raise MigrationMismatch(f"run {run.id}: the corrections in the cluster differ")


def migrate(
    data_dir: Path, target: PostgresStore, progress: Callable[[str], None] = lambda _: None
) -> Migrated:
    """Copy every run of ``data_dir`` into ``target`` and verify it (module docstring)."""
    copied = verified = 0
    with HDF5Store(data_dir) as source:
        offset = 0
        while True:
            page = source.list_runs(RunQuery(limit=_PAGE, offset=offset)).runs
            if not page:
                break
            offset += len(page)
            for run in page:
                key, history = source.history(run.id)
                batches = _batches(source, run, history)
                fixes = source.corrections(run.id)
                if target.import_run(run, key, source.results(run.id), batches, fixes):
                    copied += 1
                    what = "copied"
                else:
                    verified += 1
                    what = "there already"
                _verify(source, target, run)
                progress(f"{run.id}: {what}, {run.batches} batches, verified")
    return Migrated(copied=copied, verified=verified)
