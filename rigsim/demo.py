"""``rigsim demo``: the service with the embedded storage and every stand posting to it.

Starts ``rigserver serve`` as a subprocess (its own process: rigsim reaches the server only
over HTTP) on a data directory, with public reads and a demo key generated into
``<data dir>/demo-keys.json`` (reused on the next start), waits until it answers, runs the
simulated stands (the lab's four, the two tribometers, and the pin-on-disc once more as a
recipe's stepped speed sweep, whose page shows the Stribeck curve) against it in threads at
an accelerated pace, prints where to look, and keeps the server running until Ctrl-C or
SIGTERM (either stops the server too). On a port where something already listens it says so
and exits with status 1.
"""

from __future__ import annotations

import errno
import json
import os
import secrets
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import httpx
from rich.console import Console

from rigclient.summary import quantity
from rigsim.batches import SimulatedRun
from rigsim.client import LabClient, RunOutcome
from rigsim.errors import PortInUse, RigsimError, ServerError, ServerUnavailable
from rigsim.simulators import simulate
from rigsim.simulators.tribometer import simulate_sweep
from schemas.labels import Part
from schemas.stands import DECLARATIONS, StandKind, theory_outside

KEYS_FILE = "demo-keys.json"
STARTUP_TIMEOUT = 60.0
#: Seconds the server has to stop after SIGTERM before it is killed.
STOP_TIMEOUT = 15.0
#: How often the demo looks up from waiting for its stands, s. Python runs a signal's
#: handler in the main thread only; a join without a timeout sleeps through Ctrl-C when the
#: kernel hands the signal to a posting thread, and the demo went on until the stands'
#: retries gave up (up to 2 min).
JOIN_INTERVAL = 0.2
#: Seconds a stand's failed try waits for the server to be seen stopping before it is told.
REPORT_GRACE = 1.0
#: The label of the demo's stepped speed sweep in its printout.
SWEEP_LABEL = "speed sweep"


def demo_key(data_dir: Path) -> tuple[Path, str]:
    """The demo's keys file in ``data_dir`` and its writing key (made on first use)."""
    data_dir.mkdir(parents=True, exist_ok=True)
    path = data_dir / KEYS_FILE
    if path.exists():
        keys = json.loads(path.read_text(encoding="utf-8"))
        return path, str(keys[0]["key"])
    key = f"demo-{secrets.token_hex(16)}"
    path.write_text(
        json.dumps([{"key": key, "scopes": ["read", "write:*"], "name": "rigsim demo"}]),
        encoding="utf-8",
    )
    path.chmod(0o600)
    return path, key


def check_port_free(host: str, port: int) -> None:
    """Refuse to start when something already listens on ``host:port`` (a second demo):
    the new server could not bind, and the readiness check would find the other one."""
    try:
        family = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)[0][0]
        with socket.socket(family) as probe:
            probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as uvicorn binds
            probe.bind((host, port))
    except OSError as exc:
        if exc.errno != errno.EADDRINUSE:
            return  # another trouble (an unknown host, a privileged port): the server says
        raise PortInUse(
            f"{host}:{port} is in use: is a demo or a rigserver already serving there? "
            f"Stop it or pick another --port"
        ) from None


def start_server(host: str, port: int, data_dir: Path, keys_file: Path) -> subprocess.Popen[bytes]:
    """``rigserver serve`` in a subprocess (in this process's group, so that Ctrl-C reaches
    both), once it answers on ``/api/v1/stands``; stopped again if it does not."""
    cmd = [sys.executable, "-m", "rigserver.cli", "serve", "--host", host, "--port", str(port)]
    cmd += ["--data-dir", str(data_dir), "--keys-file", str(keys_file), "--public-reads"]
    cmd += ["--log-level", "warning"]  # the console shows the demo's lines and the problems
    proc = subprocess.Popen(cmd, env={**os.environ, "PYTHONUNBUFFERED": "1"})
    try:
        deadline = time.monotonic() + STARTUP_TIMEOUT
        while time.monotonic() < deadline:
            if proc.poll() is not None:
                raise ServerUnavailable(f"rigserver exited with status {proc.returncode}")
            try:
                httpx.get(f"http://{host}:{port}/api/v1/stands", timeout=1.0)
                return proc
            except httpx.TransportError:
                time.sleep(0.2)
        raise ServerUnavailable(f"rigserver did not answer on port {port} in {STARTUP_TIMEOUT:g} s")
    except BaseException:
        stop_server(proc)
        raise


def stop_server(proc: subprocess.Popen[bytes]) -> None:
    """SIGTERM, then SIGKILL after ``STOP_TIMEOUT`` s; returns once the server is gone."""
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=STOP_TIMEOUT)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def stop_on_signals() -> None:
    """SIGTERM (and SIGHUP, unless nohup ignores it) end the demo like Ctrl-C does: through
    the ``finally`` that stops the server. SIGINT keeps Python's KeyboardInterrupt, or stays
    ignored when whoever started the demo ignores it (a background job)."""
    for sig in (signal.SIGTERM, signal.SIGHUP):
        if signal.getsignal(sig) is not signal.SIG_IGN:
            signal.signal(sig, _exit_on_signal)


