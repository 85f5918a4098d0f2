"""PostgresStore: the catalogue and the journal in PostgreSQL, shared by several rigservers.

Tables (created if missing, under an advisory lock so that workers may start together)::

    rig_runs(id, stand, operator, state, created, ended, run, batches, rows, max_seq,
             key_results, results, idem_key)
                                the catalogue: filters are columns, ``run`` the Run JSON,
                                ``idem_key`` the Idempotency-Key it was opened with
    rig_batches(run_id, seq, grp, rows, group_rows, digest, payload)
                                every batch, kept for ever: its receipt and its readings
                                (:func:`~rigserver.storage.payloads.encode`)
    rig_corrections(run_id, n, body)
                                every correction of a run's readings (body: the
                                schemas.corrections.Correction as JSON), committed with the
                                run's count before it is acknowledged; the readings stay

A batch is acknowledged once the transaction that inserted it has committed: PostgreSQL's
WAL is then fsynced (``synchronous_commit=on``), so a receipt survives a crash of the
worker, of the database server and of the machine. The seq and idempotency rules are the
embedded store's, checked by the same helpers (:mod:`~rigserver.storage._checks`).

Several processes. Every append locks its runs' catalogue rows (``SELECT ... FOR UPDATE``,
in id order: no deadlock), so the row counts, the retry lookups and the last values a
batch is checked against are those of the batches committed before it, whichever worker
took them; ending a run takes the same lock and happens once. Every read goes to the
database, so a worker sees what the others stored as soon as it is committed. Every such
commit (and the end of a run) notifies ``rig_runs`` (:mod:`~rigserver.storage.cluster.notify`):
the live streams of every worker wait on :meth:`wait_for_appends` and read the run's row
counts (:meth:`get_run`) when woken. :meth:`readings_version` (the run's batches and
corrections) grows with every stored batch and correction: a results cache in any process
compares it to see that it is stale.

The arrays are read from the journal (the batches overlapping the rows asked for). With
HSDS (``hsds``, the ``cluster`` extra) a background thread materialises every run's arrays
in a domain of its own (:mod:`~rigserver.storage.cluster.materialiser`); with ``hsds_reads`` the
rows materialised there are read from HSDS and the rest from the journal, and while HSDS is
down such reads raise ``StorageUnavailable`` (posts are unaffected: PostgreSQL acknowledges
them). Reads from the journal are the default: they are faster here
(``benchmarks/hsds_reads.py``, docs/scale-out.md). A run's
HDF5 file (:meth:`run_file`) is materialised from the journal into ``files_dir``: once for
an ended run (``runs/<id>.h5``, written atomically, shared by the workers when
``files_dir`` is on a shared file system), afresh for an open run (a snapshot).

Failures of the database (it is down, restarting, the pool has no connection within
:data:`CONNECT_SECONDS`) raise ``StorageUnavailable``, which the API answers with 503 and
Retry-After; nothing was acknowledged.
"""

from __future__ import annotations

import json
import logging
import os
import shutil
import tempfile
import threading
from collections.abc import Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import psycopg
import psycopg_pool
from numpy.typing import NDArray

from rigserver.storage._catalogue import ENTRY_COLUMNS, entry, run_filters
from rigserver.storage._checks import (
    Batch,
    StoredBatch,
    channel_group,
    channel_names,
    check,
    last_finite,
    new_run,
    padded,
    posted_or_refusal,
    reopened,
    retry_receipt,
    stored_receipt,
)
from rigserver.storage._derived import Derived
from rigserver.storage._failures import failures_as, translated
from rigserver.storage._results import check_results
from rigserver.storage._time import as_utc, now
from rigserver.storage.base import NewBatch
from rigserver.storage.cluster.materialiser import MARKS_SCHEMA, materialised_rows
from rigserver.storage.cluster.notify import Appends, notify
from rigserver.storage.corrections import (
    RowEdit,
    RowEdits,
    corrected_row,
    corrected_run,
    new_corrections,
)
from rigserver.storage.errors import (
    RunExists,
    RunNotFound,
    RunNotOpen,
    SequenceConflict,
)
from rigserver.storage.payloads import decode, encode
from rigserver.storage.runfile import RunFile, write_file
from schemas.channels import ChannelGroup
from schemas.corrections import CorrectedRow, Correction
from schemas.readings import BatchReceipt
from schemas.runs import Run, RunPage, RunQuery, RunState

