"""Group commit in the embedded store: the batches of one call staged in one journal
transaction and committed together, then handed to their run files (or to a file's backlog,
:mod:`~rigserver.storage.embedded.backlog`). A batch is durable, and acknowledged, once the
journal has committed; the file only follows it.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rigserver.storage._checks import (
    Batch,
    StoredBatch,
    check,
    last_finite,
    padded,
    posted_or_refusal,
    retry_receipt,
    stored_receipt,
)
from rigserver.storage._failures import LOW_LEVEL, failures_as, translated
from rigserver.storage.base import NewBatch
from rigserver.storage.embedded.backlog import MAX_BACKLOG_BYTES, Owed, WhenQuiet
from rigserver.storage.embedded.journal import Journal, payload_of
from rigserver.storage.embedded.views import Live, RunFiles
from rigserver.storage.errors import SequenceConflict, StorageError, StorageUnavailable
from rigserver.storage.payloads import Payload
from schemas.readings import BatchReceipt


class GroupCommit:
    """The store's batches into ``journal`` and the files of ``views``: a batch of at least
    ``backlog_rows`` rows joins its file's backlog, written when ``quiet``."""

    def __init__(
        self, journal: Journal, views: RunFiles, backlog_rows: int, quiet: WhenQuiet
    ) -> None:
        self.journal = journal
        self.views = views
        self.backlog_rows = backlog_rows
        self.quiet = quiet

    def commit(
        self, batches: Sequence[NewBatch], prepared: Sequence[tuple[Batch, Payload] | ValueError]
    ) -> tuple[list[BatchReceipt | Exception], dict[str, int]]:
        """Stage ``batches`` (as :func:`prepared_batch` made them) in one journal
        transaction, commit it, then hand each to its run's file: one outcome per batch,
        and the open runs' new batch counts (for the live streams), empty if the commit
        failed. Called under the store's lock."""
        outcomes: list[BatchReceipt | Exception | None] = [None] * len(batches)
        staged: list[_Staged] = []
        saved: dict[str, _Saved] = {}
        doing = f"storing {len(batches)} batch(es)"
        try:
            self.journal.begin()
            for i, (nb, batch) in enumerate(zip(batches, prepared, strict=True)):
                outcomes[i] = (
                    batch
                    if isinstance(batch, Exception)
                    else self._stage(i, nb, *batch, staged, saved)
                )
            self.journal.set_counters(self.views.live[run_id].run for run_id in saved)
            self.journal.commit()
        except BaseException as exc:
            for run_id, before in saved.items():
                before.restore(self.views.live[run_id])
            with failures_as(f"rolling back {doing}"):
                self.journal.rollback()
            if not isinstance(exc, LOW_LEVEL):
                raise
            failure = translated(exc, doing)
            # a retry's receipt or conflict may stem from a batch of this call: void
            voided: list[BatchReceipt | Exception] = [
                failure if o is None or isinstance(o, BatchReceipt | SequenceConflict) else o
                for o in outcomes
            ]
            return voided, {}
        for st in staged:
            outcomes[st.index] = self._write_staged(st)
        grown = {run_id: self.views.live[run_id].run.batches for run_id in saved}
        return [o for o in outcomes if o is not None], grown

    def _stage(
        self,
        index: int,
        nb: NewBatch,
        batch: Batch,
        payload: Payload,
        staged: list[_Staged],
        saved: dict[str, _Saved],
    ) -> BatchReceipt | Exception | None:
        """Add one batch (``nb`` as ``batch``, its readings as ``payload``) to the open
        journal transaction: its receipt if it is a retry, the exception that refuses it, or
        None once staged. Journal failures are raised."""
        run_id, seq, group = nb.run_id, nb.seq, nb.group
        try:
            open_run = self.views.live.get(run_id)
            if open_run is None or seq <= open_run.max_seq:  # maybe a retry
                stored = self.journal.stored_batch(run_id, seq)
                if stored is not None:
                    return retry_receipt(run_id, seq, stored, batch)
            live = self.views.open_run(run_id)
            if run_id in saved and live.stale:  # a rebuild now would take in staged batches
                raise StorageUnavailable(
                    f"the file of run {run_id} failed while batch {seq} waited; retry it"
                )
            if nb.check is not None:
                nb.check(batch.columns, self.views.last(live, group))
            decl = check(live.run.stand, batch)
            if live.stale or run_id not in self.views.files:
                self.views.view(live, f"opening the file of run {run_id}")  # before the commit
        except sqlite3.Error:
            raise
        except Exception as exc:
            return exc
        if run_id not in saved:
            saved[run_id] = _Saved.of(live)
        group_rows = live.run.rows.get(group, 0) + batch.rows
        place = self.journal.add_batch(run_id, seq, batch, group_rows, payload)
        if isinstance(place, StoredBatch):
            try:
                return retry_receipt(run_id, seq, place, batch)
            except SequenceConflict as exc:
                return exc
        live.run.rows = {**live.run.rows, group: group_rows}
        live.run.batches += 1
        live.max_seq = max(live.max_seq, seq)
        _remember_last(live, batch)
        stored = StoredBatch(group, batch.rows, group_rows, batch.digest)
        columns = padded(decl, batch.columns, batch.rows)
        staged.append(_Staged(index, live, seq, columns, stored, place))
        return None

    def _write_staged(self, st: _Staged) -> BatchReceipt | Exception:
        """Hand a committed batch to its run's file, or to the file's backlog if it is
        large or the file owes earlier ones; a failure marks the view stale."""
        live = st.live
        receipt = stored_receipt(live.run.id, st.seq, st.stored, duplicate=False)
        if live.stale:  # the rebuild from the journal will bring the batch in
            return receipt
        doing = (
            f"writing batch {st.seq} of run {live.run.id} to its file (the batch is stored: "
            "retry with the same seq)"
        )
        try:
            rf = self.views.files.get(live.run.id) or self.views.view(live, doing)
            if live.direct or not (live.backlog or st.stored.rows >= self.backlog_rows):
                rf.append(st.stored.group, st.columns, st.stored.rows)
            else:
                live.backlog.add(Owed(st.stored.group, st.stored.rows, *st.place))
                if live.backlog.bytes > MAX_BACKLOG_BYTES:  # no burst: a steady stream
                    self.views.pay(live, rf, len(live.backlog.owed))
                    live.direct = True
                self.quiet.wanted()
        except LOW_LEVEL as exc:
            self.views.spoil(live)
            return translated(exc, doing)
        except StorageError as exc:
            return exc
        return receipt


