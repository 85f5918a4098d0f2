"""The open runs' HDF5 files as views of the journal: opened, kept open (the most recently
used), paid their backlog, rebuilt from the journal when stale or missing, finalized; and
the ended runs' final files, read or rewritten by copy and rename.

A view is stale when its file lags the journal or may be damaged (a write failed): it is
rebuilt at its next use, never trusted (the journal makes a batch durable, the file only
follows it).
"""

from __future__ import annotations

import json
import logging
import os
import shutil
from collections import OrderedDict
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from rigserver.storage._checks import StoredBatch, channel_group, padded
from rigserver.storage._failures import LOW_LEVEL, UNREADABLE, failures_as, translated
from rigserver.storage._results import CheckedResults, check_results
from rigserver.storage.embedded.backlog import PIECE_ROWS, Backlog
from rigserver.storage.embedded.journal import CatalogueEntry, Journal
from rigserver.storage.errors import (
    RunDamaged,
    RunNotFound,
    RunNotOpen,
    StorageError,
    StorageUnavailable,
)
from rigserver.storage.runfile import RunFile, replacing, write_file
from schemas.corrections import Correction
from schemas.runs import Run

log = logging.getLogger(__name__)

#: Open runs whose HDF5 file is kept open; the least recently used are closed beyond this.
MAX_OPEN_FILES = 32
#: What reading an opened run file raises when it is corrupt (not: a channel it lacks).
_CORRUPT: tuple[type[Exception], ...] = (*LOW_LEVEL, KeyError)
#: What writing a file's backlog and closing it may raise.
_CLOSING: tuple[type[Exception], ...] = (*LOW_LEVEL, StorageError)


@dataclass(slots=True)
class Live:
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


