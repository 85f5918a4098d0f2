"""What idle live viewers cost the service (issue 25): CPU with 200 ``/live`` streams open
on a run that receives nothing, against none.

Run from the repository root::

    .venv/bin/python benchmarks/live.py [--quick] [--viewers N]

Prints one JSON object: the service's CPU time (user + system, all its threads, from
``/proc/<pid>/stat``) over the same window with no viewer and with ``viewers`` idle streams
attached (the embedded store wakes a stream when its run stores a batch; an idle one waits
for its keep-alive), each as a percentage of one core, and the difference. Each stream is
opened once and held for the window (shorter than a stream's 60 s lifetime).
"""

from __future__ import annotations

import argparse
import json
import os
import socket
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.ingest import API, KEY, open_runs, rigserver

TARGET_PERCENT_OF_A_CORE = 2.0


def cpu_seconds(pid: int) -> float:
    """User + system CPU seconds of a process, all its threads."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def busy_percent(pid: int, seconds: float) -> float:
    """The process's CPU over ``seconds`` of wall clock, % of one core."""
    c0, t0 = cpu_seconds(pid), time.monotonic()
    time.sleep(seconds)
    return 100.0 * (cpu_seconds(pid) - c0) / (time.monotonic() - t0)


def attach(url: str, run_id: str, viewers: int) -> list[socket.socket]:
    """Open ``viewers`` live streams and read each one's head and first event."""
    host, port = url.removeprefix("http://").split(":")
    request = (
        f"GET {API}/runs/{run_id}/live HTTP/1.1\r\nHost: {host}\r\n"
        f"Authorization: Bearer {KEY}\r\nAccept: text/event-stream\r\n\r\n"
    ).encode()
    streams = []
    for _ in range(viewers):
        s = socket.create_connection((host, int(port)), timeout=30)
        s.sendall(request)
        head = b""
        while b"retry:" not in head:
            chunk = s.recv(4096)
            if not chunk:
                raise RuntimeError(f"a live stream closed at once: {head[:300]!r}")
            head += chunk
        if not head.startswith(b"HTTP/1.1 200"):
            raise RuntimeError(f"a live stream was refused: {head[:300]!r}")
        streams.append(s)
    return streams


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a 10 s window instead of 30 s")
    parser.add_argument("--viewers", type=int, default=200)
    args = parser.parse_args(argv)
    window = 10.0 if args.quick else 30.0
    out: dict[str, Any] = {"viewers": args.viewers, "window_s": window}
    with (
        tempfile.TemporaryDirectory(prefix="rig-bench-") as tmp,
        rigserver(Path(tmp), "live") as (url, pid),
    ):
        (run_id,) = open_runs(url, 1)
        time.sleep(2.0)  # the start's imports and caches settle
        out["cpu_percent_no_viewers"] = round(busy_percent(pid, window), 2)
        streams = attach(url, run_id, args.viewers)
        try:
            time.sleep(2.0)  # the streams' first reads are done
            out["cpu_percent_idle_viewers"] = round(busy_percent(pid, window), 2)
        finally:
            for s in streams:
                s.close()
    out["cpu_percent_for_the_viewers"] = round(
        out["cpu_percent_idle_viewers"] - out["cpu_percent_no_viewers"], 2
    )
    out["target_percent_of_a_core"] = TARGET_PERCENT_OF_A_CORE
    out["meets_target"] = out["cpu_percent_for_the_viewers"] <= TARGET_PERCENT_OF_A_CORE
    print(json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