if TYPE_CHECKING:
    from rigserver.storage.cluster.hsds import HsdsArrays
    from rigserver.storage.cluster.hsds_settings import HsdsSettings
    from rigserver.storage.cluster.materialiser import Materialiser

log = logging.getLogger(__name__)

#: Seconds a request waits for a database connection before it is answered 503
CONNECT_SECONDS = 5.0
#: Batches fetched at a time when looking back for a group's last values
_LOOK_BACK = 16
#: Groups whose last values a worker keeps (the cache is emptied beyond)
_CACHED_GROUPS = 4096
#: The advisory lock key under which the tables are created
_SCHEMA_LOCK = 0x716753

#: What the database layer raises when the server, the network or the pool fails
PG_FAILURES: tuple[type[Exception], ...] = (psycopg.Error, psycopg_pool.PoolTimeout, OSError)

_SCHEMA = """
CREATE TABLE IF NOT EXISTS rig_runs (
    id TEXT PRIMARY KEY,
    stand TEXT NOT NULL,
    operator TEXT NOT NULL,
    state TEXT NOT NULL,
    created TIMESTAMPTZ NOT NULL,
    ended TIMESTAMPTZ,
    run TEXT NOT NULL,
    batches BIGINT NOT NULL DEFAULT 0,
    rows TEXT NOT NULL DEFAULT '{}',
    max_seq BIGINT NOT NULL DEFAULT -1,
    key_results TEXT NOT NULL DEFAULT '{}',
    results TEXT,
    idem_key TEXT UNIQUE
);
CREATE INDEX IF NOT EXISTS rig_runs_by_created ON rig_runs (created, id);
CREATE INDEX IF NOT EXISTS rig_runs_by_stand ON rig_runs (stand, created);
CREATE INDEX IF NOT EXISTS rig_runs_by_operator ON rig_runs (operator, created);
CREATE TABLE IF NOT EXISTS rig_batches (
    run_id TEXT NOT NULL REFERENCES rig_runs (id),
    seq BIGINT NOT NULL,
    grp TEXT NOT NULL,
    rows BIGINT NOT NULL,
    group_rows BIGINT NOT NULL,
    digest BYTEA NOT NULL,
    payload BYTEA NOT NULL,
    PRIMARY KEY (run_id, seq)
);
CREATE INDEX IF NOT EXISTS rig_batches_by_rows ON rig_batches (run_id, grp, group_rows);
CREATE TABLE IF NOT EXISTS rig_corrections (
    run_id TEXT NOT NULL REFERENCES rig_runs (id),
    n BIGINT NOT NULL,
    body TEXT NOT NULL,
    PRIMARY KEY (run_id, n)
);
ALTER TABLE rig_batches ALTER COLUMN payload SET STORAGE EXTERNAL;
"""

_RUN_COLUMNS = "run, batches, rows, max_seq, state"


@dataclass(slots=True)
class _Locked:
    """A run as locked by an append: its metadata, counters and the group last values seen."""

    run: Run
    max_seq: int
    last: dict[str, dict[str, float]]
    touched: bool = False


