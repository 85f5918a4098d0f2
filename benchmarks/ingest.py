"""Ingest speed of the service against what the platform allows (issue 7).

Run from the repository root (needs ``wrk``: ``make system-deps``)::

    .venv/bin/python benchmarks/ingest.py [--quick]

Prints one JSON object. Every figure is measured in this run beside its baseline, with the
load generator in another process on loopback:

``single``
    Single-reading posts (one SMTs-2 friction row, JSON) by ``wrk`` at 16 connections, one
    run per connection as 16 lab PCs would post, against ``rigserver serve``: throughput
    (acknowledged posts/s), p50 and p99 latency; ``baseline_throughput`` is ``wrk`` against
    the bare FastAPI endpoint of ``benchmarks/bare_app.py`` (same uvicorn settings), which
    validates the same body and stores nothing; ``ratio`` = throughput / baseline.
``batch_json``, ``batch_binary``
    Batches of the friction record posted as JSON columns and as ``.npz`` by a Python
    generator process (two connections, one run each): readings (rows of five channels)
    per second, against raw h5py appending the same arrays to one file in one process
    (``baseline_readings_per_s``). ``generator_readings_per_s`` is the generator's own
    ceiling: the same posts to a sink endpoint that only reads the body;
    ``file_catch_up_s`` the time to then read a row of each run, which first writes to the
    run files what large batches left for after their acknowledgement;
    ``bare_endpoint_readings_per_s`` (JSON) the bare endpoint parsing the same bodies.
``long_run``
    One SMTs-2 run of ``readings`` rows posted in binary batches of 500 000 rows to a fresh
    server: its peak resident memory (``rss_mb``, VmHWM of /proc/<pid>/status), the time
    to compute its results (``results_s``: ``GET /results`` of the open run, which streams
    over the HDF5 chunks), to finish it (``finish_s``: results stored, file finalized) and
    to render its report (``report_s``: ``GET /runs/{id}/report.html``; null if the server
    has no such route).

``--quick`` shortens every part (the long run to 5 million readings) to run in under a
minute. ``--repeat N`` runs the whole benchmark N times (the long run once), prints each
run's ratios as it ends, and adds ``summary``: the median and range of each ratio. One run
says little on a shared machine (docs/speed.md): judge by the median of five.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import multiprocessing as mp
import os
import queue
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from http.client import HTTPConnection
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

import h5py
import httpx
import numpy as np
from numpy.typing import NDArray

ROOT = Path(__file__).resolve().parents[1]
KEY = "benchmark-key-0000000000000000"
API = "/api/v1"
CHANNELS = ("time", "load", "speed", "friction_moment", "revolutions")
SINGLE_CONNECTIONS = 16
BATCH_CONNECTIONS = 2
LONG_RUN_BATCH = 500_000
#: A generator thread makes its bodies before the start up to this many rows (400 MB)
PREBUILT_ROWS = 10_000_000
REPORT_PATH = API + "/runs/{run_id}/report.html"
TARGETS = {
    "single_ratio": 0.55,
    "single_p99_ms": 25.0,
    "binary_ratio": 0.4,
    "binary_readings_per_s": 2e6,
    "json_readings_per_s": 3e5,
    "long_run_rss_mb": 400.0,
    "long_run_results_s": 10.0,
    "long_run_report_s": 10.0,
}


# --- servers ------------------------------------------------------------------------------


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextlib.contextmanager
def serving(cmd: list[str], port: int, log: Path) -> Iterator[subprocess.Popen[bytes]]:
    """Run a server command until it accepts connections on ``port``; stop it after."""
    env = {**os.environ, "PYTHONUNBUFFERED": "1", "OPENBLAS_NUM_THREADS": "1"}
    with log.open("ab") as out:  # its own process group, stopped as one
        proc = subprocess.Popen(
            cmd, env=env, stdout=out, stderr=out, cwd=ROOT, start_new_session=True
        )
    try:
        deadline = time.monotonic() + 60
        while True:
            if proc.poll() is not None:
                raise RuntimeError(f"{cmd[:4]} exited: {log.read_text()[-2000:]}")
            try:
                with socket.create_connection(("127.0.0.1", port), timeout=1):
                    break
            except OSError:
                if time.monotonic() > deadline:
                    raise RuntimeError(f"{cmd[:4]} did not start in 60 s") from None
                time.sleep(0.1)
        yield proc
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGTERM)
        with contextlib.suppress(subprocess.TimeoutExpired):
            proc.wait(timeout=30)
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)  # whatever of the group is left
        proc.wait()


@contextlib.contextmanager
def rigserver(work: Path, name: str, *args: str) -> Iterator[tuple[str, int]]:
    """``rigserver serve`` on a fresh data directory (more options in ``args``): (url, pid).
    Its log is ``work/<name>.log``."""
    keys = work / "keys.json"
    keys.write_text(json.dumps([{"key": KEY, "scopes": ["read", "write:*"]}]))
    data = work / f"data-{name}"
    port = free_port()
    cmd = [sys.executable, "-m", "rigserver.cli", "serve", "--port", str(port)]
    cmd += ["--data-dir", str(data), "--keys-file", str(keys), "--log-level", "warning"]
    cmd += args
    try:
        with serving(cmd, port, work / f"{name}.log") as proc:
            yield f"http://127.0.0.1:{port}", proc.pid
    finally:
        shutil.rmtree(data, ignore_errors=True)


@contextlib.contextmanager
def bare_app(work: Path) -> Iterator[str]:
    port = free_port()
    cmd = [sys.executable, str(ROOT / "benchmarks" / "bare_app.py"), str(port)]
    with serving(cmd, port, work / "bare.log"):
        yield f"http://127.0.0.1:{port}"


def open_runs(url: str, n: int) -> list[str]:
    with httpx.Client(base_url=url + API, headers={"Authorization": f"Bearer {KEY}"}) as http:
        runs = []
        for _ in range(n):
            r = http.post("/runs", json={"stand": "smts2", "operator": "benchmark"})
            r.raise_for_status()
            runs.append(str(r.json()["id"]))
    return runs


def rows_stored(url: str, run_ids: list[str]) -> int:
    with httpx.Client(base_url=url + API, headers={"Authorization": f"Bearer {KEY}"}) as http:
        return sum(int(http.get(f"/runs/{r}").json()["rows"]["friction"]) for r in run_ids)


def catch_up_seconds(url: str, run_ids: list[str]) -> float:
    """Seconds to read one row of each run: a read brings the run file up to date first, so
    this is the run files' writes that large batches leave until after their
    acknowledgement (rigserver.storage.embedded.backlog)."""
    auth = {"Authorization": f"Bearer {KEY}"}
    with httpx.Client(base_url=url + API, headers=auth, timeout=120) as http:
        t0 = time.perf_counter()
        for r in run_ids:
            read = http.get(f"/runs/{r}/readings", params={"group": "friction", "stop": 1})
            read.raise_for_status()
        return time.perf_counter() - t0


# --- single-reading posts -----------------------------------------------------------------


def wrk(url: str, runs: list[str], seconds: float) -> dict[str, Any]:
    if shutil.which("wrk") is None:
        raise SystemExit("benchmarks/ingest.py needs wrk (make system-deps)")
    n = SINGLE_CONNECTIONS
    cmd = ["wrk", f"-t{n}", f"-c{n}", f"-d{seconds:g}s", "--timeout", "10s"]
    cmd += ["-s", str(ROOT / "benchmarks" / "single.lua"), url, "--", KEY, ",".join(runs)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    found: dict[str, Any] = json.loads(out.strip().splitlines()[-1])
    return found


def bench_single(work: Path, seconds: float) -> dict[str, Any]:
    with bare_app(work) as url:
        wrk(url, ["warm-up"], 1)
        bare = wrk(url, [f"run-{i}" for i in range(SINGLE_CONNECTIONS)], seconds)
    with rigserver(work, "single") as (url, _):
        wrk(url, open_runs(url, SINGLE_CONNECTIONS), 1)  # warm-up: imports, files, caches
        runs = open_runs(url, SINGLE_CONNECTIONS)
        ours = wrk(url, runs, seconds)
        stored = rows_stored(url, runs)
    acknowledged = ours["requests"] - ours["status_errors"] - ours["socket_errors"]
    throughput = acknowledged / (ours["duration_us"] / 1e6)
    baseline = bare["requests"] / (bare["duration_us"] / 1e6)
    return {
        "clients": SINGLE_CONNECTIONS,
        "throughput": round(throughput),
        "p50_ms": ours["p50_us"] / 1e3,
        "p99_ms": ours["p99_us"] / 1e3,
        "baseline_throughput": round(baseline),
        "baseline_p50_ms": bare["p50_us"] / 1e3,
        "baseline_p99_ms": bare["p99_us"] / 1e3,
        "ratio": round(throughput / baseline, 3),
        "errors": ours["status_errors"] + ours["socket_errors"],
        # every acknowledged post is a stored row (posts in flight at the end may add some)
        "rows_stored": stored,
    }


# --- batches --------------------------------------------------------------------------------


def friction(start: int, rows: int) -> dict[str, NDArray[np.float64]]:
    """Rows ``start ..`` of an SMTs-2 record sampled at 1 kHz at 1000 rpm (within limits)."""
    i = np.arange(start, start + rows, dtype=np.float64)
    t = i * 1e-3
    return {
        "time": t,
        "load": 300.0 + (i % 7),
        "speed": np.full(rows, 1000.0),
        "friction_moment": 2.5 + 0.5 * np.sin(t),
        "revolutions": np.floor(t * 1000.0 / 60.0) / 100.0,
    }


def body(form: str, seq: int, rows: int) -> bytes:
    columns = friction(seq * rows, rows)
    if form == "json":
        lists = {name: values.tolist() for name, values in columns.items()}
        return json.dumps({"seq": seq, "group": "friction", "columns": lists}).encode()
    buffer = io.BytesIO()
    np.savez(buffer, **columns)  # type: ignore[arg-type]
    return buffer.getvalue()


def _post_all(
    url: str, run_id: str | None, form: str, rows: int, batches: int, start: threading.Barrier
) -> None:
    """Post ``batches`` batches to one run (or the sink: run ``None``, the bare endpoint:
    run ``"bare"``). The bodies are made before the start (making them holds the GIL),
    but for a long run's (they would take gigabytes): made while the last is on its way."""
    streamed = rows * batches > PREBUILT_ROWS
    made: queue.Queue[bytes] = queue.Queue(maxsize=2 if streamed else 0)

    def produce() -> None:
        for seq in range(batches):
            made.put(body(form, seq, rows))

    if streamed:
        threading.Thread(target=produce, daemon=True).start()
    else:
        produce()
    headers = {"Authorization": f"Bearer {KEY}"}
    headers["Content-Type"] = "application/json" if form == "json" else "application/x-npz"
    # http.client sends the body as it is (one sendall): the least work per byte
    address = urlsplit(url)
    http = HTTPConnection(address.hostname or "127.0.0.1", address.port, timeout=120)
    try:
        first = made.get()
        start.wait()
        for seq in range(batches):
            content = first if seq == 0 else made.get()
            if run_id is None:
                path = "/sink"
            else:
                query = "" if form == "json" else f"?seq={seq}&group=friction"
                path = f"{API}/runs/{run_id}/readings{query}"
            http.request("POST", path, body=content, headers=headers)
            r = http.getresponse()
            answer = r.read()
            if r.status != 201:
                raise RuntimeError(f"batch {seq}: {r.status} {answer[:300]!r}")
    finally:
        http.close()