class RunFiles:
    """The run files of a data directory (``runs/``, ``snapshots/``) and the open runs
    (:attr:`live`), whose files are views of ``journal``; called under the store's lock."""

    def __init__(self, journal: Journal, runs: Path, snapshots: Path) -> None:
        self.journal = journal
        self.runs = runs
        self.snapshots = snapshots
        self.live: dict[str, Live] = {}
        self.files: OrderedDict[str, RunFile] = OrderedDict()
        #: ended runs whose finalized file is being fsynced (outside the lock)
        self.finishing: set[str] = set()

    def path(self, run_id: str) -> Path:
        return self.runs / f"{run_id}.h5"

    def last(self, live: Live, group: str) -> dict[str, float]:
        """The open run's cached last values of ``group`` (read from its file if need be)."""
        cached = live.last.get(group)
        if cached is None:
            rf = self.view(live, f"reading run {live.run.id}")
            with self.spoiling(live, f"reading run {live.run.id}"):
                cached = rf.last_values(group)
            live.last[group] = cached
        return cached

    def open_run(self, run_id: str) -> Live:
        live = self.live.get(run_id)
        if live is None:
            with failures_as(f"looking up run {run_id}"):
                state = self.journal.entry(run_id).run.state
            raise RunNotOpen(f"run {run_id} is {state.value}: it takes no more readings")
        return live

    @contextmanager
    def final_file(self, run_id: str) -> Iterator[RunFile]:
        """The ended run's file, read-only; ``RunDamaged`` if it is missing or corrupt (the
        journal no longer holds its readings)."""
        path = self.path(run_id)
        try:
            rf = RunFile.open(path, writable=False)
        except UNREADABLE as exc:
            raise _damaged(run_id, path, exc) from exc
        with rf:
            try:
                yield rf
            except _CORRUPT as exc:
                raise _damaged(run_id, path, exc) from exc

    def final_entry(self, run_id: str) -> CatalogueEntry:
        """The catalogue entry of a run that is not open, its file made final if need be."""
        with failures_as(f"looking up run {run_id}"):
            entry = self.journal.entry(run_id)
        if not entry.file_final and run_id not in self.finishing:  # finalized, fsync due
            self.finish_file(entry.run)
        return entry

    def view(self, live: Live, doing: str) -> RunFile:
        """The open run's file, opened if need be, rebuilt first if stale or missing."""
        run_id = live.run.id
        with self.spoiling(live, doing):
            if live.stale:
                self.close_file(run_id)
                live.backlog.clear()
                self.rebuild(live.run, final=False)
                live.stale = False
            rf = self.files.get(run_id)
            if rf is None:
                path = self.path(run_id)
                if not path.exists():
                    self.rebuild(live.run, final=False)
                rf = self.keep_open(run_id, RunFile.open(path, writable=True))
            else:
                self.files.move_to_end(run_id)
            if live.backlog:
                self.pay(live, rf, len(live.backlog.owed))
            return rf

    def pay(self, live: Live, rf: RunFile, count: int) -> None:
        """Write the ``count`` oldest batches of the run's backlog to its file, read back
        from the journal a piece at a time; if that fails, the view is stale (the rebuild
        from the journal brings them in)."""
        try:
            for o in live.backlog.take(count):
                decl = channel_group(live.run.stand, o.group)
                # pieces that end where the file's chunks do: HDF5 writes whole chunks as
                # they are, without holding them in its chunk cache
                first = PIECE_ROWS - rf.rows(o.group) % PIECE_ROWS
                pieces = self.journal.payload_pieces(live.run.id, o.at, o.size, PIECE_ROWS, first)
                for piece in pieces:
                    rows = max(len(v) for v in piece.values())
                    rf.append(o.group, padded(decl, piece, rows), rows)
                    rf.write_pending()  # the piece's buffers are read into again
        except BaseException:
            self.spoil(live)
            raise

    @contextmanager
    def spoiling(self, live: Live, doing: str) -> Iterator[None]:
        """Translate the failures of the block; the run's file view is then stale."""
        try:
            yield
        except LOW_LEVEL as exc:
            self.spoil(live)
            raise translated(exc, doing) from exc

    def keep_open(self, run_id: str, rf: RunFile) -> RunFile:
        self.files[run_id] = rf
        while len(self.files) > MAX_OPEN_FILES:
            self.close_file(next(iter(self.files)))
        return rf

    def close_file(self, run_id: str) -> bool:
        """Write the run's backlog and close its file if open; False (and the view stale)
        if that failed."""
        rf = self.files.pop(run_id, None)
        if rf is None:
            return True
        live = self.live.get(run_id)
        try:
            try:
                if live is not None and live.backlog and not live.stale:
                    self.pay(live, rf, len(live.backlog.owed))
            finally:
                rf.close()
        except _CLOSING as exc:
            log.warning("closing the file of run %s failed (%s); it will be rebuilt", run_id, exc)
            if live is not None:
                live.stale = True
                live.backlog.clear()
            return False
        return True

    def spoil(self, live: Live) -> None:
        live.stale = True
        live.backlog.clear()  # the rebuild from the journal brings every batch in
        self.close_file(live.run.id)

    def rebuild(self, run: Run, *, final: bool) -> None:
        """Write the run's file anew from the journal (atomically)."""
        text = self.journal.results(run.id)
        results = None if text is None else check_results(json.loads(text), run.key_results)

        def batches() -> Iterator[tuple[str, dict[str, NDArray[np.float64]], int]]:
            for group, columns in self.journal.payloads(run.id):
                rows = max((len(v) for v in columns.values()), default=0)
                yield group, padded(channel_group(run.stand, group), columns, rows), rows

        corrections = self.journal.corrections(run.id)
        write_file(self.path(run.id), run, batches(), results, final=final, corrections=corrections)

    def finish_file(self, run: Run) -> None:
        """Write the ended run's final file anew from the journal (fsynced), then drop its
        readings from the journal."""
        with failures_as(f"finalizing the file of run {run.id}"):
            self.rebuild(run, final=True)
            self.mark_final(run.id)

    def mark_final(self, run_id: str) -> None:
        """The run's file is final and fsynced: its readings leave the journal."""
        self.journal.mark_final(run_id)
        (self.snapshots / f"{run_id}.h5").unlink(missing_ok=True)

    def rewrite_results(self, run: Run, results: CheckedResults) -> None:
        self.rewrite(run, lambda rf: rf.write_results(results, run))

    def rewrite(self, run: Run, change: Callable[[RunFile], None]) -> None:
        """Change an ended run's final file: a copy changed, fsynced and renamed over it."""
        path = self.path(run.id)
        with replacing(path) as tmp:
            shutil.copyfile(path, tmp)
            with RunFile.open(tmp, writable=True) as rf:
                change(rf)

    def finalize(self, rf: RunFile, ended: Run) -> bool:
        """Finalize an ended run's open file (not yet fsynced); False when it failed where
        the journal did not (its cached chunks written on a full disk) and the final file
        was written anew from the journal instead (fsynced, final)."""
        try:
            with failures_as(f"finalizing the file of run {ended.id}"):
                try:
                    rf.finalize(ended)
                finally:
                    rf.close()
        except StorageError as exc:
            log.warning(
                "finalizing run %s: %s; its file is written from the journal", ended.id, exc
            )
            self.finish_file(ended)
            return False
        return True

    def snapshot(self, live: Live) -> Path:
        """A fresh consistent copy of an open run's file (``snapshots/<id>.h5``)."""
        run_id = live.run.id
        rf = self.view(live, f"flushing run {run_id}")
        with self.spoiling(live, f"flushing run {run_id}"):
            rf.flush()
        snapshot = self.snapshots / f"{run_id}.h5"
        tmp = snapshot.with_name(snapshot.name + ".tmp")
        with failures_as(f"copying a snapshot of run {run_id}"):
            shutil.copyfile(rf.path, tmp)
            os.replace(tmp, snapshot)
        return snapshot

    def pay_backlog(self) -> bool:
        """One batch of the backlog of the first open run that has one (the store is
        quiet); True if any is left."""
        for live in self.live.values():
            live.direct = False  # whatever stream made it so has paused
        owing = [live for live in self.live.values() if live.backlog and not live.stale]
        if not owing:
            return False
        live = owing[0]
        rf = self.files.get(live.run.id)
        try:
            if rf is None:  # not expected: a file is closed only with its backlog written
                raise StorageUnavailable(f"the file of run {live.run.id} is not open")
            with self.spoiling(live, f"writing the backlog of run {live.run.id}"):
                self.pay(live, rf, 1)
        except StorageError as exc:
            log.warning("%s; the file will be rebuilt from the journal", exc)
            self.spoil(live)
        return len(owing) > 1 or bool(live.backlog)

    def write_final(
        self,
        run: Run,
        batches: Iterable[tuple[int, StoredBatch, Mapping[str, NDArray[np.float64]]]],
        results: CheckedResults | None,
        corrections: Sequence[Correction],
    ) -> None:
        """Write an imported run's final file whole (a temp file renamed when complete)."""
        write_file(
            self.path(run.id),
            run,
            ((s.group, dict(columns), s.rows) for _, s, columns in batches),
            results,
            final=True,
            corrections=list(corrections),
        )

    def catalogued(self, run_id: str) -> bool:
        """Whether the catalogue has the run (damaged or not)."""
        with failures_as(f"looking up run {run_id}"):
            try:
                self.journal.entry(run_id)
            except RunNotFound:
                return False
            except RunDamaged:
                pass
        return True

    def write_corrections(
        self, live: Live | None, edited: Run, every: list[Correction], doing: str
    ) -> None:
        """Write the run's corrections, committed to the journal, to its file: an open
        run's view, an ended run's final file by copy and rename."""
        if live is not None:
            live.run.corrections = edited.corrections
            live.run.corrected_after_finish = edited.corrected_after_finish
            rf = self.view(live, doing)
            with self.spoiling(live, doing):
                rf.write_corrections(every, edited)
            return
        with failures_as(f"{doing} (it is stored; the file follows)"):
            self.rewrite(edited, lambda rf: rf.write_corrections(every, edited))

    def sync_corrections(self, run: Run) -> None:
        """Bring an ended run's final file up to the corrections of the journal (a crash
        between a correction's commit and the file's rewrite left it behind)."""
        every = self.journal.corrections(run.id)
        with RunFile.open(self.path(run.id), writable=False) as rf:
            held = len(rf.corrections())
        if held != len(every):
            log.info("writing %d correction(s) of run %s to its file", len(every), run.id)
            self.rewrite(run, lambda rf: rf.write_corrections(every, run))


def _damaged(run_id: str, path: Path, exc: Exception) -> RunDamaged:
    return RunDamaged(f"run {run_id} is damaged: its file {path.name} cannot be read ({exc})")
