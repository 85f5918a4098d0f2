"""Ingest into a cluster (PostgreSQL and 1 or 2 workers) against the embedded store (issue 19).

Run from the repository root (needs the Debian ``postgresql`` package)::

    .venv/bin/python benchmarks/cluster.py [--quick]

Prints one JSON object. Four client threads in this process each post binary (``.npz``)
batches of the SMTs-2 friction record to a run of their own for a fixed time, thread k to
worker k mod N. Each body is made once, the first ones before the clock starts
(``benchmarks/ingest.py``'s ``body``: batch k holds rows from k*20000 on, so its times
follow the batch before). ``readings_per_s`` counts rows (of five channels) acknowledged
per second.

``embedded``
    ``rigserver serve`` on a data directory (SQLite journal, HDF5 run files): the baseline.
``cluster_1``, ``cluster_2``
    ``scripts/cluster up --no-hsds`` with 1 and 2 workers on one local PostgreSQL;
    ``ratio`` is the readings/s over the embedded store's, measured in the same run.
``cluster_2_hsds`` (when hsds and h5pyd are installed)
    the same with HSDS, the workers materialising the arrays there as they come;
    ``materialised_after_s`` is how long after the last post HSDS held every row.

On a machine of two cores the workers, PostgreSQL and the clients share them: the figures
show what the cluster costs per reading, not how it scales (docs/scale-out.md).
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import tempfile
import threading
import time
from http.client import HTTPConnection
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

import httpx
import psycopg

sys.path.insert(0, str(Path(__file__).parent))
from ingest import body

from rigserver import cluster
from rigserver.storage.servers.hsdsserver import hsds_missing

API = "/api/v1"
CLIENTS = 4
ROWS = 20_000


def _open_run(url: str, key: str) -> str:
    r = httpx.post(
        f"{url}{API}/runs",
        json={"stand": "smts2", "operator": "bench"},
        headers={"Authorization": f"Bearer {key}"},
    )
    r.raise_for_status()
    return str(r.json()["id"])


def ingest(urls: list[str], key: str, seconds: float) -> dict[str, Any]:
    """Readings per second acknowledged by ``urls`` from :data:`CLIENTS` client threads."""
    bodies = [body("npz", seq, ROWS) for seq in range(16)]  # more made as the clients go
    made = threading.Lock()

    def body_of(seq: int) -> bytes:
        with made:
            while len(bodies) <= seq:
                bodies.append(body("npz", len(bodies), ROWS))
            return bodies[seq]

    runs = [(urls[k % len(urls)], _open_run(urls[k % len(urls)], key)) for k in range(CLIENTS)]
    start = threading.Barrier(CLIENTS + 1)
    stop = threading.Event()
    posted = [0] * CLIENTS
    failures: list[str] = []

    def client(k: int) -> None:
        url, run_id = runs[k]
        where = urlsplit(url)
        http = HTTPConnection(where.hostname or "127.0.0.1", where.port, timeout=120)
        headers = {"Authorization": f"Bearer {key}", "Content-Type": "application/x-npz"}
        start.wait()
        seq = 0
        try:
            while not stop.is_set():
                path = f"{API}/runs/{run_id}/readings?seq={seq}&group=friction"
                http.request("POST", path, body=body_of(seq), headers=headers)
                r = http.getresponse()
                answer = r.read()
                if r.status != 201:
                    failures.append(f"{r.status} {answer[:200]!r}")
                    return
                seq += 1
                posted[k] += ROWS
        finally:
            http.close()

    threads = [threading.Thread(target=client, args=(k,)) for k in range(CLIENTS)]
    for t in threads:
        t.start()
    start.wait()
    t0 = time.perf_counter()
    time.sleep(seconds)
    stop.set()
    for t in threads:
        t.join()
    elapsed = time.perf_counter() - t0
    if failures:
        raise RuntimeError(f"a post failed: {failures[0]}")
    return {"workers": len(urls), "readings_per_s": round(sum(posted) / elapsed)}


def embedded(work: Path, seconds: float) -> dict[str, Any]:
    directory = work / "embedded"
    directory.mkdir()
    key = cluster.write_keys(directory)
    url = cluster.start_worker(directory, 1, None)
    try:
        return ingest([url], key, seconds)
    finally:
        cluster.stop_worker(directory / "worker-1.pid")


def clustered(work: Path, workers: int, seconds: float, *, hsds: bool) -> dict[str, Any]:
    directory = work / f"cluster-{workers}{'-hsds' if hsds else ''}"
    urls = cluster.up(directory, workers, hsds=hsds)
    try:
        key = json.loads((directory / "keys.json").read_text())[0]["key"]
        result = ingest(urls, key, seconds)
        if hsds:
            result["materialised_after_s"] = _caught_up(directory)
        return result
    finally:
        cluster.down(directory)


def _caught_up(directory: Path) -> float:
    """Seconds until every stored batch is marked materialised in HSDS."""
    server = cluster.postgres_of(directory)
    t0 = time.perf_counter()
    with psycopg.connect(server.url, autocommit=True) as conn:
        while True:
            row = conn.execute(
                "SELECT (SELECT SUM(batches) FROM rig_runs) - "
                "COALESCE((SELECT SUM(batches) FROM rig_hsds_marks), 0)"
            ).fetchone()
            if row is not None and int(row[0]) == 0:
                return round(time.perf_counter() - t0, 2)
            time.sleep(0.1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="3 s per deployment, not 15")
    seconds = 3.0 if parser.parse_args().quick else 15.0
    work = Path(tempfile.mkdtemp(prefix="rig-bench-cluster-"))
    work.chmod(0o711)  # the database's user (not root) passes through it
    try:
        out: dict[str, Any] = {"clients": CLIENTS, "rows_per_batch": ROWS, "seconds": seconds}
        out["embedded"] = embedded(work, seconds)
        base = out["embedded"]["readings_per_s"]
        for workers in (1, 2):
            result = clustered(work, workers, seconds, hsds=False)
            result["ratio"] = round(result["readings_per_s"] / base, 3)
            out[f"cluster_{workers}"] = result
        if hsds_missing() is None:
            result = clustered(work, 2, seconds, hsds=True)
            result["ratio"] = round(result["readings_per_s"] / base, 3)
            out["cluster_2_hsds"] = result
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