class PostgresStore(Derived, RowEdits):
    """The :class:`~rigserver.storage.base.RunStore` protocol on PostgreSQL (module docstring).

    Parameters
    ----------
    url : str
        A libpq connection string or URL of the database (``RIG_DATABASE_URL``).
    files_dir : Path, optional
        Where run files are materialised (shared by the workers if on a shared file
        system); a temporary directory of this process if ``None``.
    pool_size : int
        Most connections this process holds.
    hsds : HsdsSettings, optional
        The HSDS service holding the run arrays (needs h5pyd); none: the journal only.
    hsds_reads : bool
        Read the rows materialised in HSDS from there (else every read is the journal's).
    """

    def __init__(
        self,
        url: str,
        *,
        files_dir: Path | None = None,
        pool_size: int = 8,
        hsds: HsdsSettings | None = None,
        hsds_reads: bool = False,
    ) -> None:
        self.url = url
        self._own_dir = files_dir is None
        if files_dir is None:
            files_dir = Path(tempfile.mkdtemp(prefix="rig-pg-files-"))
        self.files_dir = files_dir
        self._snapshot_lock = threading.Lock()
        #: (run id, group) -> (the run's batch count, last values): valid while it matches
        self._last_cache: dict[tuple[str, str], tuple[int, dict[str, float]]] = {}
        self._cache_lock = threading.Lock()
        with failures_as(f"opening the database {_safe(url)}", PG_FAILURES):
            (self.files_dir / "runs").mkdir(parents=True, exist_ok=True)
            (self.files_dir / "snapshots").mkdir(parents=True, exist_ok=True)
            self._pool = psycopg_pool.ConnectionPool(
                url,
                min_size=1,
                max_size=pool_size,
                timeout=CONNECT_SECONDS,
                # give up reconnecting soon: the next request starts afresh (1 s backoff),
                # so a restarted server is in use again within a second or two
                reconnect_timeout=CONNECT_SECONDS,
                open=False,
                name="rig",
                # a connection broken by a restart of the server is replaced when taken
                check=psycopg_pool.ConnectionPool.check_connection,
            )
            try:
                self._pool.open(wait=True, timeout=CONNECT_SECONDS)
                with self._pool.connection() as conn, conn.transaction():
                    conn.execute("SELECT pg_advisory_xact_lock(%s)", (_SCHEMA_LOCK,))
                    conn.execute(_SCHEMA)
                    conn.execute(MARKS_SCHEMA)
            except BaseException:
                self._pool.close()
                if self._own_dir:
                    shutil.rmtree(self.files_dir, ignore_errors=True)
                raise
        self._appends: Appends | None = None
        self._appends_lock = threading.Lock()
        self._arrays: HsdsArrays | None = None
        self._materialiser: Materialiser | None = None
        if hsds is not None:
            # the cluster extra: imported only when used
            from rigserver.storage.cluster.hsds import HsdsArrays
            from rigserver.storage.cluster.materialiser import Materialiser

            arrays = HsdsArrays(hsds)
            self._arrays = arrays if hsds_reads else None
            self._materialiser = Materialiser(url, self._pool, arrays)
            self._materialiser.start()

    def __enter__(self) -> PostgresStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # --- runs -------------------------------------------------------------------------

    def create_run(self, run: Run, key: str | None = None) -> Run:
        stored = new_run(run)
        with failures_as(f"creating run {run.id}", PG_FAILURES):
            if key is not None:
                found = self._run_for_key(key)
                if found is not None:
                    return reopened(self.get_run(found), stored, key)
            try:
                with self._pool.connection() as conn:
                    conn.execute(
                        f"INSERT INTO rig_runs {_INSERT_RUN}", _run_values(stored, None, key)
                    )
            except psycopg.errors.UniqueViolation as exc:
                found = None if key is None else self._run_for_key(key)
                if found is not None:  # another worker opened it with the key meanwhile
                    return reopened(self.get_run(found), stored, key or "")
                raise RunExists(f"a run with id {run.id} is stored already") from exc
        return stored

    def _run_for_key(self, key: str) -> str | None:
        with self._pool.connection() as conn:
            row = conn.execute("SELECT id FROM rig_runs WHERE idem_key = %s", (key,)).fetchone()
        return None if row is None else str(row[0])

    def get_run(self, run_id: str) -> Run:
        doing = f"reading the catalogue entry of run {run_id}"
        with failures_as(doing, PG_FAILURES), self._pool.connection() as conn:
            return _select_run(conn, run_id)

    def list_runs(self, query: RunQuery) -> RunPage:
        """Runs matching the query, newest first (``since <= created < until``)."""
        found = run_filters(query)
        where = [f"{column} {op} %s" for column, op, _ in found]
        params = [value for _, _, value in found]
        sql_where = f" WHERE {' AND '.join(where)}" if where else ""
        with failures_as("listing runs", PG_FAILURES), self._pool.connection() as conn:
            count = conn.execute(f"SELECT COUNT(*) FROM rig_runs{sql_where}", params).fetchone()
            rows = conn.execute(
                f"SELECT {_RUN_COLUMNS} FROM rig_runs{sql_where} "
                "ORDER BY created DESC, id DESC LIMIT %s OFFSET %s",
                [*params, query.limit, min(query.offset, 2**63 - 1)],
            ).fetchall()
        total = 0 if count is None else int(count[0])
        return RunPage(total=total, runs=[_run(r) for r in rows])

    def end_run(self, run_id: str, state: RunState) -> Run:
        """Finish or abort an open run, once across all workers (the run's row is locked);
        its final file is then materialised (a failure there is logged: it is made at the
        next :meth:`run_file`)."""
        if state is RunState.OPEN:
            raise ValueError("a run can end as finished or aborted, not open")
        with self._locked_run(run_id, f"ending run {run_id}") as (conn, run):
            if run.state is not RunState.OPEN:
                raise RunNotOpen(f"run {run_id} is already {run.state.value}")
            ended = run.model_copy(update={"state": state, "ended": now()})
            conn.execute(
                "UPDATE rig_runs SET state = %s, ended = %s, run = %s WHERE id = %s",
                (state.value, ended.ended, ended.model_dump_json(), run_id),
            )
            notify(conn, run_id, run.batches)
        try:
            self._final_file(ended)
        except Exception as exc:  # the run has ended; its file is made when next asked for
            log.warning("materialising the file of run %s failed: %s", run_id, exc)
        return ended

    # --- readings ---------------------------------------------------------------------

    def append_many(self, batches: Sequence[NewBatch]) -> list[BatchReceipt | Exception]:
        """Store the batches in order in one transaction; each is refused alone as
        :meth:`HDF5Store.append_many <rigserver.storage.HDF5Store.append_many>` refuses it.
        A failure of the database refuses every batch its checks did not refuse."""
        outcomes: list[BatchReceipt | Exception | None] = [None] * len(batches)
        prepared = [posted_or_refusal(nb) for nb in batches]
        run_ids = sorted({nb.run_id for nb in batches})
        doing = f"storing {len(batches)} batch(es)"
        try:
            with self._pool.connection() as conn, conn.transaction():
                locked = self._lock_runs(conn, run_ids)
                for i, (nb, batch) in enumerate(zip(batches, prepared, strict=True)):
                    outcomes[i] = (
                        batch
                        if isinstance(batch, Exception)
                        else self._stage(conn, nb, batch, locked)
                    )
                for lr in locked.values():
                    if lr.touched:
                        conn.execute(
                            "UPDATE rig_runs SET batches = %s, rows = %s, max_seq = %s "
                            "WHERE id = %s",
                            (lr.run.batches, json.dumps(lr.run.rows), lr.max_seq, lr.run.id),
                        )
                        notify(conn, lr.run.id, lr.run.batches)
        except PG_FAILURES as exc:
            failure = translated(exc, doing)
            # a retry's receipt or conflict may stem from a batch of this call: void
            return [
                failure if o is None or isinstance(o, BatchReceipt | SequenceConflict) else o
                for o in outcomes
            ]
        with self._cache_lock:
            if len(self._last_cache) > _CACHED_GROUPS:  # ended runs' entries go, in time
                self._last_cache.clear()
            for lr in locked.values():
                for group, values in lr.last.items():
                    self._last_cache[(lr.run.id, group)] = (lr.run.batches, dict(values))
        return [o for o in outcomes if o is not None]

    def _lock_runs(self, conn: psycopg.Connection[Any], run_ids: list[str]) -> dict[str, _Locked]:
        rows = conn.execute(
            f"SELECT {_RUN_COLUMNS} FROM rig_runs WHERE id = ANY(%s) ORDER BY id FOR UPDATE",
            (run_ids,),
        ).fetchall()
        return {(run := _run(row)).id: _Locked(run, int(row[3]), {}) for row in rows}

    def _stage(
        self, conn: psycopg.Connection[Any], nb: NewBatch, batch: Batch, locked: dict[str, _Locked]
    ) -> BatchReceipt | Exception:
        """Insert one batch in the open transaction: its receipt, or the exception that
        refuses it. Database failures are raised."""
        run_id, seq, group = nb.run_id, nb.seq, nb.group
        lr = locked.get(run_id)
        try:
            if lr is None:
                raise RunNotFound(f"no run with id {run_id}")
            if seq <= lr.max_seq:  # maybe a retry
                stored = _stored_batch(conn, run_id, seq)
                if stored is not None:
                    return retry_receipt(run_id, seq, stored, batch)
            run = lr.run
            if run.state is not RunState.OPEN:
                raise RunNotOpen(f"run {run_id} is {run.state.value}: it takes no more readings")
            if nb.check is not None:
                nb.check(batch.columns, self._locked_last(conn, lr, group))
            check(run.stand, batch)
        except PG_FAILURES:
            raise
        except Exception as exc:
            return exc
        group_rows = run.rows.get(group, 0) + batch.rows
        conn.execute(
            "INSERT INTO rig_batches (run_id, seq, grp, rows, group_rows, digest, payload) "
            "VALUES (%s, %s, %s, %s, %s, %s, %s)",
            (run_id, seq, group, batch.rows, group_rows, batch.digest, _payload(batch)),
        )
        if group in lr.last:
            _remember_last(lr.last[group], batch)
        run.rows = {**run.rows, group: group_rows}
        run.batches += 1
        lr.max_seq = max(lr.max_seq, seq)
        lr.touched = True
        stored = StoredBatch(group, batch.rows, group_rows, batch.digest)
        return stored_receipt(run_id, seq, stored, duplicate=False)

    def _locked_last(
        self, conn: psycopg.Connection[Any], lr: _Locked, group: str
    ) -> dict[str, float]:
        """The last values of a locked run's group: from this call, the cache if it is of
        the run's current batch count, else the database."""
        found = lr.last.get(group)
        if found is None:
            with self._cache_lock:
                cached = self._last_cache.get((lr.run.id, group))
            if cached is not None and cached[0] == lr.run.batches:
                found = dict(cached[1])
            else:
                found = _last_values(conn, lr.run, group)
            lr.last[group] = found
        return found

    def receipt(self, run_id: str, seq: int) -> BatchReceipt | None:
        doing = f"looking up batch {seq} of run {run_id}"
        with failures_as(doing, PG_FAILURES), self._pool.connection() as conn:
            stored = _stored_batch(conn, run_id, seq)
            if stored is None:
                self._exists(conn, run_id)
                return None
        return stored_receipt(run_id, seq, stored, duplicate=True)

    def last_values(self, run_id: str, group: str) -> dict[str, float]:
        """The last non-NaN value of each channel of ``group``."""
        run = self.get_run(run_id)
        channel_group(run.stand, group)
        with failures_as(f"reading run {run_id}", PG_FAILURES), self._pool.connection() as conn:
            return _last_values(conn, run, group)

    def read(
        self,
        run_id: str,
        group: str,
        channels: list[str] | None = None,
        start: int = 0,
        stop: int | None = None,
    ) -> dict[str, NDArray[np.float64]]:
        """Rows ``start:stop`` (slice semantics) of the channels: from an ended run's
        materialised file if it is there, else from HSDS as far as materialised there and
        from the batches holding the rest."""
        run = self.get_run(run_id)
        decl = channel_group(run.stand, group)
        names = channel_names(decl, channels)
        if run.state is not RunState.OPEN:
            with failures_as(f"reading the file of run {run_id}"):
                try:
                    rf = RunFile.open(self._final_path(run_id), writable=False)
                except FileNotFoundError:
                    pass
                else:
                    with rf:
                        return rf.read(group, names, start, stop)
        lo, hi, _ = slice(start, stop).indices(run.rows.get(group, 0))
        if hi <= lo:
            return {n: np.empty(0) for n in names}
        with failures_as(f"reading run {run_id}", PG_FAILURES), self._pool.connection() as conn:
            done = 0 if self._arrays is None else materialised_rows(conn, run_id, group)
            rows = conn.execute(
                "SELECT payload, rows, group_rows FROM rig_batches WHERE run_id = %s "
                "AND grp = %s AND group_rows > %s AND group_rows - rows < %s "
                "ORDER BY group_rows",
                (run_id, group, max(lo, done), hi),
            ).fetchall()
        if self._arrays is not None and lo < done:
            stored = self._arrays.read(run_id, group, names, lo, min(hi, done))
            if hi <= done:
                return stored
            rest = _journal_rows(decl, names, rows, done, hi)
            return {n: np.concatenate((stored[n], rest[n])) for n in names}
        return _journal_rows(decl, names, rows, lo, hi)

    #: Notifications may be lost while the listener reconnects: waiters read the catalogue
    #: again now and then (:mod:`rigserver.api.routes.live`)
    appends_lossy = True

    def wake_waiters(self) -> None:
        """Wake every live stream waiting (the server is stopping)."""
        with self._appends_lock:
            appends = self._appends
        if appends is not None:
            appends.wake_all()

    async def wait_for_appends(self, run_id: str, batches: int, timeout: float) -> bool:
        """Until any worker stores more than ``batches`` batches of the run or ends it:
        True if notified, False after ``timeout`` seconds (the listener starts at the
        first call)."""
        with self._appends_lock:
            if self._appends is None:
                self._appends = Appends(self.url)
            appends = self._appends
        return await appends.wait(run_id, batches, timeout)

    def materialised(self, run_id: str, group: str) -> int:
        """Rows of the group in HSDS's storage (0 without HSDS)."""
        doing = f"reading the HSDS mark of run {run_id}"
        with failures_as(doing, PG_FAILURES), self._pool.connection() as conn:
            return materialised_rows(conn, run_id, group)

    # --- results and files ------------------------------------------------------------

    def set_results(
        self, run_id: str, results: Mapping[str, Any], key_results: Mapping[str, float]
    ) -> None:
        checked = check_results(results, key_results)
        with self._locked_run(run_id, f"storing the results of run {run_id}") as (conn, run):
            run = run.model_copy(update={"key_results": checked.key_results})
            conn.execute(
                "UPDATE rig_runs SET run = %s, key_results = %s, results = %s WHERE id = %s",
                (run.model_dump_json(), json.dumps(checked.key_results), checked.text, run_id),
            )
        if run.state is not RunState.OPEN:  # the final file takes the results
            self._final_file(run)

    def results(self, run_id: str) -> dict[str, Any] | None:
        with failures_as(f"reading the results of run {run_id}", PG_FAILURES):
            text = self._results_text(run_id)
        return None if text is None else dict(json.loads(text))

    def _results_text(self, run_id: str) -> str | None:
        with self._pool.connection() as conn:
            row = conn.execute("SELECT results FROM rig_runs WHERE id = %s", (run_id,)).fetchone()
        if row is None:
            raise RunNotFound(f"no run with id {run_id}")
        return None if row[0] is None else str(row[0])

    def run_file(self, run_id: str) -> Path:
        """The ended run's final file (materialised once); a fresh snapshot for an open run."""
        run = self.get_run(run_id)
        if run.state is not RunState.OPEN:
            path = self._final_path(run_id)
            if not path.exists():
                self._final_file(run)
            return path
        snapshot = self.files_dir / "snapshots" / f"{run_id}.h5"
        with self._snapshot_lock:
            self._materialise(run, snapshot, final=False)
        return snapshot

    def _final_path(self, run_id: str) -> Path:
        return self.files_dir / "runs" / f"{run_id}.h5"

    def _final_file(self, run: Run) -> None:
        self._materialise(run, self._final_path(run.id), final=True)

    def _materialise(self, run: Run, path: Path, *, final: bool) -> None:
        """Write the run's file from the journal: under a name of this process and thread,
        then renamed over ``path`` (workers sharing ``files_dir`` never see half a file)."""
        doing = f"writing the file of run {run.id}"
        with failures_as(doing, PG_FAILURES):
            text = self._results_text(run.id)
            results = None if text is None else check_results(json.loads(text), run.key_results)
            own = path.with_name(f"{path.stem}.{os.getpid()}.{threading.get_ident()}.h5")
            with self._pool.connection() as conn, conn.transaction():
                fixes = _corrections(conn, run.id)
                write_file(
                    own, run, _file_batches(conn, run), results, final=final, corrections=fixes
                )
            os.replace(own, path)

    def corrections(self, run_id: str) -> list[Correction]:
        doing = f"reading the corrections of run {run_id}"
        with failures_as(doing, PG_FAILURES), self._pool.connection() as conn:
            _select_run(conn, run_id)  # RunNotFound
            return _corrections(conn, run_id)

    def _edit(self, run_id: str, edit: RowEdit) -> CorrectedRow:
        """A correction committed with the run's row locked (one at a time across the
        workers), then an ended run's file materialised again."""
        group, index = edit.group, edit.index

        def read(lo: int, hi: int) -> dict[str, NDArray[np.float64]]:
            return self.read(run_id, group, None, lo, hi)

        doing = f"correcting row {index} of {group} of run {run_id}"
        with self._locked_run(run_id, doing) as (conn, run):
            earlier = _corrections(conn, run_id)
            new = new_corrections(run, edit, now(), read, earlier)
            every = [*earlier, *new]
            run = corrected_run(run, every)
            if new:
                _add_corrections(conn, run_id, new)
                conn.execute(
                    "UPDATE rig_runs SET run = %s WHERE id = %s", (run.model_dump_json(), run_id)
                )
                notify(conn, run_id, run.batches)
        if new and run.state is not RunState.OPEN:  # the final file takes the corrections
            try:
                self._final_file(run)
            except Exception:  # made at the next run_file, from the database
                self._final_path(run_id).unlink(missing_ok=True)
                raise
        return corrected_row(run_id, group, index, read(index, index + 1), every)

    def import_run(
        self,
        run: Run,
        key: str | None,
        results: Mapping[str, Any] | None,
        batches: Iterable[tuple[int, StoredBatch, Mapping[str, NDArray[np.float64]]]],
        corrections: Sequence[Correction] = (),
    ) -> bool:
        """Store a run of another store whole, in one transaction: its catalogue entry as it
        is (state, times, counters, results) and its batches (seq, receipt, every channel),
        in the order stored; False, and nothing changes, if a run with its id is here
        already (``rigserver migrate``)."""
        text = None if results is None else check_results(results, run.key_results).text
        max_seq = -1
        doing = f"importing run {run.id}"
        with (
            failures_as(doing, PG_FAILURES),
            self._pool.connection() as conn,
            conn.transaction(),
        ):
            inserted = conn.execute(
                f"INSERT INTO rig_runs {_INSERT_RUN} ON CONFLICT (id) DO NOTHING RETURNING id",
                _run_values(run, text, key),
            ).fetchone()
            if inserted is None:
                return False
            with conn.cursor() as cur:
                for seq, stored, columns in batches:
                    cur.execute(
                        "INSERT INTO rig_batches "
                        "(run_id, seq, grp, rows, group_rows, digest, payload) "
                        "VALUES (%s, %s, %s, %s, %s, %s, %s)",
                        (
                            run.id,
                            seq,
                            stored.group,
                            stored.rows,
                            stored.group_rows,
                            stored.digest,
                            _encoded(dict(columns)),
                        ),
                    )
                    max_seq = max(max_seq, seq)
            conn.execute("UPDATE rig_runs SET max_seq = %s WHERE id = %s", (max_seq, run.id))
            if corrections:
                _add_corrections(conn, run.id, corrections)
        return True

    def close(self) -> None:
        """Stop materialising; close the pool; remove the files directory if it was this
        process's own."""
        if self._materialiser is not None:
            self._materialiser.stop()
        if self._appends is not None:
            self._appends.close()
        self._pool.close()
        if self._own_dir:
            shutil.rmtree(self.files_dir, ignore_errors=True)

    @contextmanager
    def _locked_run(self, run_id: str, doing: str) -> Iterator[tuple[psycopg.Connection[Any], Run]]:
        """A transaction with the run's catalogue row locked until its commit (one at a
        time across the workers): the connection and the run; ``RunNotFound``."""
        with failures_as(doing, PG_FAILURES), self._pool.connection() as conn, conn.transaction():
            yield conn, _select_run(conn, run_id, lock=True)

    def _exists(self, conn: psycopg.Connection[Any], run_id: str) -> None:
        if conn.execute("SELECT 1 FROM rig_runs WHERE id = %s", (run_id,)).fetchone() is None:
            raise RunNotFound(f"no run with id {run_id}")


