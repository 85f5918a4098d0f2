"""Reading a long run's arrays from HSDS against reading them from the PostgreSQL journal,
and how fast the materialiser fills HSDS (issue 19).

Run from the repository root (needs the ``postgresql`` package and the cluster extra)::

    .venv/bin/python benchmarks/hsds_reads.py [--quick]

Prints one JSON object. One run of the SMTs-2 friction record (five float64 channels) is
stored through ``PostgresStore`` in batches of 20 000 rows; a store with HSDS materialises
it (``materialise_rows_per_s``: rows from the first append until HSDS holds them all).
Then the whole group and a 10 000-row window in its middle are read, best of three:
``journal`` by a store without HSDS (the batches decoded), ``hsds`` by a store with it
(every row materialised, so all from HSDS); ``ratio`` is hsds time over journal time.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import tempfile
import time
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from rigserver.cluster import free_port
from rigserver.storage.cluster.postgres import PostgresStore
from rigserver.storage.servers.hsdsserver import start_hsds
from rigserver.storage.servers.pgserver import start_local
from schemas.runs import Run, new_run_id
from schemas.stands import StandKind

ROWS = 20_000


def friction(start: int, n: int) -> dict[str, np.ndarray]:
    k = np.arange(start, start + n, dtype=np.float64)
    return {
        "time": 0.001 * k,
        "load": 300.0 + k % 3,
        "speed": np.full(n, 1000.0),
        "friction_moment": 3.0 + np.sin(k / 1000.0),
        "revolutions": k // 60,
    }


def best_of_three(store: PostgresStore, run_id: str, lo: int, hi: int | None) -> float:
    times = []
    for _ in range(3):
        t0 = time.perf_counter()
        store.read(run_id, "friction", None, lo, hi)
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="200 000 rows, not 2 million")
    batches = 10 if parser.parse_args().quick else 100
    work = Path(tempfile.mkdtemp(prefix="rig-bench-hsds-"))
    work.chmod(0o711)  # the database's user (not root) passes through it
    server = start_local(work / "pg", free_port())
    hsds = start_hsds(work / "hsds")
    out: dict[str, Any] = {"rows": batches * ROWS, "rows_per_batch": ROWS}
    try:
        with PostgresStore(
            server.url, files_dir=work / "a", hsds=hsds.settings, hsds_reads=True
        ) as with_hsds:
            created = datetime.now(UTC)
            run = Run(
                id=new_run_id(created),
                stand=StandKind.SMTS2,
                operator="bench",
                created=created,
                configuration={"disc_radius": 0.0225},
            )
            with_hsds.create_run(run)
            t0 = time.perf_counter()
            for seq in range(batches):
                with_hsds.append(run.id, seq, "friction", friction(seq * ROWS, ROWS))
            out["append_rows_per_s"] = round(batches * ROWS / (time.perf_counter() - t0))
            while with_hsds.materialised(run.id, "friction") < batches * ROWS:
                time.sleep(0.05)
            out["materialise_rows_per_s"] = round(batches * ROWS / (time.perf_counter() - t0))
            with PostgresStore(server.url, files_dir=work / "b") as journal:
                mid = batches * ROWS // 2
                for name, (lo, hi) in {"whole": (0, None), "window": (mid, mid + 10_000)}.items():
                    a = journal.read(run.id, "friction", None, lo, hi)
                    b = with_hsds.read(run.id, "friction", None, lo, hi)
                    assert all(np.array_equal(a[k], b[k]) for k in a), "HSDS differs"
                    tj = best_of_three(journal, run.id, lo, hi)
                    th = best_of_three(with_hsds, run.id, lo, hi)
                    out[name] = {
                        "journal_s": round(tj, 4),
                        "hsds_s": round(th, 4),
                        "ratio": round(th / tj, 2),
                    }
    finally:
        hsds.stop()
        server.stop("immediate")
        shutil.rmtree(work, ignore_errors=True)
    json.dump(out, sys.stdout, indent=2)
    print()


if __name__ == "__main__":
    main()
