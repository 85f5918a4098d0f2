"""The HSDS materialiser: brings the run domains up to date from the PostgreSQL journal.

Every worker runs one thread; the one holding the PostgreSQL advisory lock
:data:`LEADER_LOCK` (a session lock on a connection of its own: it goes when the worker
dies or loses the database) does the work, the others wait to take over. A round takes
the runs whose catalogue batch count is above their materialised count and, per channel
group, the next batches after the group's mark in row order (appends to a run serialise
on its catalogue row, so row order is commit order and the rows are contiguous), writes
them into the run's domain at their absolute rows, has HSDS flush them to storage, and
only then advances the mark in ``rig_hsds_marks(run_id, grp, rows, batches)``. A crash
or an HSDS failure between the write and the mark writes the same rows again in the next
round: nothing is counted that is not in HSDS's storage.
"""

from __future__ import annotations

import logging
import threading
from typing import TYPE_CHECKING, Any

import numpy as np
import psycopg
import psycopg_pool
from numpy.typing import NDArray

from rigserver.storage._checks import channel_group, padded
from rigserver.storage.errors import StorageError
from rigserver.storage.payloads import decode
from schemas.runs import Run

if TYPE_CHECKING:
    from rigserver.storage.cluster.hsds import HsdsArrays

log = logging.getLogger(__name__)

#: The advisory lock held by the worker that materialises
LEADER_LOCK = 0x716754
#: Seconds between rounds when nothing was left to do, or after a failure
IDLE_SECONDS = 0.2
FAILED_SECONDS = 1.0
#: Batches written to HSDS per group and round (one write and one flush per channel)
ROUND_BATCHES = 256
#: Runs looked at per round
ROUND_RUNS = 64

MARKS_SCHEMA = """
CREATE TABLE IF NOT EXISTS rig_hsds_marks (
    run_id TEXT NOT NULL,
    grp TEXT NOT NULL,
    rows BIGINT NOT NULL,
    batches BIGINT NOT NULL,
    PRIMARY KEY (run_id, grp)
);
"""

_BEHIND = """
SELECT r.run, r.batches FROM rig_runs r
LEFT JOIN (SELECT run_id, SUM(batches) AS done FROM rig_hsds_marks GROUP BY run_id) m
    ON m.run_id = r.id
WHERE r.batches > COALESCE(m.done, 0)
ORDER BY r.created LIMIT %s
"""


def materialised_rows(conn: psycopg.Connection[Any], run_id: str, group: str) -> int:
    """Rows of the group in HSDS's storage (0 if none)."""
    row = conn.execute(
        "SELECT rows FROM rig_hsds_marks WHERE run_id = %s AND grp = %s", (run_id, group)
    ).fetchone()
    return 0 if row is None else int(row[0])


class Materialiser:
    """The background thread of one worker (module docstring)."""

    def __init__(self, url: str, pool: psycopg_pool.ConnectionPool, arrays: HsdsArrays) -> None:
        self._url = url
        self._pool = pool
        self._arrays = arrays
        self._stop = threading.Event()
        self._leader: psycopg.Connection[Any] | None = None
        self._thread = threading.Thread(target=self._loop, name="rig-hsds", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        self._thread.join()
        self._resign()

    def _loop(self) -> None:
        while not self._stop.is_set():
            try:
                busy = self._elected() and self.round()
            except (StorageError, psycopg.Error, psycopg_pool.PoolTimeout, OSError) as exc:
                log.warning("materialising run arrays in HSDS failed (retried): %s", exc)
                if isinstance(exc, psycopg.Error | psycopg_pool.PoolTimeout):
                    self._resign()
                self._stop.wait(FAILED_SECONDS)
                continue
            if not busy:
                self._stop.wait(IDLE_SECONDS)

    def _elected(self) -> bool:
        if self._leader is not None and not self._leader.closed:
            self._leader.execute("SELECT 1")  # the lock lives as long as the session
            return True
        conn = psycopg.connect(self._url, autocommit=True, connect_timeout=5)
        row = conn.execute("SELECT pg_try_advisory_lock(%s)", (LEADER_LOCK,)).fetchone()
        if row is None or not row[0]:
            conn.close()
            return False
        self._leader = conn
        return True

    def _resign(self) -> None:
        if self._leader is not None:
            self._leader.close()
            self._leader = None

    def round(self) -> bool:
        """Materialise what is behind, a bounded amount; True if anything was written."""
        with self._pool.connection() as conn:
            behind = conn.execute(_BEHIND, (ROUND_RUNS,)).fetchall()
        wrote = False
        for run_json, _ in behind:
            run = Run.model_validate_json(run_json)
            with self._pool.connection() as conn:
                groups = conn.execute(
                    "SELECT DISTINCT grp FROM rig_batches WHERE run_id = %s", (run.id,)
                ).fetchall()
            for (group,) in groups:
                wrote = self._group(run, str(group)) or wrote
        return wrote

    def _group(self, run: Run, group: str) -> bool:
        with self._pool.connection() as conn:
            mark = materialised_rows(conn, run.id, group)
            rows = conn.execute(
                "SELECT payload, rows, group_rows FROM rig_batches WHERE run_id = %s "
                "AND grp = %s AND group_rows > %s ORDER BY group_rows LIMIT %s",
                (run.id, group, mark, ROUND_BATCHES),
            ).fetchall()
        if not rows:
            return False
        decl = channel_group(run.stand, group)
        parts: dict[str, list[NDArray[np.float64]]] = {c.name: [] for c in decl.channels}
        for payload, n_rows, _ in rows:
            for name, values in padded(decl, decode(bytes(payload)), int(n_rows)).items():
                parts[name].append(values)
        first = int(rows[0][2]) - int(rows[0][1])
        if first != mark:
            raise StorageError(f"run {run.id} group {group}: rows {mark}..{first} missing")
        self._arrays.write(run, group, mark, {n: np.concatenate(p) for n, p in parts.items()})
        with self._pool.connection() as conn:
            conn.execute(
                "INSERT INTO rig_hsds_marks (run_id, grp, rows, batches) VALUES (%s, %s, %s, %s) "
                "ON CONFLICT (run_id, grp) DO UPDATE SET rows = EXCLUDED.rows, "
                "batches = rig_hsds_marks.batches + %s WHERE rig_hsds_marks.rows = %s",
                (run.id, group, int(rows[-1][2]), len(rows), len(rows), mark),
            )
        return True
