"""The summary ``rigclient import`` prints once the run is finished (issue 37, item 5): a
result that rests on the stand's default says so there, as in the results and the report
(a file without a distance column: the distance from the planned speed nobody gave)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from rigserver.analysis.tribometer import NOTE_SPEED_DEFAULT
from tests.api.conftest import WRITER, Server


def _import(server: Server, tmp: Path, csv: str, *more: str) -> str:
    """``rigclient import`` of ``csv`` as a pin-on-disc record: what it printed, its lines
    joined (the console wraps a long note)."""
    tmp.mkdir(exist_ok=True)
    export = tmp / "export.csv"
    export.write_text(csv, encoding="utf-8")
    args = [
        "-m",
        "rigclient.cli",
        "import",
        str(export),
        "--stand",
        "pin_on_disc",
        "--group",
        "friction",
        *more,
    ]
    args += ["--url", server.url, "--key", WRITER, "--spool", str(tmp / "spool")]
    done = subprocess.run(
        [sys.executable, *args, "--drain", "60"],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    assert done.returncode == 0, done.stderr
    return " ".join(done.stdout.split())


def test_a_distance_from_the_default_speed_is_said_in_the_summary(
    server: Server, tmp_path: Path
) -> None:
    rows = "".join(f"{k},0.4,3\n" for k in range(40))
    said = _import(server, tmp_path, "time,friction_coefficient,normal_load\n" + rows)
    assert f"note: {NOTE_SPEED_DEFAULT}" in said
    # with the distance in the file, nothing rests on the speed
    rows = "".join(f"{k},{0.1 * k:.1f},0.4,3\n" for k in range(40))
    header = "time,distance,friction_coefficient,normal_load\n"
    said = _import(server, tmp_path / "again", header + rows)
    assert NOTE_SPEED_DEFAULT not in said and "sliding distance" in said
