"""rigsim.cli and rigsim.demo: argument parsing, settings, the demo's key, the printout."""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import httpx
import pytest
from rich.console import Console

from rigsim.cli import parse_fault, parse_speed, settings_for
from rigsim.demo import KEYS_FILE, demo_key
from rigsim.instruments import Fault
from rigsim.report import print_results
from rigsim.simulators import mtos, smts2
from rigsim.simulators.tribometer import SWEEP
from schemas.stands import StandKind
from tests.api.conftest import READER, Server, auth, free_port
from tests.processes import spawn, stop


@pytest.mark.parametrize(
    ("text", "speed"), [("100x", 100.0), ("1x", 1.0), ("2.5X", 2.5), ("max", None)]
)
def test_parse_speed(text: str, speed: float | None) -> None:
    assert parse_speed(text) == speed


@pytest.mark.parametrize("text", ["fast", "0x", "-3x"])
def test_parse_speed_refuses_nonsense(text: str) -> None:
    with pytest.raises(argparse.ArgumentTypeError, match="speed must"):
        parse_speed(text)


def test_settings_for_the_command_line() -> None:
    adhesive = settings_for(StandKind.SMTS2, mode="adhesive")
    assert isinstance(adhesive, smts2.Smts2Settings) and adhesive.load == 200.0
    short = settings_for(StandKind.MTOS, model="short")
    assert isinstance(short, mtos.MtosSettings) and short.model == "short"
    assert settings_for(StandKind.MTOS).model == "finite"


def test_demo_key_is_made_once_and_kept_private(tmp_path: Path) -> None:
    path, key = demo_key(tmp_path / "data")
    assert path == tmp_path / "data" / KEYS_FILE
    assert (path.stat().st_mode & 0o777) == 0o600
    keys = json.loads(path.read_text())
    assert keys[0]["key"] == key and set(keys[0]["scopes"]) == {"read", "write:*"}
    assert len(key) >= 16  # the server refuses shorter keys
    assert demo_key(tmp_path / "data") == (path, key)


def test_results_are_printed_with_units() -> None:
    console = Console(record=True, width=200)
    results = {
        "stand": "mtos",
        "values": {"h_crit": 4.8e-6, "steps": [{"load": 500.0, "chi": 0.25, "film": "fluid"}]},
        "units": {"h_crit": "m", "steps[].load": "N", "steps[].chi": "1"},
    }
    print_results(
        console,
        results,
        mtos.truth_of(
            mtos.MtosSettings(
                model="short", loads_fluid=(500.0,), loads_mixed=(), loads_boundary=()
            )
        ),
    )
    text = console.export_text()
    # labelled, in µm (the manual's unit for film thickness), not 4.8e-06 m
    assert "critical film thickness" in text and "4.8" in text and "µm" in text
    assert "4.8 " in text.split("simulator truth")[0] and "N [N]" in text and "χ" in text
    assert "truth: steps" in text and "representable" in text


#: ``rigsim demo`` with Ctrl-C heard, as in a terminal, or ignored, as in a background job,
#: however the tests were launched (a process started with SIGINT ignored passes that on to
#: its children)
_WITH_SIGINT = (
    "import runpy, signal, sys; signal.signal(signal.SIGINT, signal.{}); "
    "sys.argv[0] = 'rigsim'; runpy.run_module('rigsim.cli', run_name='__main__')"
)


def _demo(
    port: int, data_dir: Path, out: Path, *, ctrl_c: bool | None = None
) -> subprocess.Popen[bytes]:
    """``rigsim demo`` in its own process group, its output into ``out``; SIGINT heard
    (``ctrl_c``), ignored (False) or as the tests were launched (None)."""
    start = ["-m", "rigsim.cli"]
    if ctrl_c is not None:
        start = ["-c", _WITH_SIGINT.format("default_int_handler" if ctrl_c else "SIG_IGN")]
    cmd = [sys.executable, *start, "demo", "--port", str(port)]
    cmd += ["--data-dir", str(data_dir), "--speed", "max"]
    env = {**os.environ, "PYTHONUNBUFFERED": "1", "COLUMNS": "120"}
    with out.open("wb") as sink:
        return spawn(cmd, stdout=sink, stderr=subprocess.STDOUT, env=env)


