"""HDF5Store: a data directory with a SQLite journal as the truth and one HDF5 file per run.

Data directory::

    journal.sqlite (+ -wal, -shm)   catalogue and batches (rigserver.storage.embedded.journal)
    payloads/<run_id>.bin           readings of the batches until the run file is final
                                    (rigserver.storage.embedded.payload_files)
    runs/<run_id>.h5                the run files (layout: rigserver.storage.runfile)
    snapshots/<run_id>.h5           consistent copies of open runs' files (run_file)
    .lock                           flock'ed while a store has the directory open

Crash safety. A batch is acknowledged once its journal transaction has committed; only then
is it handed to the run's HDF5 file (which buffers small batches, see
:mod:`~rigserver.storage.runfile`; it is never fsynced per batch), or, for a large batch, to
the file's backlog, written later (:mod:`~rigserver.storage.embedded.backlog`). For an open
run that file is a view that can always be rebuilt from the journal
(:mod:`~rigserver.storage.embedded.views`). ``journal.sqlite`` holds a clean-shutdown
marker, "0" while a store is open and "1" after :meth:`HDF5Store.close`. Opening after an
unclean shutdown (:mod:`~rigserver.storage.embedded.recovery`) rebuilds the file of every
open run from the journal into a temp file, fsyncs it and renames it over the old one; a run
whose end did not complete is finished the same way. A run's file is final when it has been
finalized, closed and fsynced; only then are the run's readings dropped from the journal
(its receipts stay, so a retried old seq is still answered). If ``journal.sqlite`` is
missing, the catalogue is rebuilt from the run files (their ``/entry@run``), and the
readings of unfinished files are taken back into the journal. A failure to write the HDF5
file after the commit marks the view stale (it is rebuilt at its next use) and is raised:
the batch is durable, and a retry with the same seq is answered as a duplicate.

Run files are in HDF5's default format, not SWMR: a live SWMR file is refused by a plain
reader and cannot be copied into a snapshot (the trials: docs/speed.md, "Findings the code
rests on"); so the open runs' files are rebuilt after an unclean shutdown, not trusted.

Thread safety: one lock serialises the journal and the open HDF5 files (h5py serialises
its calls anyway); reading a finished run's file happens outside it. The store holds that
lock and coordinates its parts: the journal, the files (``views``), the group commit
(:mod:`~rigserver.storage.embedded.ingest`), the backlog's writer and the recovery.
"""

from __future__ import annotations

import fcntl
import json
import os
import threading
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rigserver.storage._checks import (
    StoredBatch,
    channel_group,
    new_run,
    reopened,
    stored_receipt,
)
from rigserver.storage._derived import Derived
from rigserver.storage._failures import LOW_LEVEL, failures_as, translated
from rigserver.storage._results import check_results
from rigserver.storage._time import now
from rigserver.storage.base import NewBatch
from rigserver.storage.corrections import (
    RowEdit,
    RowEdits,
    corrected_row,
    corrected_run,
    new_corrections,
)
from rigserver.storage.embedded.backlog import (
    BACKLOG_ROWS,
    QUIET_SECONDS,
    WhenQuiet,
)
from rigserver.storage.embedded.ingest import GroupCommit, prepared_batch
from rigserver.storage.embedded.journal import Synchronous
from rigserver.storage.embedded.recovery import open_journal, recover_directory
from rigserver.storage.embedded.views import Live, RunFiles
from rigserver.storage.errors import (
    RunNotOpen,
    StorageUnavailable,
)
from rigserver.storage.runfile import RunFile, fsync_path
from rigserver.storage.waiters import AppendWaiters, TellsInProcess
from schemas.corrections import CorrectedRow, Correction
from schemas.readings import BatchReceipt
from schemas.runs import Run, RunPage, RunQuery, RunState


