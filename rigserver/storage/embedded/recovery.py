"""Opening a data directory after a stop: the open runs loaded, their files rebuilt from
the journal after an unclean shutdown, the ends that did not complete completed, the final
files brought up to the journal's corrections; a lost journal's catalogue rebuilt from the
run files (``/entry@run``), the readings of unfinished files taken back into the journal.
"""

from __future__ import annotations

import logging
from pathlib import Path

from rigserver.storage._checks import prepare, stand_groups
from rigserver.storage._failures import UNREADABLE
from rigserver.storage.embedded.journal import Journal, Synchronous
from rigserver.storage.embedded.views import Live, RunFiles
from rigserver.storage.errors import StorageError
from rigserver.storage.runfile import RunFile, fsync_path, read_summary
from schemas.runs import Run, RunState

log = logging.getLogger(__name__)

#: What bringing a final file up to its corrections may raise at start (logged, left).
_SYNC_FAILURES: tuple[type[Exception], ...] = (*UNREADABLE, StorageError)
#: Rows per batch when the readings of an unfinished file are taken back into the journal.
_IMPORT_ROWS = 1 << 20


def open_journal(data_dir: Path, synchronous: Synchronous) -> tuple[Journal, bool]:
    """The directory's journal, and whether it is new (then a WAL or payload files left
    beside a lost journal belong to no journal and are removed)."""
    path = data_dir / "journal.sqlite"
    new = not path.exists()
    if new:
        for stale in (path.with_name(path.name + s) for s in ("-wal", "-shm")):
            stale.unlink(missing_ok=True)
        for stale in data_dir.glob("payloads/*.bin"):
            stale.unlink()
    journal = Journal(path, synchronous=synchronous)
    fsync_path(data_dir)
    return journal, new


def recover_directory(files: RunFiles, *, new: bool) -> None:
    """Bring the directory to what its journal says: temp files and snapshots removed, a
    new journal's catalogue rebuilt from the run files, the payloads of final runs dropped,
    the open runs loaded (rebuilt after an unclean shutdown); the store is then open
    (the clean-shutdown marker "0")."""
    for leftover in [*files.runs.glob("*.tmp"), *files.snapshots.iterdir()]:
        leftover.unlink()
    if new:
        rebuild_catalogue(files.journal, files.runs)
    for run_id in files.journal.final_runs_with_payloads():
        files.journal.drop_payloads(run_id)
    clean = files.journal.clean_shutdown()
    files.journal.set_clean_shutdown(False)
    recover(files, clean=clean)


def recover(files: RunFiles, *, clean: bool) -> None:
    """Load the open runs; rebuild their files after an unclean shutdown; finish the
    files of ended runs whose end did not complete."""
    unfinished = files.journal.unfinished()
    if not clean:
        _recover_corrections(files, {e.run.id for e in unfinished})
    for entry in unfinished:
        run = entry.run
        if run.state is not RunState.OPEN:
            log.info("completing the end of run %s", run.id)
            files.finish_file(run)
            continue
        files.live[run.id] = Live(run, max_seq=files.journal.max_seq(run.id))
        if not clean or not files.path(run.id).exists():
            log.info("rebuilding the file of open run %s from the journal", run.id)
            files.rebuild(run, final=False)


def _recover_corrections(files: RunFiles, unfinished: set[str]) -> None:
    """The final files of corrected runs brought up to the journal's corrections."""
    for run_id in files.journal.corrected_runs():
        if run_id in unfinished:
            continue  # its file is rebuilt from the journal, corrections included
        try:
            files.sync_corrections(files.journal.entry(run_id).run)
        except _SYNC_FAILURES as exc:
            log.warning("run %s: its corrections could not reach its file (%s)", run_id, exc)


def rebuild_catalogue(journal: Journal, runs: Path) -> None:
    """Fill a new journal from the run files; unfinished files' readings are imported."""
    for path in sorted(runs.glob("*.h5")):
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
            journal.insert_run(run, file_final=True, results=summary.results)
            continue
        run = run.model_copy(
            update={
                "state": RunState.OPEN,
                "ended": None,
                "batches": 0,
                "rows": {g.name: 0 for g in stand_groups(run.stand)},
            }
        )
        journal.insert_run(run, results=summary.results)
        _import_readings(journal, run, path)
        log.warning("run %s recovered from its unfinished file", run.id)


def _import_readings(journal: Journal, run: Run, path: Path) -> None:
    """The readings of a run file into the journal, as batches with negative seqs."""
    rows = {g.name: 0 for g in stand_groups(run.stand)}
    seq = -1
    with RunFile.open(path, writable=False) as rf:
        for group in rows:
            for start in range(0, rf.rows(group), _IMPORT_ROWS):
                columns = rf.read(group, None, start, start + _IMPORT_ROWS)
                batch = prepare(group, columns)
                rows[group] += batch.rows
                journal.begin()
                journal.add_batch(run.id, seq, batch, rows[group])
                run.rows, run.batches = dict(rows), -seq
                journal.set_counters([run])
                journal.commit()
                seq -= 1
