"""Reports rendered once, and what downloading them costs the others (issue 25, issue 22 item 9).

Run from the repository root::

    .venv/bin/python benchmarks/reports.py [--quick]

Prints one JSON object. Against ``rigserver serve`` (log level info) on a fresh data
directory, with one finished run of each stand (rigsim, posted over HTTP):

``stands``
    Per stand, the first render of its PDF report (``first_render_s``: its kept files
    removed, then downloaded), a repeated download of the same report
    (``repeat_download_s``), their ratio (target <= 0.05), and a download with
    ``If-None-Match`` (``not_modified_s``, answered 304).
``concurrent``
    15 clients downloading the finished reports (both languages) in a loop while 4
    simulated stands post runs (each run finished, so its reports render in the background):
    p50/p99 of the downloads and of ``GET /api/v1/stands`` probed 10 times a second, beside
    the p99 of ``/api/v1/stands`` while the stands post and nobody downloads (same run).
``log_lines_per_download``
    Lines the service wrote to its log during the concurrent part, per download.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import httpx

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.ingest import API, KEY, rigserver  # noqa: E402
from rigsim.batches import SimulatedRun  # noqa: E402
from rigsim.simulators import simulate  # noqa: E402
from schemas.stands import StandKind  # noqa: E402

TARGET_REPEAT_RATIO = 0.05
DOWNLOADERS = 15
POSTING_STANDS = 4
AUTH = {"Authorization": f"Bearer {KEY}"}


def post(http: httpx.Client, sim: SimulatedRun[Any]) -> str:
    """Open the run, post its batches, finish it: its id."""
    answer = http.post(f"{API}/runs", json=sim.run_create.model_dump(mode="json"))
    answer.raise_for_status()
    run_id = str(answer.json()["id"])
    for seq, batch in enumerate(sim.batches):
        body = {"seq": seq, "group": batch.group, "columns": batch.as_json()}
        http.post(f"{API}/runs/{run_id}/readings", json=body).raise_for_status()
    http.post(f"{API}/runs/{run_id}/finish").raise_for_status()
    return run_id


def wait_for_background(reports: Path, quiet: float = 5.0, timeout: float = 600.0) -> None:
    """Until the finished runs' background renders have ended (those the pool had room for):
    no report file written for ``quiet`` seconds."""
    deadline = time.monotonic() + timeout
    seen: list[str] = []
    still = time.monotonic()
    while time.monotonic() - still < quiet:
        if time.monotonic() > deadline:
            raise RuntimeError(f"the background renders did not end in {timeout} s")
        now = sorted(str(p) for p in reports.rglob("*.*"))
        if now != seen:
            seen, still = now, time.monotonic()
        time.sleep(0.5)


def timed_get(http: httpx.Client, url: str, **kwargs: Any) -> tuple[float, httpx.Response]:
    t0 = time.perf_counter()
    answer = http.get(url, **kwargs)
    return time.perf_counter() - t0, answer


def first_and_repeat(http: httpx.Client, data: Path, run_id: str) -> dict[str, Any]:
    folder = data / "reports" / "run" / run_id
    for kept in folder.glob("en-*.*"):
        kept.unlink()
    url = f"{API}/runs/{run_id}/report.pdf"
    first, answer = timed_get(http, url, params={"lang": "en"})
    answer.raise_for_status()
    repeats = []
    for _ in range(5):
        took, again = timed_get(http, url, params={"lang": "en"})
        again.raise_for_status()
        repeats.append(took)
    etag = answer.headers["etag"]
    not_modified, unchanged = timed_get(
        http, url, params={"lang": "en"}, headers={"If-None-Match": etag}
    )
    if unchanged.status_code != 304:
        raise RuntimeError(f"If-None-Match answered {unchanged.status_code}")
    repeat = statistics.median(repeats)
    return {
        "pdf_bytes": len(answer.content),
        "first_render_s": round(first, 3),
        "repeat_download_s": round(repeat, 4),
        "ratio": round(repeat / first, 4),
        "not_modified_s": round(not_modified, 4),
    }


def percentiles(samples: list[float]) -> dict[str, float]:
    ordered = sorted(samples)
    if not ordered:
        return {"n": 0}
    at = lambda q: ordered[min(len(ordered) - 1, int(q * len(ordered)))]  # noqa: E731
    return {
        "n": len(ordered),
        "p50_ms": round(at(0.5) * 1e3, 1),
        "p99_ms": round(at(0.99) * 1e3, 1),
    }


def probe_stands(url: str, stop: threading.Event, out: list[float]) -> None:
    with httpx.Client(base_url=url, headers=AUTH, timeout=60) as http:
        while not stop.is_set():
            took, answer = timed_get(http, f"{API}/stands")
            answer.raise_for_status()
            out.append(took)
            stop.wait(0.1)


def keep_posting(url: str, kind: StandKind, stop: threading.Event, seed: int) -> None:
    with httpx.Client(base_url=url, headers=AUTH, timeout=120) as http:
        while not stop.is_set():
            post(http, simulate(kind, seed=seed))
            seed += 1


def keep_downloading(
    url: str, reports: list[str], stop: threading.Event, out: list[float], refused: list[int]
) -> None:
    with httpx.Client(base_url=url, headers=AUTH, timeout=120) as http:
        i = 0
        while not stop.is_set():
            took, answer = timed_get(http, reports[i % len(reports)])
            if answer.status_code == 503:
                refused.append(1)
                continue
            answer.raise_for_status()
            out.append(took)
            i += 1


def render_all(url: str, reports: list[str]) -> None:
    """Every report downloaded once (rendered where the background did not)."""
    with httpx.Client(base_url=url, headers=AUTH, timeout=600) as http:
        for report in reports:
            while (answer := http.get(report)).status_code == 503:
                time.sleep(1.0)
            answer.raise_for_status()


def concurrent(url: str, runs: dict[str, str], log: Path, seconds: float) -> dict[str, Any]:
    kinds = list(StandKind)[:POSTING_STANDS]
    reports = [
        f"{url}{API}/runs/{run_id}/report.pdf?lang={lang}"
        for run_id in runs.values()
        for lang in ("en", "ru")
    ]
    render_all(url, reports)
    refused: list[int] = []
    stop = threading.Event()
    quiet: list[float] = []
    posters = [
        threading.Thread(target=keep_posting, args=(url, kind, stop, 1000 + 100 * i))
        for i, kind in enumerate(kinds)
    ]
    for t in posters:
        t.start()
    prober = threading.Thread(target=probe_stands, args=(url, stop, quiet))
    prober.start()
    time.sleep(seconds / 2)  # the stands post, nobody downloads
    quiet_n = len(quiet)
    downloads: list[float] = []
    lines_before = len(log.read_text(errors="replace").splitlines())
    downloading = threading.Event()
    clients = [
        threading.Thread(
            target=keep_downloading,
            args=(url, reports[i:] + reports[:i], downloading, downloads, refused),
        )
        for i in range(DOWNLOADERS)
    ]
    for t in clients:
        t.start()
    time.sleep(seconds)
    downloading.set()
    for t in clients:
        t.join()
    busy_stands = quiet[quiet_n:]
    lines = len(log.read_text(errors="replace").splitlines()) - lines_before
    stop.set()
    for t in [*posters, prober]:
        t.join()
    return {
        "downloaders": DOWNLOADERS,
        "posting_stands": POSTING_STANDS,
        "downloads": percentiles(downloads),
        "downloads_refused_503": len(refused),
        "stands_while_downloading": percentiles(busy_stands),
        "stands_while_posting_only": percentiles(quiet[:quiet_n]),
        "log_lines": lines,
        "log_lines_per_download": round(lines / max(1, len(downloads)), 4),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a 10 s concurrent part, not 30 s")
    args = parser.parse_args(argv)
    out: dict[str, Any] = {"quick": args.quick}
    with tempfile.TemporaryDirectory(prefix="rig-bench-") as tmp:
        work = Path(tmp)
        with rigserver(work, "reports", "--log-level", "info") as (url, _):
            data = work / "data-reports"
            with httpx.Client(base_url=url, headers=AUTH, timeout=600) as http:
                runs = {kind.value: post(http, simulate(kind, seed=7)) for kind in StandKind}
                wait_for_background(data / "reports")
                out["stands"] = {
                    kind: first_and_repeat(http, data, run_id) for kind, run_id in runs.items()
                }
            out["concurrent"] = concurrent(
                url, runs, work / "reports.log", 10 if args.quick else 30
            )
    out["log_lines_per_download"] = out["concurrent"]["log_lines_per_download"]
    out["worst_repeat_ratio"] = max(s["ratio"] for s in out["stands"].values())
    out["target_repeat_ratio"] = TARGET_REPEAT_RATIO
    out["meets_target"] = out["worst_repeat_ratio"] <= TARGET_REPEAT_RATIO
    print(json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
