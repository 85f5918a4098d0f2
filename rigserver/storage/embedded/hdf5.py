"""HDF5Store: a data directory with a SQLite journal as the truth and one HDF5 file per run.

Data directory::

    journal.sqlite (+ -wal, -shm)   catalogue and batches (rigserver.storage.embedded.journal)
    payloads/<run_id>.bin           readings of the batches until the run file is final
                                    (rigserver.storage.payloads)
    runs/<run_id>.h5                the run files (layout: rigserver.storage.runfile)
    snapshots/<run_id>.h5           consistent copies of open runs' files (run_file)
    .lock                           flock'ed while a store has the directory open

Crash safety. A batch is acknowledged once its journal transaction has committed; only
then is it handed to the run's HDF5 file (which buffers small batches, see
:mod:`~rigserver.storage.runfile`; it is never fsynced per batch), or, for a large batch,
to the file's backlog, written later (:mod:`~rigserver.storage.embedded.backlog`). For an
open run that file is a view that can always be rebuilt from the journal. ``journal.sqlite`` holds a
clean-shutdown marker, "0" while a store is open and "1" after :meth:`HDF5Store.close`.
Opening after an unclean shutdown rebuilds the file of every open run from the journal
into a temp file, fsyncs it and renames it over the old one; a run whose end did not
complete is finished the same way. A run's file is final when it has been finalized,
closed and fsynced; only then are the run's readings dropped from the journal (its
receipts stay, so a retried old seq is still answered). If ``journal.sqlite`` is missing,
the catalogue is rebuilt from the run files (their ``/entry@run``), and the readings of
unfinished files are taken back into the journal. A failure to write the HDF5 file after
the commit marks the view stale (it is rebuilt at its next use) and is raised: the batch
is durable, and a retry with the same seq is answered as a duplicate.

Run files are in HDF5's default format, not SWMR: a live SWMR file is refused by a plain
reader and cannot be copied into a snapshot (the trials: docs/speed.md, "Findings the code
rests on"); so the open runs' files are rebuilt after an unclean shutdown, not trusted.

Thread safety: one lock serialises the journal and the open HDF5 files (h5py serialises
its calls anyway); reading a finished run's file happens outside it.
"""

from __future__ import annotations

import fcntl
import json
import logging
import os
import shutil
import sqlite3
import threading
from collections import OrderedDict
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rigserver.storage._checks import (
    Batch,
    StoredBatch,
    channel_group,
    check,
    chunks,
    last_finite,
    new_run,
    padded,
    posted_or_refusal,
    prepare,
    reopened,
    retry_receipt,
    stand_groups,
    stored_receipt,
)
from rigserver.storage._failures import LOW_LEVEL, UNREADABLE, failures_as, translated
from rigserver.storage._results import CheckedResults, check_results
from rigserver.storage._time import now
from rigserver.storage.base import Columns, NewBatch
from rigserver.storage.corrections import RowEdit, RowEdits, corrected_row, new_corrections
from rigserver.storage.embedded.backlog import (
    BACKLOG_ROWS,
    MAX_BACKLOG_BYTES,
    PIECE_ROWS,
    QUIET_SECONDS,
    Backlog,
    Owed,
    WhenQuiet,
)
from rigserver.storage.embedded.journal import CatalogueEntry, Journal, Synchronous, payload_of
from rigserver.storage.errors import (
    RunDamaged,
    RunNotFound,
    RunNotOpen,
    SequenceConflict,
    StorageError,
    StorageUnavailable,
)
from rigserver.storage.payloads import Payload
from rigserver.storage.runfile import RunFile, fsync_path, read_summary, write_file
from rigserver.storage.waiters import AppendWaiters
from schemas.corrections import CorrectedRow, Correction
from schemas.readings import BatchReceipt
from schemas.runs import Run, RunPage, RunQuery, RunState

log = logging.getLogger(__name__)

#: Open runs whose HDF5 file is kept open; the least recently used are closed beyond this.
MAX_OPEN_FILES = 32
#: What reading an opened run file raises when it is corrupt (not: a channel it lacks).
_CORRUPT: tuple[type[Exception], ...] = (*LOW_LEVEL, KeyError)
#: What writing a file's backlog and closing it may raise.
_CLOSING: tuple[type[Exception], ...] = (*LOW_LEVEL, StorageError)
#: What bringing a final file up to its corrections may raise at start (logged, left).
_SYNC_FAILURES: tuple[type[Exception], ...] = (*UNREADABLE, StorageError)
#: Rows per batch when the readings of an unfinished file are taken back into the journal.
_IMPORT_ROWS = 1 << 20