def _generate(
    url: str, runs: list[str | None], form: str, rows: int, batches: int, out: Any
) -> None:
    """The generator process: one thread per run; puts the seconds from start to end."""
    start = threading.Barrier(len(runs) + 1)
    threads = [
        threading.Thread(target=_post_all, args=(url, r, form, rows, batches, start)) for r in runs
    ]
    for t in threads:
        t.start()
    start.wait()
    t0 = time.perf_counter()
    for t in threads:
        t.join()
    out.put(time.perf_counter() - t0)


def generate(url: str, runs: list[str | None], form: str, rows: int, batches: int) -> float:
    """Readings per second of the posts, made by a generator in another process."""
    ctx = mp.get_context("spawn")
    out = ctx.Queue()
    proc = ctx.Process(target=_generate, args=(url, runs, form, rows, batches, out))
    proc.start()
    seconds = float(out.get(timeout=600))
    proc.join()
    return len(runs) * rows * batches / seconds


def raw_h5py(work: Path, rows: int, batches: int) -> float:
    """Readings per second of plain h5py appending the same batches to resizable datasets
    chunked as the run files are (65 536 rows), in one process."""
    arrays = [friction(seq * rows, rows) for seq in range(batches)]
    path = work / "raw.h5"
    t0 = time.perf_counter()
    with h5py.File(path, "w") as f:
        group = f.create_group("friction")
        datasets = {
            name: group.create_dataset(
                name, shape=(0,), maxshape=(None,), chunks=(65_536,), dtype="f8"
            )
            for name in CHANNELS
        }
        n = 0
        for batch in arrays:
            for name, ds in datasets.items():
                ds.resize((n + rows,))
                ds[n : n + rows] = batch[name]
            n += rows
    seconds = time.perf_counter() - t0
    path.unlink()
    return rows * batches / seconds


