"""``scripts/cluster up`` prints one URL per worker and writes the keys and process ids;
``scripts/cluster down`` stops exactly what it started."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import httpx
import pytest

from rigserver.cluster import alive
from rigserver.storage.servers.hsdsserver import hsds_missing
from rigserver.storage.servers.pgserver import NoPostgres, server_bin
from tests.postgres import NO_POSTGRES

SCRIPT = Path(__file__).parents[2] / "scripts" / "cluster"
pytestmark = pytest.mark.slow


def test_up_and_down(tmp_path: Path) -> None:
    try:
        server_bin()
    except NoPostgres as exc:
        pytest.skip(NO_POSTGRES.format(exc))
    top = Path(tempfile.mkdtemp(prefix="rig-cluster-script-"))
    top.chmod(0o711)
    directory = top / "c"
    env = {**os.environ, "PYTHON": sys.executable}
    try:
        up = subprocess.run(
            [str(SCRIPT), "up", "--workers", "2", "--dir", str(directory)],
            capture_output=True,
            text=True,
            env=env,
            timeout=300,
            check=False,
        )
        assert up.returncode == 0, up.stderr
        urls = up.stdout.split()
        assert len(urls) == 2 and all(u.startswith("http://127.0.0.1:") for u in urls)
        key = json.loads((directory / "keys.json").read_text())[0]["key"]
        pids = [int((directory / f"worker-{n}.pid").read_text()) for n in (1, 2)]
        postmaster = directory / "postgres" / "pgdata" / "postmaster.pid"
        pg_pid = int(postmaster.read_text().split()[0])
        if hsds_missing() is None:  # HSDS runs, listening on unix sockets only
            pids.append(int((directory / "hsds" / "hsds.pid").read_text()))
            assert (directory / "hsds" / "sockets" / "sn_1.sock").is_socket()
        else:
            assert "HSDS not started" in up.stderr
        for url in urls:
            r = httpx.get(f"{url}/api/v1/runs", headers={"Authorization": f"Bearer {key}"})
            assert r.status_code == 200, r.text
    finally:
        down = subprocess.run(
            [str(SCRIPT), "down", "--dir", str(directory)],
            capture_output=True,
            text=True,
            env=env,
            timeout=120,
            check=False,
        )
        shutil.rmtree(top, ignore_errors=True)
    assert down.returncode == 0, down.stderr
    assert not any(alive(pid) for pid in [*pids, pg_pid])
