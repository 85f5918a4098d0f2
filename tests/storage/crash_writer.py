"""Append to a store until killed, printing what was acknowledged (for test_crash.py).

Usage: ``python crash_writer.py STORE RUN_ID FIRST_SEQ FILES_DIR``, STORE a data directory
(HDF5Store), ``backlog:`` and a data directory (HDF5Store writing batches of 1 000 rows or
more to the run file after their acknowledgement) or a ``postgresql:`` URL
(PostgresStore, its run files in FILES_DIR). Prints
``ready`` once the store is open, ``ack SEQ`` after each batch of RUN_ID is acknowledged,
and ``ended RUN_ID`` after a side run (created, two batches, results, finished) is ended;
one side run every 40 seqs.
"""

from __future__ import annotations

import sys
from datetime import UTC, datetime
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from rigserver.storage import HDF5Store, PostgresStore, RunStore
from schemas.runs import Run, RunState, new_run_id


def batch_of(seq: int) -> tuple[str, dict[str, NDArray[np.float64]]]:
    """The batch posted under ``seq``: a function of ``seq`` alone."""
    if seq % 10 == 9:
        return "measurements", {"pin_mass_before": np.array([float(seq)])}
    n = 30_000 if seq % 25 == 0 else 1 + (seq * 7919) % 50
    k = np.arange(n, dtype=np.float64)
    return "friction", {
        "time": seq * 1e5 + k,
        "load": np.full(n, 300.0 + seq % 7),
        "speed": np.full(n, 1000.0),
        "friction_moment": k / (n + seq),
        "revolutions": np.full(n, float(seq)),
    }


def open_store(target: str, files_dir: Path) -> RunStore:
    """The store at ``target``: a ``postgresql:`` URL (run files in ``files_dir``), or a
    data directory (after ``backlog:``, large batches go to the run file's backlog)."""
    if target.startswith("postgresql:"):
        return PostgresStore(target, files_dir=files_dir)
    if target.startswith("backlog:"):
        return HDF5Store(Path(target.removeprefix("backlog:")), backlog_rows=1_000)
    return HDF5Store(Path(target))


def side_run(store: RunStore) -> str:
    run = store.create_run(
        Run(
            id=new_run_id(),
            stand="smts2",
            operator="crash",
            configuration={},
            created=datetime.now(UTC),
        )
    )
    for seq in range(2):
        store.append(run.id, seq, *batch_of(seq + 1))
    store.set_results(run.id, {"values": {"f": 0.1}, "units": {"f": "1"}}, {"f": 0.1})
    store.end_run(run.id, RunState.FINISHED)
    return run.id


def main(target: str, run_id: str, first_seq: str, files_dir: str) -> None:
    store = open_store(target, Path(files_dir))
    print("ready", flush=True)
    seq = int(first_seq)
    while True:
        store.append(run_id, seq, *batch_of(seq))
        print(f"ack {seq}", flush=True)
        if seq % 40 == 20:
            print(f"ended {side_run(store)}", flush=True)
        seq += 1


if __name__ == "__main__":
    main(*sys.argv[1:5])