def bench_batches(work: Path, form: str, rows: int, batches: int) -> dict[str, Any]:
    extra = {}
    with bare_app(work) as url:
        ceiling = generate(url, [None] * BATCH_CONNECTIONS, form, rows, batches)
        if form == "json":  # the bare endpoint parses the same bodies and stores nothing
            bare = generate(url, ["bare"] * BATCH_CONNECTIONS, form, rows, batches)
            extra["bare_endpoint_readings_per_s"] = round(bare)
    with rigserver(work, f"batch-{form}") as (url, _):
        generate(url, list(open_runs(url, BATCH_CONNECTIONS)), form, rows, 2)  # warm-up
        runs = open_runs(url, BATCH_CONNECTIONS)
        rate = generate(url, list(runs), form, rows, batches)
        catch_up = catch_up_seconds(url, runs)
        stored = rows_stored(url, runs)
    posted = BATCH_CONNECTIONS * rows * batches
    if stored != posted:
        raise RuntimeError(f"{form}: {stored} rows stored, not {posted}")
    baseline = raw_h5py(work, rows, max(batches, 4_000_000 // rows))
    return {
        "rows_per_batch": rows,
        "connections": BATCH_CONNECTIONS,
        "readings_per_s": round(rate),
        "baseline_readings_per_s": round(baseline),
        "ratio": round(rate / baseline, 3),
        "generator_readings_per_s": round(ceiling),
        "file_catch_up_s": round(catch_up, 3),
        **extra,
    }


# --- the long run -------------------------------------------------------------------------


def memory_mb(pid: int) -> tuple[float, float]:
    """(VmRSS, VmHWM) of a process, MB."""
    fields = {}
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        key, _, value = line.partition(":")
        if key in ("VmRSS", "VmHWM"):
            fields[key] = int(value.split()[0]) / 1024
    return fields["VmRSS"], fields["VmHWM"]


def bench_long_run(work: Path, readings: int) -> dict[str, Any]:
    batches = readings // LONG_RUN_BATCH
    with rigserver(work, "long") as (url, pid):
        (run_id,) = open_runs(url, 1)
        t0 = time.perf_counter()
        generate(url, [run_id], "npz", LONG_RUN_BATCH, batches)
        ingest_s = time.perf_counter() - t0
        rss_after_ingest, _ = memory_mb(pid)
        auth = {"Authorization": f"Bearer {KEY}"}
        with httpx.Client(base_url=url + API, headers=auth, timeout=600) as http:
            t0 = time.perf_counter()
            results = http.get(f"/runs/{run_id}/results")
            results_s = time.perf_counter() - t0
            results.raise_for_status()
            t0 = time.perf_counter()
            http.post(f"/runs/{run_id}/finish").raise_for_status()
            finish_s = time.perf_counter() - t0
            report_s = None
            if REPORT_PATH in http.get(f"{url}/openapi.json").json()["paths"]:
                t0 = time.perf_counter()
                http.get(f"/runs/{run_id}/report.html").raise_for_status()
                report_s = time.perf_counter() - t0
            rows = int(http.get(f"/runs/{run_id}").json()["rows"]["friction"])
        rss, peak = memory_mb(pid)
    if rows != batches * LONG_RUN_BATCH:
        raise RuntimeError(f"long run: {rows} rows stored, not {batches * LONG_RUN_BATCH}")
    return {
        "readings": rows,
        "rss_mb": round(peak, 1),
        "rss_after_ingest_mb": round(rss_after_ingest, 1),
        "rss_end_mb": round(rss, 1),
        "ingest_readings_per_s": round(rows / ingest_s),
        "results_s": round(results_s, 2),
        "finish_s": round(finish_s, 2),
        "report_s": None if report_s is None else round(report_s, 2),
    }


#: The ratios summarised over repeated runs, by where they are in a run's figures
RATIOS = {
    "single_ratio": ("single", "ratio"),
    "json_ratio": ("batch_json", "ratio"),
    "binary_ratio": ("batch_binary", "ratio"),
}


def one_run(work: Path, quick: bool, long_run: bool) -> dict[str, Any]:
    """The figures of one run: each part beside its baseline measured just before it."""
    out: dict[str, Any] = {}
    out["single"] = bench_single(work, 3 if quick else 10)
    out["batch_json"] = bench_batches(work, "json", 20_000, 5 if quick else 25)
    out["batch_binary"] = bench_batches(work, "npz", 200_000, 5 if quick else 25)
    if long_run:
        out["long_run"] = bench_long_run(work, 5_000_000 if quick else 50_000_000)
    return out


def summary(runs: list[dict[str, Any]]) -> dict[str, Any]:
    """Median and range of each ratio over the runs."""
    found: dict[str, Any] = {}
    for name, (part, key) in RATIOS.items():
        values = [run[part][key] for run in runs]
        found[name] = {
            "runs": values,
            "median": round(statistics.median(values), 3),
            "range": [min(values), max(values)],
            "target": TARGETS.get(name),
        }
    return found


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a reduced run (under a minute)")
    parser.add_argument(
        "--repeat",
        type=int,
        default=1,
        help="runs of the whole benchmark (each line to stderr as it ends); the summary "
        "gives the median and range of each ratio (the long run: once)",
    )
    args = parser.parse_args(argv)
    quick = args.quick
    runs: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory(prefix="rig-bench-") as tmp:
        work = Path(tmp)
        for i in range(args.repeat):
            run = one_run(work, quick, long_run=i == 0)
            runs.append(run)
            ratios = {name: run[part][key] for name, (part, key) in RATIOS.items()}
            print(f"run {i + 1}/{args.repeat}: {json.dumps(ratios)}", file=sys.stderr, flush=True)
    out: dict[str, Any] = {"quick": quick, "repeat": args.repeat, **runs[0]}
    if args.repeat > 1:
        out["runs"] = runs
        out["summary"] = summary(runs)
    out["targets"] = TARGETS
    print(json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