def run_demo(
    *,
    host: str,
    port: int,
    data_dir: Path,
    speed: float | None,
    seed: int,
    console: Console,
) -> int:
    """Serve, post every stand concurrently, then serve until Ctrl-C (or SIGTERM)."""
    check_port_free(host, port)
    keys_file, key = demo_key(data_dir)
    url = f"http://{host}:{port}"
    stop_on_signals()
    proc = start_server(host, port, data_dir, keys_file)
    stopping = threading.Event()
    try:
        console.print(f"rigserver is up: data in {data_dir.resolve()}")
        console.print(f"  runs page       {url}/")
        console.print(f"  API docs        {url}/docs")
        console.print(f"  runs (JSON)     {url}/api/v1/runs")
        console.print(f"  demo key        in {keys_file} (reads are public)")
        outcomes: dict[str, RunOutcome | str] = {}

        def report(label: str, text: str) -> None:
            """A stand's failed tries, told while the demo runs; once it stops (Ctrl-C, the
            server gone), what the stands meet is the stop itself, said once by the demo. A
            try is told only if the server still runs a moment later: Ctrl-C reaches the
            server and the demo together, and a stand may find the server closed before the
            demo's main thread hears the signal."""
            try:
                proc.wait(timeout=REPORT_GRACE)
            except subprocess.TimeoutExpired:
                if not stopping.is_set():
                    console.print(f"  {label}: {text}", markup=False, soft_wrap=True)

        def post(label: str, make: Callable[[int], SimulatedRun[Any]], stand_seed: int) -> None:
            try:
                sim = make(stand_seed)
                with LabClient(url, key, seed=stand_seed) as client:
                    client.report = lambda text: report(label, text)
                    outcomes[label] = client.run(sim, speed=speed)
            except (RigsimError, ServerError) as exc:
                outcomes[label] = f"failed: {exc}"

        jobs = [(kind.value, _stand(kind), seed + i) for i, kind in enumerate(StandKind)]
        jobs += [(f"smts2 #{n}", _stand(StandKind.SMTS2), seed + 100 + n) for n in (2, 3)]
        jobs.append((SWEEP_LABEL, _sweep, seed + 200))
        threads = [
            threading.Thread(target=post, args=job, name=job[0], daemon=True) for job in jobs
        ]
        for thread in threads:
            thread.start()
        console.print(
            "posting the four simulated stands (the SMTs-2 three times) and the two "
            f"tribometers (the pin-on-disc once more, a speed sweep) at {_pace(speed)} ..."
        )
        for thread in threads:
            while thread.is_alive():  # woken each interval: Ctrl-C is heard while stands post
                if proc.poll() is not None:  # the server stopped (a signal to the group)
                    console.print(
                        f"the server stopped (exit code {proc.returncode}): so does the demo"
                    )
                    return proc.returncode or 1
                thread.join(JOIN_INTERVAL)
        for label, outcome in outcomes.items():
            if isinstance(outcome, str):
                console.print(f"  {label:14s} {outcome}")
            else:
                units = outcome.results.get("units", {})
                console.print(
                    f"  {label:14s} {url}/runs/{outcome.run.id}"
                    f"  (report: {url}/api/v1/runs/{outcome.run.id}/report.pdf)\n"
                    f"  {'':14s} {_headline(outcome.run.key_results, units, outcome.run.stand)}",
                    soft_wrap=True,
                )
        repeats = [
            o.run.id
            for label, o in sorted(outcomes.items())
            if label.startswith("smts2") and not isinstance(o, str)
        ]
        if repeats:
            console.print(f"  {'series':14s} {url}/series/{demo_series(url, key, repeats)}")
        console.print("serving; Ctrl-C stops the server")
        proc.wait()
        return proc.returncode or 0
    finally:
        stopping.set()
        stop_server(proc)


def demo_series(url: str, key: str, run_ids: list[str]) -> str:
    """A repeatability series of the demo's SMTs-2 runs; its id."""
    headers = {"Authorization": f"Bearer {key}"}
    with httpx.Client(base_url=f"{url}/api/v1", headers=headers, timeout=30.0) as http:
        made = http.post(
            "/series",
            json={
                "name": "SMTs-2 wear run, three repeats (demo)",
                "purpose": "repeatability",
                "notes": "St3sp pin on R9 disc, 300 N, 1000 rpm: the manual's wear run, repeated",
            },
        )
        made.raise_for_status()
        series_id = str(made.json()["id"])
        for run_id in run_ids:
            http.post(f"/series/{series_id}/runs", json={"run_id": run_id}).raise_for_status()
    return series_id


def _stand(kind: StandKind) -> Callable[[int], SimulatedRun[Any]]:
    """The stand's simulated run of a seed."""
    return lambda stand_seed: simulate(kind, seed=stand_seed)


def _sweep(stand_seed: int) -> SimulatedRun[Any]:
    """The pin-on-disc's stepped speed sweep (four steps of 3 min, 75-300 mm/s)."""
    return simulate_sweep(stand_seed)


def _exit_on_signal(signum: int, frame: object) -> None:
    raise SystemExit(128 + signum)


def _pace(speed: float | None) -> str:
    return "full speed" if speed is None else f"{speed:g} times the stands' pace"


def _headline(key_results: dict[str, Any], units: dict[str, str], stand: StandKind) -> str:
    """The key results with the manual's symbols, in the display units (µm, MPa), each
    theoretical value outside its theory's range marked so (its declaration's ``theory_verdict``),
    never a bare headline."""
    outside = theory_outside(stand, key_results)
    verdict = DECLARATIONS[stand].theory_verdict
    parts = []
    for k, v in key_results.items():
        label = DECLARATIONS[stand].labels.get(k)
        if k == verdict or label is None:
            continue
        part = quantity(label, v, units.get(k, label.unit))
        if outside and label.part is Part.THEORY:
            part += " (theory outside its range)"
        parts.append(part)
    return ", ".join(parts)