class HDF5Store(Derived, RowEdits, TellsInProcess):
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
        self._runs = self.data_dir / "runs"
        self._snapshots = self.data_dir / "snapshots"
        self._lock = threading.RLock()
        self._closed = False
        #: the live streams waiting for a run's next batch (woken after each commit)
        self.appends = AppendWaiters()
        with failures_as(f"opening the data directory {self.data_dir}"):
            for d in (self.data_dir, self._runs, self._snapshots):
                d.mkdir(parents=True, exist_ok=True)
            self._dir_lock = _lock_directory(self.data_dir)
        try:
            with failures_as(f"opening the journal in {self.data_dir}"):
                self._journal, new = open_journal(self.data_dir, synchronous)
            #: the open runs and the run files, views of the journal
            self._views = RunFiles(self._journal, self._runs, self._snapshots)
            try:
                with failures_as(f"recovering the runs of {self.data_dir}"):
                    recover_directory(self._views, new=new)
            except BaseException:
                self._journal.close()
                raise
        except BaseException:
            os.close(self._dir_lock)
            raise
        self._quiet = WhenQuiet(self._write_backlog, quiet=QUIET_SECONDS, name="rig-backlog")
        self._ingest = GroupCommit(self._journal, self._views, backlog_rows, self._quiet)

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
                rf = RunFile.create(self._views.path(run.id), stored)
            except BaseException as exc:
                self._views.path(run.id).unlink(missing_ok=True)
                with failures_as(f"removing run {run.id}, whose file could not be created"):
                    self._journal.delete_run(run.id, key)
                if isinstance(exc, LOW_LEVEL):
                    raise translated(exc, f"creating the file of run {run.id}") from exc
                raise
            self._views.live[run.id] = Live(stored, last={group: {} for group in stored.rows})
            self._views.keep_open(run.id, rf)
            return stored.model_copy(deep=True)

    def get_run(self, run_id: str) -> Run:
        with self._lock:
            self._check_open()
            live = self._views.live.get(run_id)
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
        path = self._views.path(run_id)
        doing = f"finalizing the file of run {run_id}"
        with self._lock:
            self._check_open()
            live = self._views.live.get(run_id)
            if live is None:
                with failures_as(f"ending run {run_id}"):
                    entry = self._journal.entry(run_id)
                if entry.run.state is state and not entry.file_final:
                    if run_id in self._views.finishing:
                        raise StorageUnavailable(f"run {run_id} is being ended; retry")
                    self._views.finish_file(entry.run)
                    return entry.run
                raise RunNotOpen(f"run {run_id} is already {entry.run.state.value}")
            rf = self._views.view(live, f"ending run {run_id}")
            ended = live.run.model_copy(deep=True, update={"state": state, "ended": now()})
            with failures_as(f"ending run {run_id}"):
                self._journal.end_run(ended)
            del self._views.live[run_id]
            self._views.files.pop(run_id, None)
            self.appends.ended(run_id)
            if not self._views.finalize(rf, ended):  # written anew from the journal
                return ended.model_copy(deep=True)
            self._views.finishing.add(run_id)
        try:
            with failures_as(doing):
                fsync_path(path)
                fsync_path(self._runs)
            with self._lock:
                self._check_open()
                with failures_as(doing):
                    self._views.mark_final(run_id)
        finally:
            with self._lock:
                self._views.finishing.discard(run_id)
        return ended.model_copy(deep=True)

    # --- readings ---------------------------------------------------------------------

    def append_many(self, batches: Sequence[NewBatch]) -> list[BatchReceipt | Exception]:
        """Store the batches in order with one journal commit (group commit), then write
        them to their run files (:class:`~rigserver.storage.embedded.ingest.GroupCommit`).

        Each batch is checked, then by its own ``check``, and refused alone, its outcome
        the exception: ``RunNotFound``, ``RunNotOpen``, ``SequenceConflict``,
        ``StorageFull``, ``StorageUnavailable``, or ``ValueError`` for a batch that does not
        fit the stand's channel groups (unknown group or channel; an aligned group's
        channels missing or of unequal lengths). A failure of the journal refuses every
        batch of the call that its checks did not refuse (retries too: their first copy
        may have been in the call): the commit is rolled back and the open runs' counters
        and last values are as before the call.
        """
        # copies, digests and the payloads' aligned memory: outside the lock
        prepared = [prepared_batch(nb) for nb in batches]
        self._quiet.touched()
        with self._lock:
            try:
                self._check_open()
            except StorageUnavailable as exc:
                return [exc] * len(batches)
            outcomes, grown = self._ingest.commit(batches, prepared)
        for run_id, count in grown.items():
            self.appends.woken(run_id, count)
        return outcomes

    def receipt(self, run_id: str, seq: int) -> BatchReceipt | None:
        with self._lock:
            self._check_open()
            with failures_as(f"looking up batch {seq} of run {run_id}"):
                stored = self._journal.stored_batch(run_id, seq)
                if stored is None:
                    if run_id not in self._views.live:
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
            live = self._views.live.get(run_id)
            if live is not None:
                channel_group(live.run.stand, group)
                return dict(self._views.last(live, group))
            self._views.final_entry(run_id)
        with self._views.final_file(run_id) as rf:
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
            live = self._views.live.get(run_id)
            if live is not None:
                rf = self._views.view(live, f"reading run {run_id}")
                with self._views.spoiling(live, f"reading run {run_id}"):
                    return rf.read(group, channels, start, stop)
            self._views.final_entry(run_id)
        with self._views.final_file(run_id) as rf:
            return rf.read(group, channels, start, stop)

    # --- corrections --------------------------------------------------------------------

    def corrections(self, run_id: str) -> list[Correction]:
        with self._lock:
            self._check_open()
            with failures_as(f"reading the corrections of run {run_id}"):
                if run_id not in self._views.live:
                    self._journal.entry(run_id)  # RunNotFound
                return self._journal.corrections(run_id)

    def _edit(self, run_id: str, edit: RowEdit) -> CorrectedRow:
        """A correction committed to the journal (then acknowledged), then written to the
        run file (an ended run's final file rewritten by copy and rename)."""
        group, index = edit.group, edit.index
        doing = f"correcting row {index} of {group} of run {run_id}"
        with self._lock:
            self._check_open()
            live = self._views.live.get(run_id)
            run = live.run if live is not None else self._views.final_entry(run_id).run
            with failures_as(doing):
                earlier = self._journal.corrections(run_id)

            def read(lo: int, hi: int) -> dict[str, NDArray[np.float64]]:
                return self.read(run_id, group, None, lo, hi)

            new = new_corrections(run, edit, now(), read, earlier)
            every = [*earlier, *new]
            if new:
                edited = corrected_run(run, every)
                with failures_as(doing):
                    self._journal.add_corrections(edited, new)
                self._views.write_corrections(live, edited, every, doing)
            elif live is None and every:  # a retry: the file may have missed the first try
                with failures_as(doing):
                    self._views.sync_corrections(run)
            row = read(index, index + 1)
        if new:  # the live streams tell their viewers
            self.appends.woken(run_id, run.batches)
        return corrected_row(run_id, group, index, row, every)

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
            live = self._views.live.get(run_id)
            doing = f"storing the results of run {run_id}"
            if live is not None:
                run = live.run.model_copy(deep=True, update={"key_results": checked.key_results})
                rf = self._views.view(live, doing)
                with failures_as(doing):
                    self._journal.set_results(run, checked.text)
                live.run.key_results = dict(checked.key_results)
                with self._views.spoiling(live, doing):
                    rf.write_results(checked, run)
                return
            entry = self._views.final_entry(run_id)
            run = entry.run.model_copy(update={"key_results": checked.key_results})
            with failures_as(doing):
                self._views.rewrite_results(run, checked)
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
        path = self._views.path(run.id)
        with self._lock:
            self._check_open()
            if run.id in self._views.live or path.exists() or self._views.catalogued(run.id):
                return False
        with failures_as(f"writing the file of imported run {run.id}"):
            self._views.write_final(run, batches, checked, corrections)
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

    def run_file(self, run_id: str) -> Path:
        """The final file of an ended run; a fresh snapshot copy for an open run."""
        with self._lock:
            self._check_open()
            live = self._views.live.get(run_id)
            if live is None:
                self._views.final_entry(run_id)
                return self._views.path(run_id)
            return self._views.snapshot(live)

    def close(self) -> None:
        """Write and close every open file, mark the shutdown clean, release the directory."""
        self._quiet.close()
        with self._lock:
            if self._closed:
                return
            self._closed = True
            clean = True
            for run_id in list(self._views.files):
                clean &= self._views.close_file(run_id)
            clean &= not any(live.stale for live in self._views.live.values())
            try:
                with failures_as(f"closing the journal of {self.data_dir}"):
                    self._journal.set_clean_shutdown(clean)
            finally:
                self._journal.close()
                os.close(self._dir_lock)

    # --- internals --------------------------------------------------------------------

    def _write_backlog(self) -> bool:
        """One batch of the backlog of the first open run that has one (the store is quiet:
        :class:`WhenQuiet`); True if any is left."""
        with self._lock:
            return not self._closed and self._views.pay_backlog()

    def _check_open(self) -> None:
        if self._closed:
            raise StorageUnavailable(f"the store of {self.data_dir} is closed")


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