def _safe(url: str) -> str:
    """The URL without a password, for messages."""
    try:
        info = psycopg.conninfo.conninfo_to_dict(url)
    except psycopg.ProgrammingError:
        return "(unparsable URL)"
    return " ".join(f"{k}={v}" for k, v in info.items() if k != "password")


#: The columns of a new catalogue entry (:func:`_run_values`)
_INSERT_RUN = f"({ENTRY_COLUMNS}, idem_key) VALUES (%s, %s, %s, %s, %s, %s, %s, %s, %s, %s, %s, %s)"


def _run_values(run: Run, results: str | None, key: str | None) -> tuple[object, ...]:
    return (*entry(run, results, as_utc), key)


def _run(row: tuple[Any, ...]) -> Run:
    run = Run.model_validate_json(row[0])
    return run.model_copy(update={"batches": int(row[1]), "rows": json.loads(row[2])})


def _corrections(conn: psycopg.Connection[Any], run_id: str) -> list[Correction]:
    rows = conn.execute(
        "SELECT body FROM rig_corrections WHERE run_id = %s ORDER BY n", (run_id,)
    ).fetchall()
    return [Correction.model_validate_json(row[0]) for row in rows]


def _add_corrections(
    conn: psycopg.Connection[Any], run_id: str, corrections: Sequence[Correction]
) -> None:
    with conn.cursor() as cur:
        cur.executemany(
            "INSERT INTO rig_corrections (run_id, n, body) VALUES (%s, %s, %s)",
            [(run_id, c.n, c.model_dump_json()) for c in corrections],
        )