def _wait_for(out: Path, marker: str, proc: subprocess.Popen[bytes], seconds: float) -> str:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        text = out.read_text(errors="replace")
        if marker in text or proc.poll() is not None:
            return text
        time.sleep(0.2)
    return out.read_text(errors="replace")


@pytest.mark.slow
def test_demo_serves_four_finished_runs_until_terminated(tmp_path: Path) -> None:
    """Whatever launched the tests (a terminal, a background job with SIGINT ignored, a CI
    runner without a terminal), SIGTERM stops the demo and the server it started."""
    port, out = free_port(), tmp_path / "demo.out"
    proc = _demo(port, tmp_path / "data", out)
    try:
        text = _wait_for(out, "Ctrl-C stops the server", proc, 90)
        assert f"http://127.0.0.1:{port}/docs" in text
        runs = httpx.get(f"http://127.0.0.1:{port}/api/v1/runs", timeout=10).json()["runs"]
        for r in runs:  # each run's page is printed, and it opens
            assert f"http://127.0.0.1:{port}/runs/{r['id']}" in text
        page = httpx.get(f"http://127.0.0.1:{port}/runs/{runs[0]['id']}", timeout=10)
        assert page.status_code == 200
        stands = [r["stand"] for r in runs]  # the SMTs-2 three times: a repeatability series
        again = ["smts2", "smts2", "pin_on_disc"]  # and the pin-on-disc's speed sweep
        assert sorted(stands) == sorted([k.value for k in StandKind] + again)
        assert {r["state"] for r in runs} == {"finished"}
        _the_sweep_has_its_steps(port, runs)
        (series,) = httpx.get(f"http://127.0.0.1:{port}/api/v1/series", timeout=10).json()
        assert series["purpose"] == "repeatability" and len(series["members"]) == 3
        assert f"http://127.0.0.1:{port}/series/{series['id']}" in text
        proc.send_signal(signal.SIGTERM)  # the demo alone: it must stop its server itself
        assert proc.wait(timeout=30) == 128 + signal.SIGTERM
        with pytest.raises(httpx.TransportError):
            httpx.get(f"http://127.0.0.1:{port}/api/v1/runs", timeout=2)
    finally:
        stop(proc)
    assert "Traceback" not in out.read_text(errors="replace")


def _the_sweep_has_its_steps(port: int, runs: list[dict[str, Any]]) -> None:
    """The demo's stepped pin-on-disc run: its steps at the recipe's speeds (v = 2πRn/60 of
    the simulator's SWEEP) and, on its page, their table and the Stribeck curve."""
    (sweep,) = [r for r in runs if r["title"].startswith("Simulated speed sweep")]
    url = f"http://127.0.0.1:{port}"
    values = httpx.get(f"{url}/api/v1/runs/{sweep['id']}/results", timeout=10).json()["values"]
    speeds = [step["sliding_speed"] for step in values["steps"]]
    assert speeds == pytest.approx([v for _, v in SWEEP], rel=1e-9)
    page = httpx.get(f"{url}/runs/{sweep['id']}", timeout=10).text
    assert 'data-table="steps"' in page and 'data-figure="stribeck"' in page


def test_ctrl_c_while_the_demo_posts_stops_it_and_its_server(tmp_path: Path) -> None:
    port, out = free_port(), tmp_path / "demo.out"
    proc = _demo(port, tmp_path / "data", out, ctrl_c=True)
    try:
        assert "posting the four" in _wait_for(out, "posting the four", proc, 60)
        os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C reaches the terminal's whole group
        assert proc.wait(timeout=30) == 130
        with pytest.raises(httpx.TransportError):
            httpx.get(f"http://127.0.0.1:{port}/api/v1/runs", timeout=2)
    finally:
        stop(proc)
    text = out.read_text(errors="replace")
    assert "interrupted" in text and "Traceback" not in text
    assert "trying again" not in text  # the stands' tries at a stopped server: not told


