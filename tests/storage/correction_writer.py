"""Correct readings of two runs until killed, printing what was acknowledged (for
test_corrections_crash.py).

Usage: ``python correction_writer.py DATA_DIR OPEN_RUN FINISHED_RUN``. Prints ``ready`` once
the store is open, then ``ack RUN N`` after the N-th correction of RUN is acknowledged,
alternating between the open run and the finished one (whose final file is rewritten with
each correction).
"""

from __future__ import annotations

import sys
from pathlib import Path

from rigserver.storage import HDF5Store

ROWS = 50


def correction(n: int) -> tuple[int, float]:
    """The row and the friction moment (N·m) the ``n``-th correction of a run sets."""
    return n % ROWS, 1.0 + n * 1e-4


def main(data_dir: str, *run_ids: str) -> None:
    store = HDF5Store(Path(data_dir))
    print("ready", flush=True)
    while True:
        for run_id in run_ids:
            n = store.get_run(run_id).corrections + 1
            row, value = correction(n)
            store.correct_reading(run_id, "friction", row, {"friction_moment": value}, "r", "k")
            print(f"ack {run_id} {n}", flush=True)


if __name__ == "__main__":
    main(*sys.argv[1:4])