def _select_run(conn: psycopg.Connection[Any], run_id: str, *, lock: bool = False) -> Run:
    """The run (with ``lock``, its catalogue row locked until the transaction ends);
    ``RunNotFound``."""
    row = conn.execute(
        f"SELECT {_RUN_COLUMNS} FROM rig_runs WHERE id = %s{' FOR UPDATE' if lock else ''}",
        (run_id,),
    ).fetchone()
    if row is None:
        raise RunNotFound(f"no run with id {run_id}")
    return _run(row)


def _payload(batch: Batch) -> bytes:
    return _encoded(batch.columns)


def _encoded(columns: dict[str, NDArray[np.float64]]) -> bytes:
    return b"".join(encode(columns).parts)


def _stored_batch(conn: psycopg.Connection[Any], run_id: str, seq: int) -> StoredBatch | None:
    row = conn.execute(
        "SELECT grp, rows, group_rows, digest FROM rig_batches WHERE run_id = %s AND seq = %s",
        (run_id, seq),
    ).fetchone()
    return None if row is None else StoredBatch(row[0], int(row[1]), int(row[2]), bytes(row[3]))


def _last_values(conn: psycopg.Connection[Any], run: Run, group: str) -> dict[str, float]:
    """The last non-NaN value of each channel of the group, looking back batch by batch."""
    wanted = {c.name for c in channel_group(run.stand, group).channels}
    found: dict[str, float] = {}
    below = 2**62
    while wanted - set(found):
        rows = conn.execute(
            "SELECT payload, group_rows FROM rig_batches WHERE run_id = %s AND grp = %s "
            "AND group_rows < %s ORDER BY group_rows DESC LIMIT %s",
            (run.id, group, below, _LOOK_BACK),
        ).fetchall()
        for payload, group_rows in rows:
            for name, values in decode(bytes(payload)).items():
                if name not in found and (value := last_finite(values)) is not None:
                    found[name] = value
            below = int(group_rows)
        if len(rows) < _LOOK_BACK:
            break
    return found