@dataclass(slots=True)
class _Live:
    """An open run: its metadata with current counters, last values, view state."""

    run: Run
    #: group -> channel -> last value; a group missing here is read from the file when asked
    last: dict[str, dict[str, float]] = field(default_factory=dict)
    #: the HDF5 file lags the journal or may be damaged: rebuild it before its next use
    stale: bool = False
    #: the largest seq stored: a batch with a larger one is no retry (no lookup)
    max_seq: int = -1
    #: batches the open file still owes (only while the file is open and not stale)
    backlog: Backlog = field(default_factory=Backlog)
    #: the backlog went past its bound: batches are written at once until the store is quiet
    direct: bool = False


class HDF5Store(RowEdits):
    """The embedded run store: a data directory on local disk (see the module docstring).

    Parameters
    ----------
    data_dir : Path
        The data directory; created if missing. One store at a time may open it.
    synchronous : {"normal", "full"}
        SQLite's ``synchronous`` for the journal: "normal" keeps every acknowledged batch
        through a kill of the process; "full" also through a power loss (one fsync per
        batch).
    backlog_rows : int
        Batches of at least this many rows are written to the run file after their
        acknowledgement (:mod:`~rigserver.storage.embedded.backlog`).
    """

    def __init__(
        self,
        data_dir: Path,
        *,
        synchronous: Synchronous = "normal",
        backlog_rows: int = BACKLOG_ROWS,
    ) -> None:
        self.data_dir = Path(data_dir)
        self._backlog_rows = backlog_rows
        self._runs = self.data_dir / "runs"
        self._snapshots = self.data_dir / "snapshots"
        self._lock = threading.RLock()
        self._live: dict[str, _Live] = {}
        self._files: OrderedDict[str, RunFile] = OrderedDict()
        #: ended runs whose finalized file is being fsynced (outside the lock)
        self._finishing: set[str] = set()
        self._closed = False
        #: the live streams waiting for a run's next batch (woken after each commit)
        self.appends = AppendWaiters()
        with failures_as(f"opening the data directory {self.data_dir}"):
            for d in (self.data_dir, self._runs, self._snapshots):
                d.mkdir(parents=True, exist_ok=True)
            self._dir_lock = _lock_directory(self.data_dir)
        try:
            with failures_as(f"opening the journal in {self.data_dir}"):
                path = self.data_dir / "journal.sqlite"
                new = not path.exists()
                if new:  # a WAL or payloads left beside a lost journal belong to no journal
                    for stale in (path.with_name(path.name + s) for s in ("-wal", "-shm")):
                        stale.unlink(missing_ok=True)
                    for stale in self.data_dir.glob("payloads/*.bin"):
                        stale.unlink()
                self._journal = Journal(path, synchronous=synchronous)
                fsync_path(self.data_dir)
            try:
                with failures_as(f"recovering the runs of {self.data_dir}"):
                    for leftover in [*self._runs.glob("*.tmp"), *self._snapshots.iterdir()]:
                        leftover.unlink()
                    if new:
                        self._rebuild_catalogue()
                    for run_id in self._journal.final_runs_with_payloads():
                        self._journal.drop_payloads(run_id)
                    clean = self._journal.clean_shutdown()
                    self._journal.set_clean_shutdown(False)
                    self._recover(clean=clean)
            except BaseException:
                self._journal.close()
                raise
        except BaseException:
            os.close(self._dir_lock)
            raise
        self._quiet = WhenQuiet(self._write_backlog, quiet=QUIET_SECONDS, name="rig-backlog")

    def __enter__(self) -> HDF5Store:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # --- runs -------------------------------------------------------------------------

    def create_run(self, run: Run, key: str | None = None) -> Run:
        """Store a new open run and create its file; ``RunExists`` if the id is taken, the
        run opened before if ``key`` was (:meth:`RunStore.create_run`).

        All or nothing: if its file cannot be created, the run is removed from the
        catalogue again and the error is raised.
        """
        stored = new_run(run)
        with self._lock:
            self._check_open()
            if key is not None:
                with failures_as(f"looking up the run of key {key[:80]!r}"):
                    found = self._journal.run_for_key(key)
                if found is not None:
                    return reopened(self.get_run(found), stored, key)
            with failures_as(f"creating run {run.id}"):
                self._journal.insert_run(stored, key=key)
            try:
                rf = RunFile.create(self._path(run.id), stored)
            except BaseException as exc:
                self._path(run.id).unlink(missing_ok=True)
                with failures_as(f"removing run {run.id}, whose file could not be created"):
                    self._journal.delete_run(run.id, key)
                if isinstance(exc, LOW_LEVEL):
                    raise translated(exc, f"creating the file of run {run.id}") from exc
                raise
            self._live[run.id] = _Live(stored, last={group: {} for group in stored.rows})
            self._keep_open(run.id, rf)
            return stored.model_copy(deep=True)

    def get_run(self, run_id: str) -> Run:
        with self._lock:
            self._check_open()
            live = self._live.get(run_id)
            if live is not None:
                return live.run.model_copy(deep=True)
            with failures_as(f"reading the catalogue entry of run {run_id}"):
                return self._journal.entry(run_id).run

    def list_runs(self, query: RunQuery) -> RunPage:
        """Runs matching the query, newest first (``since <= created < until``)."""
        with self._lock:
            self._check_open()
            with failures_as("listing runs"):
                return self._journal.list_runs(query)

    def end_run(self, run_id: str, state: RunState) -> Run:
        """Finish or abort an open run: record the end, finalize and fsync its file.

        The fsync (seconds for a run of gigabytes) happens outside the store's lock: other
        runs' batches go on meanwhile, and the run's finalized file can be read.
        Ending again with the same state a run whose file could not be finalized (e.g. the
        disk was full) completes it; otherwise a run that is not open raises
        ``RunNotOpen``.
        """
        if state is RunState.OPEN:
            raise ValueError("a run can end as finished or aborted, not open")
        path = self._path(run_id)
        doing = f"finalizing the file of run {run_id}"
        with self._lock:
            self._check_open()
            live = self._live.get(run_id)
            if live is None:
                with failures_as(f"ending run {run_id}"):
                    entry = self._journal.entry(run_id)
                if entry.run.state is state and not entry.file_final:
                    if run_id in self._finishing:
                        raise StorageUnavailable(f"run {run_id} is being ended; retry")
                    self._finish_file(entry.run)
                    return entry.run
                raise RunNotOpen(f"run {run_id} is already {entry.run.state.value}")
            rf = self._view(live, f"ending run {run_id}")
            ended = live.run.model_copy(deep=True, update={"state": state, "ended": now()})
            with failures_as(f"ending run {run_id}"):
                self._journal.end_run(ended)
            del self._live[run_id]
            self._files.pop(run_id, None)
            self.appends.ended(run_id)
            try:
                with failures_as(doing):
                    try:
                        rf.finalize(ended)
                    finally:
                        rf.close()
            except StorageError as exc:
                # The file failed where the journal did not (a write of its cached chunks
                # on a disk that was full): the final file is written anew from the journal.
                log.warning(
                    "finalizing run %s: %s; its file is written from the journal", run_id, exc
                )
                self._finish_file(ended)
                return ended.model_copy(deep=True)
            self._finishing.add(run_id)
        try:
            with failures_as(doing):
                fsync_path(path)
                fsync_path(self._runs)
            with self._lock:
                self._check_open()
                with failures_as(doing):
                    self._mark_final(run_id)
        finally:
            with self._lock:
                self._finishing.discard(run_id)
        return ended.model_copy(deep=True)

    # --- readings ---------------------------------------------------------------------

    def append(self, run_id: str, seq: int, group: str, columns: Columns) -> BatchReceipt:
        """Store one batch: committed to the journal, then written to the run's file.

        Raises ``RunNotFound``, ``RunNotOpen``, ``SequenceConflict``, ``StorageFull``,
        ``StorageUnavailable``, and ``ValueError`` for a batch that does not fit the
        stand's channel groups (unknown group or channel; an aligned group's channels
        missing or of unequal lengths).
        """
        (outcome,) = self.append_many([NewBatch(run_id, seq, group, columns)])
        if isinstance(outcome, Exception):
            raise outcome
        return outcome

    def append_many(self, batches: Sequence[NewBatch]) -> list[BatchReceipt | Exception]:
        """Store the batches in order with one journal commit (group commit), then write
        them to their run files.

        Each batch is checked as :meth:`append` checks it, then by its own ``check``, and
        refused alone (its outcome is the exception :meth:`append` would raise). A failure
        of the journal refuses every batch of the call that its checks did not refuse
        (retries too: their first copy may have been in the call): the commit is rolled
        back and the open runs' counters and last values are as before the call.
        """
        outcomes: list[BatchReceipt | Exception | None] = [None] * len(batches)
        staged: list[_Staged] = []
        saved: dict[str, _Saved] = {}
        # copies, digests and the payloads' aligned memory: outside the lock
        prepared = [_prepared(nb) for nb in batches]
        self._quiet.touched()
        with self._lock:
            try:
                self._check_open()
            except StorageUnavailable as exc:
                return [exc] * len(batches)
            doing = f"storing {len(batches)} batch(es)"
            try:
                self._journal.begin()
                for i, (nb, batch) in enumerate(zip(batches, prepared, strict=True)):
                    outcomes[i] = (
                        batch
                        if isinstance(batch, Exception)
                        else self._stage(i, nb, *batch, staged, saved)
                    )
                self._journal.set_counters(self._live[run_id].run for run_id in saved)
                self._journal.commit()
            except BaseException as exc:
                for run_id, before in saved.items():
                    before.restore(self._live[run_id])
                with failures_as(f"rolling back {doing}"):
                    self._journal.rollback()
                if not isinstance(exc, LOW_LEVEL):
                    raise
                failure = translated(exc, doing)
                # a retry's receipt or conflict may stem from a batch of this call: void
                return [
                    failure if o is None or isinstance(o, BatchReceipt | SequenceConflict) else o
                    for o in outcomes
                ]
            for st in staged:
                outcomes[st.index] = self._write_staged(st)
            grown = {run_id: self._live[run_id].run.batches for run_id in saved}
        for run_id, count in grown.items():
            self.appends.woken(run_id, count)
        return [o for o in outcomes if o is not None]

    #: Told in process: no notification is lost
    appends_lossy = False

    def wake_waiters(self) -> None:
        """Wake every live stream waiting (the server is stopping)."""
        self.appends.wake_all()

    async def wait_for_appends(self, run_id: str, batches: int, timeout: float) -> bool:
        """Until a batch of the run beyond ``batches`` is committed or the run ends (told
        in this process, :mod:`rigserver.storage.waiters`); False after ``timeout`` s."""
        return await self.appends.wait(run_id, batches, timeout)

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
            open_run = self._live.get(run_id)
            if open_run is None or seq <= open_run.max_seq:  # maybe a retry
                stored = self._journal.stored_batch(run_id, seq)
                if stored is not None:
                    return retry_receipt(run_id, seq, stored, batch)
            live = self._open_run(run_id)
            if run_id in saved and live.stale:  # a rebuild now would take in staged batches
                raise StorageUnavailable(
                    f"the file of run {run_id} failed while batch {seq} waited; retry it"
                )
            if nb.check is not None:
                nb.check(batch.columns, self._last(live, group))
            decl = check(live.run.stand, batch)
            if live.stale or run_id not in self._files:
                self._view(live, f"opening the file of run {run_id}")  # before the commit
        except sqlite3.Error:
            raise
        except Exception as exc:
            return exc
        if run_id not in saved:
            saved[run_id] = _Saved.of(live)
        group_rows = live.run.rows.get(group, 0) + batch.rows
        place = self._journal.add_batch(run_id, seq, batch, group_rows, payload)
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
            rf = self._files.get(live.run.id) or self._view(live, doing)
            if live.direct or not (live.backlog or st.stored.rows >= self._backlog_rows):
                rf.append(st.stored.group, st.columns, st.stored.rows)
            else:
                live.backlog.add(Owed(st.stored.group, st.stored.rows, *st.place))
                if live.backlog.bytes > MAX_BACKLOG_BYTES:  # no burst: a steady stream
                    self._pay(live, rf, len(live.backlog.owed))
                    live.direct = True
                self._quiet.wanted()
        except LOW_LEVEL as exc:
            self._spoil(live)
            return translated(exc, doing)
        except StorageError as exc:
            return exc
        return receipt

    def receipt(self, run_id: str, seq: int) -> BatchReceipt | None:
        with self._lock:
            self._check_open()
            with failures_as(f"looking up batch {seq} of run {run_id}"):
                stored = self._journal.stored_batch(run_id, seq)
                if stored is None:
                    if run_id not in self._live:
                        self._journal.entry(run_id)  # RunNotFound
                    return None
            return stored_receipt(run_id, seq, stored, duplicate=True)

    def history(self, run_id: str) -> tuple[str | None, list[tuple[int, StoredBatch]]]:
        """The run's Idempotency-Key and its batches' receipts in the order stored (for
        ``rigserver migrate``); ``RunNotFound``."""
        with self._lock:
            self._check_open()
            with failures_as(f"reading the batches of run {run_id}"):
                self._journal.entry(run_id)
                return self._journal.key_of(run_id), self._journal.stored_batches(run_id)

    def last_values(self, run_id: str, group: str) -> dict[str, float]:
        """The last non-NaN value of each channel of ``group`` (cached for open runs)."""
        with self._lock:
            self._check_open()
            live = self._live.get(run_id)
            if live is not None:
                channel_group(live.run.stand, group)
                return dict(self._last(live, group))
            self._final_entry(run_id)
        with self._final_file(run_id) as rf:
            return rf.last_values(group)

    def read(
        self,
        run_id: str,
        group: str,
        channels: list[str] | None = None,
        start: int = 0,
        stop: int | None = None,
    ) -> dict[str, NDArray[np.float64]]:
        """Rows ``start:stop`` (slice semantics) of the channels, read from the run file."""
        with self._lock:
            self._check_open()
            live = self._live.get(run_id)
            if live is not None:
                rf = self._view(live, f"reading run {run_id}")
                with self._spoiling(live, f"reading run {run_id}"):
                    return rf.read(group, channels, start, stop)
            self._final_entry(run_id)
        with self._final_file(run_id) as rf:
            return rf.read(group, channels, start, stop)

    def iter_chunks(
        self, run_id: str, group: str, channels: list[str] | None = None, rows: int = 1 << 20
    ) -> Iterator[dict[str, NDArray[np.float64]]]:
        """The rows stored when called, in consecutive slices of at most ``rows`` rows."""
        return chunks(self, run_id, group, channels, rows)

    # --- corrections --------------------------------------------------------------------

    def corrections(self, run_id: str) -> list[Correction]:
        with self._lock:
            self._check_open()
            with failures_as(f"reading the corrections of run {run_id}"):
                if run_id not in self._live:
                    self._journal.entry(run_id)  # RunNotFound
                return self._journal.corrections(run_id)

    def _edit(self, run_id: str, edit: RowEdit) -> CorrectedRow:
        """A correction committed to the journal (then acknowledged), then written to the
        run file (an ended run's final file rewritten by copy and rename)."""
        group, index = edit.group, edit.index
        doing = f"correcting row {index} of {group} of run {run_id}"
        with self._lock:
            self._check_open()
            live = self._live.get(run_id)
            run = live.run if live is not None else self._final_entry(run_id).run
            with failures_as(doing):
                earlier = self._journal.corrections(run_id)

            def read(lo: int, hi: int) -> dict[str, NDArray[np.float64]]:
                return self.read(run_id, group, None, lo, hi)

            new = new_corrections(run, edit, now(), read, earlier)
            every = [*earlier, *new]
            if new:
                after = run.state is RunState.FINISHED or run.corrected_after_finish
                update = {"corrections": len(every), "corrected_after_finish": after}
                edited = run.model_copy(deep=True, update=update)
                with failures_as(doing):
                    self._journal.add_corrections(edited, new)
                if live is not None:
                    live.run.corrections = edited.corrections
                    live.run.corrected_after_finish = edited.corrected_after_finish
                    rf = self._view(live, doing)
                    with self._spoiling(live, doing):
                        rf.write_corrections(every, edited)
                else:
                    with failures_as(f"{doing} (it is stored; the file follows)"):
                        self._rewrite(edited, lambda rf: rf.write_corrections(every, edited))
            elif live is None and every:  # a retry: the file may have missed the first try
                with failures_as(doing):
                    self._sync_corrections(run)
            row = read(index, index + 1)
        if new:  # the live streams tell their viewers
            self.appends.woken(run_id, run.batches)
        return corrected_row(run_id, group, index, row, every)

    def _sync_corrections(self, run: Run) -> None:
        """Bring an ended run's final file up to the corrections of the journal (a crash
        between a correction's commit and the file's rewrite left it behind)."""
        every = self._journal.corrections(run.id)
        with RunFile.open(self._path(run.id), writable=False) as rf:
            held = len(rf.corrections())
        if held != len(every):
            log.info("writing %d correction(s) of run %s to its file", len(every), run.id)
            self._rewrite(run, lambda rf: rf.write_corrections(every, run))

    # --- results and files ------------------------------------------------------------

    def set_results(
        self, run_id: str, results: Mapping[str, Any], key_results: Mapping[str, float]
    ) -> None:
        """Store the results in the catalogue and under ``/entry/results`` of the run file.

        A finished run's file is rewritten by copy and rename, never in place. The results'
        convention is described in :mod:`rigserver.storage._results`.
        """
        checked = check_results(results, key_results)
        with self._lock:
            self._check_open()
            live = self._live.get(run_id)
            doing = f"storing the results of run {run_id}"
            if live is not None:
                run = live.run.model_copy(deep=True, update={"key_results": checked.key_results})
                rf = self._view(live, doing)
                with failures_as(doing):
                    self._journal.set_results(run, checked.text)
                live.run.key_results = dict(checked.key_results)
                with self._spoiling(live, doing):
                    rf.write_results(checked, run)
                return
            entry = self._final_entry(run_id)
            run = entry.run.model_copy(update={"key_results": checked.key_results})
            with failures_as(doing):
                self._rewrite_results(run, checked)
                self._journal.set_results(run, checked.text)

    def results(self, run_id: str) -> dict[str, Any] | None:
        with self._lock:
            self._check_open()
            with failures_as(f"reading the results of run {run_id}"):
                text = self._journal.results(run_id)
        return None if text is None else dict(json.loads(text))

    def import_run(
        self,
        run: Run,
        key: str | None,
        results: Mapping[str, Any] | None,
        batches: Iterable[tuple[int, StoredBatch, Mapping[str, NDArray[np.float64]]]],
        corrections: Sequence[Correction] = (),
    ) -> bool:
        """Store a run made elsewhere whole (:meth:`RunStore.import_run`): its final file
        is written first, outside the store's lock (a temp file renamed when complete),
        then its catalogue entry; the run is seen only once both are there. The batches'
        receipts are not kept: an imported run has ended and takes no retries."""
        checked = None if results is None else check_results(results, run.key_results)
        path = self._path(run.id)
        with self._lock:
            self._check_open()
            if run.id in self._live or path.exists() or self._catalogued(run.id):
                return False
        with failures_as(f"writing the file of imported run {run.id}"):
            write_file(
                path,
                run,
                ((s.group, dict(columns), s.rows) for _, s, columns in batches),
                checked,
                final=True,
                corrections=list(corrections),
            )
        try:
            with self._lock:
                self._check_open()
                with failures_as(f"importing run {run.id}"):
                    self._journal.insert_run(
                        run,
                        file_final=True,
                        results=None if checked is None else checked.text,
                        key=key,
                        corrections=corrections,
                    )
        except BaseException:
            path.unlink(missing_ok=True)
            raise
        return True

    def _catalogued(self, run_id: str) -> bool:
        with failures_as(f"looking up run {run_id}"):
            try:
                self._journal.entry(run_id)
            except RunNotFound:
                return False
            except RunDamaged:
                pass
        return True

    def readings_version(self, run_id: str) -> int:
        """The run's batches and corrections counted (:meth:`RunStore.readings_version`)."""
        with self._lock:
            self._check_open()
            live = self._live.get(run_id)
            if live is not None:
                return live.run.batches + live.run.corrections
            with failures_as(f"reading the catalogue entry of run {run_id}"):
                run = self._journal.entry(run_id).run
                return run.batches + run.corrections

    def run_file(self, run_id: str) -> Path:
        """The final file of an ended run; a fresh snapshot copy for an open run."""
        with self._lock:
            self._check_open()
            live = self._live.get(run_id)
            if live is None:
                self._final_entry(run_id)
                return self._path(run_id)
            rf = self._view(live, f"flushing run {run_id}")
            with self._spoiling(live, f"flushing run {run_id}"):
                rf.flush()
            snapshot = self._snapshots / f"{run_id}.h5"
            tmp = snapshot.with_name(snapshot.name + ".tmp")
            with failures_as(f"copying a snapshot of run {run_id}"):
                shutil.copyfile(rf.path, tmp)
                os.replace(tmp, snapshot)
            return snapshot

    def close(self) -> None:
        """Write and close every open file, mark the shutdown clean, release the directory."""
        self._quiet.close()
        with self._lock:
            if self._closed:
                return
            self._closed = True
            clean = True
            for run_id in list(self._files):
                clean &= self._close_file(run_id)
            clean &= not any(live.stale for live in self._live.values())
            try:
                with failures_as(f"closing the journal of {self.data_dir}"):
                    self._journal.set_clean_shutdown(clean)
            finally:
                self._journal.close()
                os.close(self._dir_lock)

    # --- internals --------------------------------------------------------------------

    def _check_open(self) -> None:
        if self._closed:
            raise StorageUnavailable(f"the store of {self.data_dir} is closed")

    def _path(self, run_id: str) -> Path:
        return self._runs / f"{run_id}.h5"

    def _last(self, live: _Live, group: str) -> dict[str, float]:
        """The open run's cached last values of ``group`` (read from its file if need be)."""
        cached = live.last.get(group)
        if cached is None:
            rf = self._view(live, f"reading run {live.run.id}")
            with self._spoiling(live, f"reading run {live.run.id}"):
                cached = rf.last_values(group)
            live.last[group] = cached
        return cached

    def _open_run(self, run_id: str) -> _Live:
        live = self._live.get(run_id)
        if live is None:
            with failures_as(f"looking up run {run_id}"):
                state = self._journal.entry(run_id).run.state
            raise RunNotOpen(f"run {run_id} is {state.value}: it takes no more readings")
        return live

    @contextmanager
    def _final_file(self, run_id: str) -> Iterator[RunFile]:
        """The ended run's file, read-only; ``RunDamaged`` if it is missing or corrupt (the
        journal no longer holds its readings)."""
        path = self._path(run_id)
        try:
            rf = RunFile.open(path, writable=False)
        except UNREADABLE as exc:
            raise _damaged(run_id, path, exc) from exc
        with rf:
            try:
                yield rf
            except _CORRUPT as exc:
                raise _damaged(run_id, path, exc) from exc

    def _final_entry(self, run_id: str) -> CatalogueEntry:
        """The catalogue entry of a run that is not open, its file made final if need be."""
        with failures_as(f"looking up run {run_id}"):
            entry = self._journal.entry(run_id)
        if not entry.file_final and run_id not in self._finishing:  # finalized, fsync due
            self._finish_file(entry.run)
        return entry

    def _view(self, live: _Live, doing: str) -> RunFile:
        """The open run's file, opened if need be, rebuilt first if stale or missing."""
        run_id = live.run.id
        with self._spoiling(live, doing):
            if live.stale:
                self._close_file(run_id)
                live.backlog.clear()
                self._rebuild(live.run, final=False)
                live.stale = False
            rf = self._files.get(run_id)
            if rf is None:
                path = self._path(run_id)
                if not path.exists():
                    self._rebuild(live.run, final=False)
                rf = self._keep_open(run_id, RunFile.open(path, writable=True))
            else:
                self._files.move_to_end(run_id)
            if live.backlog:
                self._pay(live, rf, len(live.backlog.owed))
            return rf

    def _pay(self, live: _Live, rf: RunFile, count: int) -> None:
        """Write the ``count`` oldest batches of the run's backlog to its file, read back
        from the journal a piece at a time; if that fails, the view is stale (the rebuild
        from the journal brings them in)."""
        try:
            for o in live.backlog.take(count):
                decl = channel_group(live.run.stand, o.group)
                # pieces that end where the file's chunks do: HDF5 writes whole chunks as
                # they are, without holding them in its chunk cache
                first = PIECE_ROWS - rf.rows(o.group) % PIECE_ROWS
                pieces = self._journal.payload_pieces(live.run.id, o.at, o.size, PIECE_ROWS, first)
                for piece in pieces:
                    rows = max(len(v) for v in piece.values())
                    rf.append(o.group, padded(decl, piece, rows), rows)
                    rf.write_pending()  # the piece's buffers are read into again
        except BaseException:
            self._spoil(live)
            raise

    def _write_backlog(self) -> bool:
        """One batch of the backlog of the first open run that has one (the store is quiet:
        :class:`WhenQuiet`); True if any is left."""
        with self._lock:
            if self._closed:
                return False
            for live in self._live.values():
                live.direct = False  # whatever stream made it so has paused
            owing = [live for live in self._live.values() if live.backlog and not live.stale]
            if not owing:
                return False
            live = owing[0]
            rf = self._files.get(live.run.id)
            try:
                if rf is None:  # not expected: a file is closed only with its backlog written
                    raise StorageUnavailable(f"the file of run {live.run.id} is not open")
                with self._spoiling(live, f"writing the backlog of run {live.run.id}"):
                    self._pay(live, rf, 1)
            except StorageError as exc:
                log.warning("%s; the file will be rebuilt from the journal", exc)
                self._spoil(live)
            return len(owing) > 1 or bool(live.backlog)

    @contextmanager
    def _spoiling(self, live: _Live, doing: str) -> Iterator[None]:
        """Translate the failures of the block; the run's file view is then stale."""
        try:
            yield
        except LOW_LEVEL as exc:
            self._spoil(live)
            raise translated(exc, doing) from exc

    def _keep_open(self, run_id: str, rf: RunFile) -> RunFile:
        self._files[run_id] = rf
        while len(self._files) > MAX_OPEN_FILES:
            self._close_file(next(iter(self._files)))
        return rf

    def _close_file(self, run_id: str) -> bool:
        """Write the run's backlog and close its file if open; False (and the view stale)
        if that failed."""
        rf = self._files.pop(run_id, None)
        if rf is None:
            return True
        live = self._live.get(run_id)
        try:
            try:
                if live is not None and live.backlog and not live.stale:
                    self._pay(live, rf, len(live.backlog.owed))
            finally:
                rf.close()
        except _CLOSING as exc:
            log.warning("closing the file of run %s failed (%s); it will be rebuilt", run_id, exc)
            if live is not None:
                live.stale = True
                live.backlog.clear()
            return False
        return True

    def _spoil(self, live: _Live) -> None:
        live.stale = True
        live.backlog.clear()  # the rebuild from the journal brings every batch in
        self._close_file(live.run.id)

    def _rebuild(self, run: Run, *, final: bool) -> None:
        """Write the run's file anew from the journal (atomically)."""
        text = self._journal.results(run.id)
        results = None if text is None else check_results(json.loads(text), run.key_results)

        def batches() -> Iterator[tuple[str, dict[str, NDArray[np.float64]], int]]:
            for group, columns in self._journal.payloads(run.id):
                rows = max((len(v) for v in columns.values()), default=0)
                yield group, padded(channel_group(run.stand, group), columns, rows), rows

        corrections = self._journal.corrections(run.id)
        write_file(
            self._path(run.id), run, batches(), results, final=final, corrections=corrections
        )

    def _finish_file(self, run: Run) -> None:
        """Write the ended run's final file anew from the journal (fsynced), then drop its
        readings from the journal."""
        with failures_as(f"finalizing the file of run {run.id}"):
            self._rebuild(run, final=True)
            self._mark_final(run.id)

    def _mark_final(self, run_id: str) -> None:
        """The run's file is final and fsynced: its readings leave the journal."""
        self._journal.mark_final(run_id)
        (self._snapshots / f"{run_id}.h5").unlink(missing_ok=True)

    def _rewrite_results(self, run: Run, results: CheckedResults) -> None:
        self._rewrite(run, lambda rf: rf.write_results(results, run))

    def _rewrite(self, run: Run, change: Callable[[RunFile], None]) -> None:
        """Change an ended run's final file: a copy changed, fsynced and renamed over it."""
        path = self._path(run.id)
        tmp = path.with_name(path.name + ".tmp")
        try:
            shutil.copyfile(path, tmp)
            with RunFile.open(tmp, writable=True) as rf:
                change(rf)
            fsync_path(tmp)
            os.replace(tmp, path)
            fsync_path(self._runs)
        except BaseException:
            tmp.unlink(missing_ok=True)
            raise

    def _recover(self, *, clean: bool) -> None:
        """Load the open runs; rebuild their files after an unclean shutdown; finish the
        files of ended runs whose end did not complete."""
        unfinished = self._journal.unfinished()
        if not clean:
            self._recover_corrections({e.run.id for e in unfinished})
        for entry in unfinished:
            run = entry.run
            if run.state is not RunState.OPEN:
                log.info("completing the end of run %s", run.id)
                self._finish_file(run)
                continue
            self._live[run.id] = _Live(run, max_seq=self._journal.max_seq(run.id))
            if not clean or not self._path(run.id).exists():
                log.info("rebuilding the file of open run %s from the journal", run.id)
                self._rebuild(run, final=False)

    def _recover_corrections(self, unfinished: set[str]) -> None:
        """The final files of corrected runs brought up to the journal's corrections."""
        for run_id in self._journal.corrected_runs():
            if run_id in unfinished:
                continue  # its file is rebuilt from the journal, corrections included
            try:
                self._sync_corrections(self._journal.entry(run_id).run)
            except _SYNC_FAILURES as exc:
                log.warning("run %s: its corrections could not reach its file (%s)", run_id, exc)

    def _rebuild_catalogue(self) -> None:
        """Fill a new journal from the run files; unfinished files' readings are imported."""
        for path in sorted(self._runs.glob("*.h5")):
            try:
                summary = read_summary(path)
            except UNREADABLE as exc:
                log.warning("run file %s is unreadable (%s); left out of the catalogue", path, exc)
                continue
            run = summary.run
            if run.id != path.stem:
                log.warning("run file %s holds run %s; left out of the catalogue", path, run.id)
                continue
            if summary.finalized:
                self._journal.insert_run(run, file_final=True, results=summary.results)
                continue
            run = run.model_copy(
                update={
                    "state": RunState.OPEN,
                    "ended": None,
                    "batches": 0,
                    "rows": {g.name: 0 for g in stand_groups(run.stand)},
                }
            )
            self._journal.insert_run(run, results=summary.results)
            self._import_readings(run, path)
            log.warning("run %s recovered from its unfinished file", run.id)

    def _import_readings(self, run: Run, path: Path) -> None:
        """The readings of a run file into the journal, as batches with negative seqs."""
        rows = {g.name: 0 for g in stand_groups(run.stand)}
        seq = -1
        with RunFile.open(path, writable=False) as rf:
            for group in rows:
                for start in range(0, rf.rows(group), _IMPORT_ROWS):
                    columns = rf.read(group, None, start, start + _IMPORT_ROWS)
                    batch = prepare(group, columns)
                    rows[group] += batch.rows
                    self._journal.begin()
                    self._journal.add_batch(run.id, seq, batch, rows[group])
                    run.rows, run.batches = dict(rows), -seq
                    self._journal.set_counters([run])
                    self._journal.commit()
                    seq -= 1