@dataclass(frozen=True, slots=True)
class _Saved:
    """An open run's counters and last values before a group commit, to restore on failure."""

    rows: dict[str, int]
    batches: int
    last: dict[str, dict[str, float]]
    max_seq: int

    @classmethod
    def of(cls, live: Live) -> _Saved:
        last = {group: dict(values) for group, values in live.last.items()}
        return cls(dict(live.run.rows), live.run.batches, last, live.max_seq)

    def restore(self, live: Live) -> None:
        live.run.rows = self.rows
        live.run.batches = self.batches
        live.last = self.last
        live.max_seq = self.max_seq


@dataclass(frozen=True, slots=True)
class _Staged:
    """A batch in the open journal transaction, to write to its run file after the commit."""

    index: int
    live: Live
    seq: int
    columns: dict[str, NDArray[np.float64]]
    stored: StoredBatch
    #: its place in the payload file (at, size), should it join the backlog
    place: tuple[int, int]


def prepared_batch(nb: NewBatch) -> tuple[Batch, Payload] | ValueError:
    """The batch as stored (:func:`posted_or_refusal`) and its readings as the journal
    writes them, or why it cannot be stored."""
    batch = posted_or_refusal(nb)
    return batch if isinstance(batch, ValueError) else (batch, payload_of(batch))


def _remember_last(live: Live, batch: Batch) -> None:
    cached = live.last.get(batch.group)
    if cached is None:
        return
    for name, values in batch.columns.items():
        if not len(values):
            continue
        last = float(values[-1])
        if last == last:  # not NaN
            cached[name] = last
        elif (value := last_finite(values)) is not None:
            cached[name] = value