def _journal_rows(
    decl: ChannelGroup, names: list[str], rows: list[tuple[Any, ...]], lo: int, hi: int
) -> dict[str, NDArray[np.float64]]:
    """Rows ``lo:hi`` of the channels from the batches ``rows`` (payload, rows, group_rows)
    that hold them, in order."""
    if not rows:
        return {n: np.empty(0) for n in names}
    first = int(rows[0][2]) - int(rows[0][1])
    parts: dict[str, list[NDArray[np.float64]]] = {n: [] for n in names}
    for payload, n_rows, _ in rows:
        full = padded(decl, decode(bytes(payload)), int(n_rows))
        for n in names:
            parts[n].append(full[n])
    return {n: np.concatenate(p)[lo - first : hi - first].copy() for n, p in parts.items()}


def _remember_last(last: dict[str, float], batch: Batch) -> None:
    for name, values in batch.columns.items():
        value = last_finite(values) if len(values) else None
        if value is not None:
            last[name] = value


def _file_batches(
    conn: psycopg.Connection[Any], run: Run
) -> Iterator[tuple[str, dict[str, NDArray[np.float64]], int]]:
    """The run's batches as a run file takes them: (group, every channel, rows), in order."""
    with conn.cursor(name=f"rig_file_{run.id}") as cur:
        cur.execute(
            "SELECT grp, payload, rows FROM rig_batches WHERE run_id = %s ORDER BY grp, group_rows",
            (run.id,),
        )
        for group, payload, rows in cur:
            decl = channel_group(run.stand, group)
            yield group, padded(decl, decode(bytes(payload)), int(rows)), int(rows)