def test_a_server_stopped_while_the_demo_posts_stops_the_demo(tmp_path: Path) -> None:
    """Launched as a background job, the demo keeps SIGINT ignored, but its server (uvicorn)
    stops on it: the demo then stops too, at once, instead of posting to nobody until the
    stands' retries give up (up to 2 min)."""
    port, out = free_port(), tmp_path / "demo.out"
    proc = _demo(port, tmp_path / "data", out, ctrl_c=False)
    try:
        assert "posting the four" in _wait_for(out, "posting the four", proc, 60)
        os.killpg(proc.pid, signal.SIGINT)
        status = proc.wait(timeout=30)
        with pytest.raises(httpx.TransportError):
            httpx.get(f"http://127.0.0.1:{port}/api/v1/runs", timeout=2)
    finally:
        stop(proc)
    text = out.read_text(errors="replace")
    assert status != 0  # the demo did not get to serve its runs
    assert "the server stopped" in text and "Traceback" not in text


def test_a_second_demo_on_a_busy_port_says_so_in_one_line(server: Server) -> None:
    """A second ``make run`` while one serves: one line, a non-zero status, nothing posted
    to the server that holds the port."""
    out = server.data_dir.parent / "second.out"
    proc = _demo(server.port, server.data_dir.parent / "second", out)
    try:
        status = proc.wait(timeout=60)
    finally:
        stop(proc)
    lines = [line for line in out.read_text(errors="replace").splitlines() if line.strip()]
    assert status != 0
    assert len(lines) == 1, lines
    assert f"127.0.0.1:{server.port} is in use" in lines[0]
    runs = httpx.get(f"{server.url}/api/v1/runs", headers=auth(READER), timeout=10).json()
    assert runs["total"] == 0


def test_a_run_posted_where_nothing_listens_says_so_at_once(tmp_path: Path) -> None:
    """``rigsim run`` at a wrong port: one line naming the address, in seconds, not after
    two minutes of tries (issue 39, item 11)."""
    url = f"http://127.0.0.1:{free_port()}"
    started = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-m", "rigsim.cli", "run", "--stand", "profilometer", "--url", url],
        capture_output=True,
        text=True,
        timeout=100,
        stdin=subprocess.DEVNULL,
        env={**os.environ, "COLUMNS": "200"},
    )
    assert done.returncode == 1
    assert time.monotonic() - started < 60  # the tries would take 120 s
    said = [line for line in done.stdout.splitlines() if line.strip()]
    assert len(said) == 1 and "connection refused" in said[0] and url[7:] in said[0], said
    assert "trying again" not in done.stdout + done.stderr


def test_parse_fault() -> None:
    assert parse_fault("stuck:friction.load@0.25*20") == Fault(
        kind="stuck", group="friction", channel="load", at=0.25, rows=20
    )
    assert parse_fault("spike:rows.p3+1.5") == Fault(
        kind="spike", group="rows", channel="p3", at=0.5, size=1.5
    )
    with pytest.raises(argparse.ArgumentTypeError, match="KIND one of dropout, spike"):
        parse_fault("melt:friction.load")
    with pytest.raises(argparse.ArgumentTypeError, match=r"fault.at must lie in \[0, 1\]"):
        parse_fault("spike:friction.load@2")


def test_faults_from_the_command_line_reach_the_settings() -> None:
    fault = parse_fault("out_of_limit:friction.friction_moment@0.5")
    settings = settings_for(StandKind.SMTS2, mode="oxidative", faults=[fault])
    assert settings.faults == (fault,) and settings.mode == "oxidative"


@pytest.mark.parametrize(
    "command", [["rigsim.cli", "demo", "--help"], ["rigclient.cli", "import", "--help"]]
)
def test_help_names_every_stand(command: list[str]) -> None:
    """The stands named by ``--help`` come from the stands' declaration (issue 39, item 11:
    four of six were named)."""
    done = subprocess.run(
        [sys.executable, "-m", *command],
        capture_output=True,
        text=True,
        timeout=60,
        env={**os.environ, "COLUMNS": "400"},
    )
    assert done.returncode == 0
    for kind in StandKind:
        assert kind.value in done.stdout
