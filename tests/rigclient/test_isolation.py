"""rigclient imports and runs where the server's packages cannot be imported (a lab PC with
only the client installed: packaging/rigclient). A meta-path finder in the child refuses
them; the child imports a finished file as a run on a real server and reports what it
loaded."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.api.conftest import WRITER, Server, read_columns

#: What the lab PC does not have: the server, the simulator and their dependencies.
BLOCKED = (
    "h5py",
    "matplotlib",
    "weasyprint",
    "fastapi",
    "starlette",
    "uvicorn",
    "scipy",
    "jinja2",
    "xxhash",
    "rigserver",
    "rigsim",
)

CHILD = """
import importlib.abc, json, sys

BLOCKED = set(sys.argv[1].split(","))

class ServerPackages(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in BLOCKED:
            raise ImportError(f"{name} is not installed on a lab PC")
        return None

sys.meta_path.insert(0, ServerPackages())
try:
    import h5py  # the blocker works
except ImportError:
    pass
else:
    raise SystemExit("h5py could be imported")

from rigclient.cli import main

code = main(sys.argv[2:])
loaded = sorted({m.split(".")[0] for m in sys.modules} & BLOCKED)
print(json.dumps({"code": code, "loaded": loaded}))
"""


@pytest.mark.slow
def test_rigclient_runs_without_the_servers_packages(server: Server, tmp_path: Path) -> None:
    path = tmp_path / "slide.csv"
    header = "limb_angle,p1 [at],p2 [at],p3 [at],p4 [at],p5 [at],x,y,t1,t2\n"
    rows = [f"{10 * k},1.{k},2.{k},3.{k},2.{k},1.{k},0.5,0.7,40,45\n" for k in range(6)]
    path.write_text(header + "".join(rows), encoding="utf-8")
    args = ["import", str(path), "--stand", "slide_bearing", "--group", "rows"]
    args += ["--url", server.url, "--key", WRITER, "--spool", str(tmp_path / "spool")]
    done = subprocess.run(
        [sys.executable, "-c", CHILD, ",".join(BLOCKED), *args],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    assert done.returncode == 0, done.stderr
    lines = done.stdout.strip().splitlines()
    report = json.loads(lines[-1])
    assert report == {"code": 0, "loaded": []}, done.stderr
    columns = read_columns(server.url, lines[0], "rows")
    assert columns["limb_angle"] == [10.0 * k for k in range(6)]
