"""Every process the server starts ends within seconds of the server's death, whatever
killed it (issue 39, item 5): its render process and multiprocessing's resource tracker
held each other's pipe and lived on, reparented to init, after a ``kill -9``."""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path

import httpx

from rigsim.client import LabClient
from rigsim.simulators import simulate
from tests.api.conftest import READER, WRITER, Server, auth
from tests.processes import descendants

#: The bound of the issue: no descendant left this long after the server's death.
WITHIN_SECONDS = 10.0


def _alive(pid: int) -> bool:
    """The process runs (a zombie waiting for init to reap it has ended)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rpartition(")")[2].split()[0] != "Z"


def test_kill_9_of_the_server_leaves_no_child(server: Server) -> None:
    with LabClient(server.url, WRITER) as client:
        run = client.run(simulate("profilometer", None, seed=1)).run
    pdf = httpx.get(
        f"{server.url}/api/v1/runs/{run.id}/report.pdf", headers=auth(READER), timeout=120
    )
    assert pdf.status_code == 200  # rendered in the render process
    assert server.proc is not None
    children = descendants(server.proc.pid)
    assert len(children) >= 2, "the render process and the resource tracker run"
    os.kill(server.proc.pid, signal.SIGKILL)  # the server alone, as the kernel's OOM killer
    server.proc.wait()
    deadline = time.monotonic() + WITHIN_SECONDS
    while (left := {p for p in children if _alive(p)}) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not left, f"still running {WITHIN_SECONDS:.0f} s after the server's death: {left}"
