"""A run file from elsewhere (the run file of an ``.eln`` archive): its run, and its batches
as :meth:`RunStore.import_run` takes them."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from rigserver.storage._checks import StoredBatch, prepare, stand_groups
from rigserver.storage._failures import UNREADABLE
from rigserver.storage.errors import RunDamaged
from rigserver.storage.runfile import FileSummary, RunFile, read_summary
from schemas.corrections import Correction
from schemas.runs import Run

#: Rows of a group per imported batch
IMPORT_ROWS = 1 << 20

#: A batch of :meth:`RunStore.import_run`: its seq, its receipt, every channel of its group.
ImportedBatch = tuple[int, StoredBatch, dict[str, NDArray[np.float64]]]


def file_corrections(path: Path) -> list[Correction]:
    """The corrections a run file holds; ``RunDamaged`` if they cannot be read."""
    try:
        with RunFile.open(path, writable=False) as rf:
            return rf.corrections()
    except UNREADABLE as exc:  # a pydantic ValidationError is a ValueError
        raise RunDamaged(f"{path.name}: its corrections cannot be read ({exc})") from None


def summary(path: Path) -> FileSummary:
    """The run, flags and results a run file holds; ``RunDamaged`` if it is no run file."""
    try:
        return read_summary(path)
    except UNREADABLE as exc:
        raise RunDamaged(f"{path.name} is not a readable run file: {exc}") from None


def file_batches(path: Path, run: Run, rows: int = IMPORT_ROWS) -> Iterator[ImportedBatch]:
    """The readings of the run file as batches (seq 0, 1, ...; at most ``rows`` rows of
    one group each, every channel, NaN where the file has it), group by group."""
    seq = 0
    with RunFile.open(path, writable=False) as rf:
        for decl in stand_groups(run.stand):
            stored = 0
            for start in range(0, rf.rows(decl.name), rows):
                columns = rf.read(decl.name, None, start, start + rows)
                batch = prepare(decl.name, columns)
                stored += batch.rows
                yield seq, StoredBatch(decl.name, batch.rows, stored, batch.digest), batch.columns
                seq += 1
