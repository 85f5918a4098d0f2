"""How fast the lab PC's spool acknowledges a batch (``rigclient``, issue 16).

Run from the repository root::

    .venv/bin/python benchmarks/spool.py [--batches N] [--rows R]

Prints one JSON object: the median time of ``run.post`` of an SMTs-2 friction batch
(R rows, five channels; the sender off, so only the spool is measured: the check of the
names, the npz payload, one fsync'd SQLite WAL commit), and the baseline measured in turn
with it, batch by batch, on the same disk: the same npz payload made and inserted bare into a
WAL database with ``synchronous=FULL``, one commit each (the floor of a durable
acknowledgement). The ratio is post / baseline; the target is a ratio below 2 (the spool's
bookkeeping, its seq, bounds and cursor, costs less than the fsync it cannot avoid).
"""

from __future__ import annotations

import argparse
import json
import sqlite3
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from rigclient import Client
from rigclient.http import npz_bytes

TARGET_RATIO = 2.0


def friction(rows: int, start: int) -> dict[str, np.ndarray]:
    t = (start + np.arange(rows)) * 0.5
    return {
        "time": t,
        "load": np.full(rows, 300.0),
        "speed": np.full(rows, 1000.0),
        "friction_moment": 2.9 + 0.01 * np.sin(t),
        "revolutions": np.floor(t / 6.0),
    }


def measure(directory: Path, batches: int, rows: int) -> tuple[list[float], list[float]]:
    """Times of ``run.post`` and of the bare insert, taken in turn (the same load on both)."""
    bare = sqlite3.connect(directory / "bare.sqlite", isolation_level=None)
    bare.execute("PRAGMA journal_mode=WAL")
    bare.execute("PRAGMA synchronous=FULL")
    bare.execute("CREATE TABLE b (seq INTEGER PRIMARY KEY, payload BLOB)")
    post, insert = [], []
    with Client("http://127.0.0.1:9", None, spool=directory / "spool", start=False) as client:
        run = client.open_run(stand="smts2", operator="bench")
        for k in range(batches):
            columns = friction(rows, k * rows)
            start = time.perf_counter()
            run.post("friction", columns)
            post.append(time.perf_counter() - start)
            start = time.perf_counter()
            payload = npz_bytes(columns)
            bare.execute("BEGIN")
            bare.execute("INSERT INTO b VALUES (?, ?)", (k, payload))
            bare.execute("COMMIT")
            insert.append(time.perf_counter() - start)
    bare.close()
    return post, insert


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--batches", type=int, default=300)
    parser.add_argument("--rows", type=int, default=200)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="rig-spool-bench-") as tmp:
        posts, inserts = measure(Path(tmp), args.batches, args.rows)
    post, bare = statistics.median(posts), statistics.median(inserts)
    ratio = post / bare
    print(
        json.dumps(
            {
                "batches": args.batches,
                "rows_per_batch": args.rows,
                "post_ms": round(post * 1e3, 3),
                "baseline_insert_ms": round(bare * 1e3, 3),
                "ratio": round(ratio, 2),
                "rows_per_s": round(args.rows / post),
                "target_ratio": TARGET_RATIO,
                "met": ratio < TARGET_RATIO,
            },
            indent=2,
        )
    )


if __name__ == "__main__":
    main()