@dataclass(frozen=True, slots=True)
class _Saved:
    """An open run's counters and last values before a group commit, to restore on failure."""

    rows: dict[str, int]
    batches: int
    last: dict[str, dict[str, float]]
    max_seq: int

    @classmethod
    def of(cls, live: _Live) -> _Saved:
        last = {group: dict(values) for group, values in live.last.items()}
        return cls(dict(live.run.rows), live.run.batches, last, live.max_seq)

    def restore(self, live: _Live) -> None:
        live.run.rows = self.rows
        live.run.batches = self.batches
        live.last = self.last
        live.max_seq = self.max_seq


@dataclass(frozen=True, slots=True)
class _Staged:
    """A batch in the open journal transaction, to write to its run file after the commit."""

    index: int
    live: _Live
    seq: int
    columns: dict[str, NDArray[np.float64]]
    stored: StoredBatch
    #: its place in the payload file (at, size), should it join the backlog
    place: tuple[int, int]


def _prepared(nb: NewBatch) -> tuple[Batch, Payload] | ValueError:
    """The batch as stored (:func:`posted_or_refusal`) and its readings as the journal
    writes them, or why it cannot be stored."""
    batch = posted_or_refusal(nb)
    return batch if isinstance(batch, ValueError) else (batch, payload_of(batch))


def _damaged(run_id: str, path: Path, exc: Exception) -> RunDamaged:
    return RunDamaged(f"run {run_id} is damaged: its file {path.name} cannot be read ({exc})")


def _remember_last(live: _Live, batch: Batch) -> None:
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


def _lock_directory(data_dir: Path) -> int:
    fd = os.open(data_dir / ".lock", os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        raise StorageUnavailable(
            f"the data directory {data_dir} is in use by another store (another rigserver?)"
        ) from None
    return fd
