"""Read latency of the service while stands post and viewers watch (issue 14, item 6).

Run from the repository root::

    .venv/bin/python benchmarks/reads.py [--quick]

Prints one JSON object. One ``rigserver serve`` on loopback with a fresh data directory is
seeded with a finished run of each stand (rigsim's simulated stands, through its lab-PC
client). Every GET route is then timed twice, by sequential requests from this process:

``idle``
    the server doing nothing else (the baseline, measured in the same run);
``busy``
    while ``--stands`` simulated stands post runs (rigsim's client in another process; each
    run lasts ``RUN_SECONDS``, its batches paced accordingly, and the next starts when it
    has finished) and ``--viewers`` viewers (another process) each hold a live page: the
    SSE stream ``/runs/{id}/live`` of an open run and ``GET /runs/{id}/results`` every
    5 s, as the page does.

For each route: p50 and p99 in ms, idle and busy, and their ratios (busy / idle); the
routes of an open run are timed on one of the runs being posted. ``load`` counts what the
stands and viewers did (batches, polls, 503s, events). The target: every route's busy p99
under 100 ms, except the report renders (``report.html``, ``report.pdf``) and the export,
which make plots or PDFs by design and are reported for information. Every process this
starts runs in its own process group and is stopped with it; the run stops by itself.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import httpx

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.ingest import API, KEY, rigserver  # noqa: E402
from rigsim.client import LabClient  # noqa: E402
from rigsim.errors import RigsimError  # noqa: E402
from rigsim.simulators import simulate  # noqa: E402
from schemas.stands import StandKind  # noqa: E402

TARGET_P99_MS = 100.0
#: Routes that render plots or a PDF by design: timed, reported, not held to the target.
RENDERS = ("report.html", "report.pdf", "export.zip")
#: Wall seconds a simulated run lasts under load, whatever its stand's own pace (rigsim's
#: runs take 1 200-1 800 s, a profile 1.6 s): its batches come that much faster or slower.
RUN_SECONDS = 45.0
#: The live page asks for the results this often, s.
RESULTS_EVERY = 5.0
#: Seconds the stands and viewers get to start before the busy phase is timed.
WARM_UP = 8.0
#: The load processes stop by themselves after this long at the latest, s.
LOAD_SECONDS_MAX = 900.0
AUTH = {"Authorization": f"Bearer {KEY}"}


def percentile(values: list[float], q: float) -> float:
    """The ``q`` quantile, interpolated between the nearest ranks (the largest for n < 2)."""
    if len(values) < 2:
        return max(values)
    return statistics.quantiles(values, n=100, method="inclusive")[round(q * 100) - 1]


def summary(ms: list[float]) -> dict[str, Any]:
    return {
        "n": len(ms),
        "p50_ms": round(statistics.median(ms), 2),
        "p99_ms": round(percentile(ms, 0.99), 2),
        "errors": 0,
    }


# --- the routes ---------------------------------------------------------------------------


def routes(finished: dict[str, str], open_run: Callable[[], str]) -> dict[str, Callable[[], str]]:
    """Route name -> the path to GET (a callable: the open run changes as stands post)."""
    mtos = finished["mtos"]
    out: dict[str, Callable[[], str]] = {
        "GET /api/v1/stands": lambda: f"{API}/stands",
        "GET /api/v1/stands/{kind}": lambda: f"{API}/stands/mtos",
        "GET /api/v1/runs": lambda: f"{API}/runs",
        "GET /api/v1/runs/{id}": lambda: f"{API}/runs/{mtos}",
        "GET /api/v1/runs/{id}/readings": lambda: f"{API}/runs/{mtos}/readings?group=steps",
        "GET /api/v1/runs/{id}/results (finished)": lambda: f"{API}/runs/{mtos}/results",
        "GET /api/v1/runs/{id}/results (open)": lambda: f"{API}/runs/{open_run()}/results",
        "GET /api/v1/runs/{id}/results.csv": lambda: f"{API}/runs/{mtos}/results.csv",
        "GET /api/v1/runs/{id}/export.zip": lambda: f"{API}/runs/{mtos}/export.zip",
        "GET /api/v1/runs/{id}/report.html": lambda: f"{API}/runs/{mtos}/report.html",
        "GET /api/v1/runs/{id}/report.pdf": lambda: f"{API}/runs/{mtos}/report.pdf",
        "GET /api/v1/runs/{id}/live (first event)": lambda: f"{API}/runs/{mtos}/live",
        "GET / (runs page)": lambda: "/",
        "GET /runs/{id} (run page)": lambda: f"/runs/{mtos}",
    }
    return out


def timed_get(http: httpx.Client, path: str) -> tuple[float, int]:
    """Milliseconds to the whole answer (to the first event for a live stream)."""
    start = time.perf_counter()
    if path.endswith("/live"):
        with http.stream("GET", path) as r:
            for line in r.iter_lines():
                if line.startswith("event:"):
                    break
            return (time.perf_counter() - start) * 1e3, r.status_code
    r = http.get(path)
    r.read()
    return (time.perf_counter() - start) * 1e3, r.status_code


def measure(url: str, paths: dict[str, Callable[[], str]], samples: int) -> dict[str, Any]:
    """Every route ``samples`` times, round robin; then the renders (seconds of CPU each,
    which would weigh on the other routes' figures) a tenth as often."""
    found: dict[str, list[float]] = {name: [] for name in paths}
    errors: dict[str, int] = dict.fromkeys(paths, 0)
    plain = [n for n in paths if not any(r in n for r in RENDERS)]
    renders = [n for n in paths if n not in plain]
    with httpx.Client(base_url=url, headers=AUTH, timeout=120) as http:
        for path in paths.values():  # one untimed request each: caches, imports
            timed_get(http, path())
        for names, rounds in ((plain, samples), (renders, max(1, samples // 10))):
            for _ in range(rounds):
                for name in names:
                    ms, status = timed_get(http, paths[name]())
                    if status == 200:
                        found[name].append(ms)
                    else:
                        errors[name] += 1
    out: dict[str, Any] = {}
    for name, times in found.items():
        out[name] = summary(times) if times else {"n": 0}
        out[name]["errors"] = errors[name]
    return out


# --- the load: stands and viewers (each in a process of its own) ---------------------------


def dump_every_second(counts: dict[str, int], out: Path, stop_at: float) -> None:
    """Write ``counts`` to ``out`` every second until ``stop_at`` (the process is killed)."""
    while time.monotonic() < stop_at:
        tmp = out.with_suffix(".tmp")
        tmp.write_text(json.dumps(counts))
        tmp.replace(out)
        time.sleep(1.0)


def post_stands(url: str, stands: int, seconds: float, out: Path) -> None:
    """``stands`` simulated stands posting runs back to back, each over ``RUN_SECONDS``,
    until killed or ``seconds`` have passed; counts into ``out``."""
    kinds = list(StandKind)
    stop_at = time.monotonic() + seconds
    counts = {"runs_finished": 0, "batches": 0, "failures": 0}
    lock = threading.Lock()

    def posted(seq: int, total: int, receipt: object) -> None:
        with lock:
            counts["batches"] += 1

    def stand(i: int) -> None:
        seed = i
        while time.monotonic() < stop_at:
            sim = simulate(kinds[i % len(kinds)], seed=seed)
            seed += stands
            try:
                with LabClient(url, KEY, seed=seed) as client:
                    lasts = max(sim.batches[-1].at, 1.0)  # the stand's own seconds
                    client.run(sim, speed=lasts / RUN_SECONDS, on_batch=posted)
                with lock:
                    counts["runs_finished"] += 1
            except RigsimError:
                with lock:
                    counts["failures"] += 1

    for i in range(stands):
        threading.Thread(target=stand, args=(i,), daemon=True).start()
    dump_every_second(counts, out, stop_at)
    os._exit(0)  # the stands still posting end with the phase


async def _viewer(http: httpx.AsyncClient, stop_at: float, counts: dict[str, int]) -> None:
    while time.monotonic() < stop_at:
        runs = (await http.get(f"{API}/runs", params={"state": "open"})).json()["runs"]
        if not runs:
            await asyncio.sleep(0.5)
            continue
        run_id = runs[counts["viewers_started"] % len(runs)]["id"]
        counts["viewers_started"] += 1

        async def poll(run_id: str = run_id) -> None:
            while True:
                r = await http.get(f"{API}/runs/{run_id}/results")
                counts["results_polls"] += 1
                counts["results_503"] += r.status_code == 503
                await asyncio.sleep(RESULTS_EVERY)

        poller = asyncio.create_task(poll())
        try:
            async with http.stream("GET", f"{API}/runs/{run_id}/live") as r:
                async for line in r.aiter_lines():
                    counts["live_events"] += line.startswith("event:")
                    if time.monotonic() > stop_at:
                        break
        except httpx.HTTPError:
            counts["live_errors"] += 1
        finally:
            poller.cancel()


async def _viewers(url: str, viewers: int, seconds: float, out: Path) -> None:
    counts = dict.fromkeys(
        ("viewers_started", "results_polls", "results_503", "live_events", "live_errors"), 0
    )
    stop_at = time.monotonic() + seconds
    threading.Thread(target=dump_every_second, args=(counts, out, stop_at), daemon=True).start()
    limits = httpx.Limits(max_connections=2 * viewers + 10)
    async with httpx.AsyncClient(
        base_url=url, headers=AUTH, timeout=httpx.Timeout(30, read=90), limits=limits
    ) as http:
        tasks = [asyncio.create_task(_viewer(http, stop_at, counts)) for _ in range(viewers)]
        await asyncio.wait(tasks, timeout=seconds + 5)
        for t in tasks:
            t.cancel()


def watch(url: str, viewers: int, seconds: float, out: Path) -> None:
    asyncio.run(_viewers(url, viewers, seconds, out))
    os._exit(0)


@contextlib.contextmanager
def load(url: str, stands: int, viewers: int, work: Path) -> Iterator[list[Path]]:
    """The stands and the viewers, in two processes (own process groups) killed on exit;
    their counts are in the files yielded."""
    script = str(Path(__file__).resolve())
    outs = [work / "stands.json", work / "viewers.json"]
    procs = []
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
    try:
        for role, n, out in (("stands", stands, outs[0]), ("viewers", viewers, outs[1])):
            cmd = [sys.executable, script, "--role", role, "--url", url, "--n", str(n)]
            cmd += ["--seconds", str(LOAD_SECONDS_MAX), "--out", str(out)]
            procs.append(
                subprocess.Popen(cmd, stderr=subprocess.DEVNULL, env=env, start_new_session=True)
            )
        yield outs
    finally:
        for proc in procs:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


# --- the benchmark ------------------------------------------------------------------------


def seed_finished(url: str) -> dict[str, str]:
    """A finished run of each stand, posted at full speed; stand -> run id."""
    out = {}
    with LabClient(url, KEY, seed=0) as client:
        for i, kind in enumerate(StandKind):
            out[kind.value] = client.run(simulate(kind, seed=100 + i)).run.id
    return out


def open_runs_of(url: str) -> Callable[[], str]:
    """The newest open MTOS run (one being posted), else any open run, else none yet."""
    fallback: list[str] = []

    def pick() -> str:
        with httpx.Client(base_url=url, headers=AUTH, timeout=30) as http:
            runs = http.get(f"{API}/runs", params={"state": "open"}).json()["runs"]
        mtos = [r["id"] for r in runs if r["stand"] == "mtos"]
        chosen = (mtos or [r["id"] for r in runs] or fallback)[:1]
        if chosen:
            fallback[:] = chosen
        return chosen[0] if chosen else "20000101T000000Z-00000000"

    return pick


def bench(quick: bool, stands: int, viewers: int) -> dict[str, Any]:
    samples = 25 if quick else 100
    with tempfile.TemporaryDirectory(prefix="rig-reads-") as tmp:
        work = Path(tmp)
        with rigserver(work, "reads") as (url, _pid):
            finished = seed_finished(url)
            with LabClient(url, KEY, seed=1) as client:  # an open run, for the idle phase only
                sim = simulate(StandKind.MTOS, seed=7)
                idle_open = client.create_run(sim.run_create).id
                for seq, batch in enumerate(sim.batches):
                    client.post_batch(idle_open, seq, batch)
            idle = measure(url, routes(finished, lambda: idle_open), samples)
            with httpx.Client(base_url=url, headers=AUTH, timeout=30) as http:
                http.post(f"{API}/runs/{idle_open}/abort").raise_for_status()  # viewers watch
            with load(url, stands, viewers, work) as outs:
                time.sleep(WARM_UP)  # the stands open their runs, the viewers connect
                started = time.monotonic()
                busy = measure(url, routes(finished, open_runs_of(url)), samples)
                measured_s = time.monotonic() - started
            counts: dict[str, Any] = {"stands": stands, "viewers": viewers}
            for out in outs:
                counts.update(json.loads(out.read_text()) if out.exists() else {})
            counts["busy_measured_s"] = round(measured_s, 1)
    table: dict[str, Any] = {}
    for name in idle:
        i, b = idle[name], busy[name]
        row: dict[str, Any] = {"idle": i, "busy": b}
        if i.get("n") and b.get("n"):
            row["ratio_p50"] = round(b["p50_ms"] / i["p50_ms"], 2)
            row["ratio_p99"] = round(b["p99_ms"] / i["p99_ms"], 2)
            if not any(r in name for r in RENDERS):
                row["target_met"] = b["p99_ms"] < TARGET_P99_MS and b["errors"] == 0
        table[name] = row
    held = [r for n, r in table.items() if "target_met" in r]
    return {
        "quick": quick,
        "routes": table,
        "load": counts,
        "target_p99_ms": TARGET_P99_MS,
        "target_met": all(r["target_met"] for r in held),
        "worst_busy_p99_ms": max(r["busy"]["p99_ms"] for r in held),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a reduced run (about 3 minutes)")
    parser.add_argument("--stands", type=int, default=8, help="simulated stands posting")
    parser.add_argument("--viewers", type=int, default=50, help="live pages held open")
    parser.add_argument("--role", choices=("stands", "viewers"), help=argparse.SUPPRESS)
    parser.add_argument("--url", help=argparse.SUPPRESS)
    parser.add_argument("--n", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--seconds", type=float, help=argparse.SUPPRESS)
    parser.add_argument("--out", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.role == "stands":
        post_stands(args.url, args.n, args.seconds, args.out)
    elif args.role == "viewers":
        watch(args.url, args.n, args.seconds, args.out)
    print(json.dumps(bench(args.quick, args.stands, args.viewers), indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
