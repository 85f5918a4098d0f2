"""The README's "Connect a real stand" walkthrough, run as printed (curl in bash) against a
real ``rigserver serve`` with the README's keys file: the receipts, the finished run, the
results and the PDF report."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path
from typing import Any

import pytest

from tests.api.conftest import Server

README = Path(__file__).resolve().parents[2] / "README.md"

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(shutil.which("curl") is None, reason="needs curl: apt-get install curl"),
]


def section(title: str) -> str:
    text = README.read_text(encoding="utf-8")
    start = text.index(f"\n## {title}\n")
    end = text.find("\n## ", start + 1)
    return text[start : end if end > 0 else None]


def block(text: str, language: str) -> str:
    found = re.search(rf"```{language}\n(.*?)```", text, re.DOTALL)
    assert found, f"no {language} block"
    return found.group(1)


def answers(output: str) -> list[dict[str, Any]]:
    """The JSON documents curl printed one after the other."""
    decoder, found, i = json.JSONDecoder(), [], 0
    while (i := output.find("{", i)) >= 0:
        value, i = decoder.raw_decode(output, i)
        found.append(value)
    return found


def test_the_walkthrough_runs_as_printed(tmp_path: Path) -> None:
    keys_file = tmp_path / "keys.json"
    keys_file.write_text(block(section("Keys"), "json"))
    server = Server(tmp_path / "data", keys_file)
    server.start()
    try:
        script = block(section("Connect a real stand"), "sh")
        assert "RIG=http://127.0.0.1:8000\n" in script
        script = script.replace("RIG=http://127.0.0.1:8000\n", f"RIG={server.url}\n")
        done = subprocess.run(
            ["bash", "-euo", "pipefail", "-c", script],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=120,
        )
    finally:
        server.stop()
    assert done.returncode == 0, done.stderr
    run_id, rest = done.stdout.split("\n", 1)
    measurements, steps, run, results = answers(rest)
    assert (measurements["seq"], measurements["rows"]) == (0, 1)
    assert (steps["seq"], steps["rows"], steps["run_id"]) == (1, 3, run_id)
    assert (run["id"], run["state"]) == (run_id, "finished")
    # (4.13)-(4.16), f = k·Δl·l1/l2/N, with the stand's default calibration k = 20 N/mm,
    # l1 = 0.2 m, l2 = 0.025 m and the walkthrough's indicator readings and loads
    f = [20.0 * dl * 0.2 / 0.025 / n for dl, n in ((0.02, 500), (0.03, 1000), (0.04, 1500))]
    got = [s["friction_measured"] for s in results["values"]["steps"]]
    assert got == pytest.approx(f, rel=1e-12)
    assert (tmp_path / "report.pdf").read_bytes().startswith(b"%PDF-")
