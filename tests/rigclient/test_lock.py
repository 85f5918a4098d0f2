"""Issue 22, item 4: two agents on one spool. The spool is locked by its agent for the
process's life; a second says which process holds it, and stops with a non-zero status."""

from __future__ import annotations

import os
import socket
import time
from pathlib import Path

import httpx
import pytest

from rigclient import Client, SpoolBusy
from rigclient.cli import main
from rigclient.lock import held_by
from tests.rigclient.conftest import AgentProcess
from tests.rigclient.fake import FakeServer


def free_port() -> int:
    """A local port nothing listens on (bound, then closed)."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
    return port


def test_a_second_client_on_the_spool_is_refused_naming_the_first(tmp_path: Path) -> None:
    transport = httpx.MockTransport(FakeServer())
    first = Client("http://rig.test", "k", spool=tmp_path, transport=transport, start=False)
    try:
        with pytest.raises(SpoolBusy) as info:
            Client("http://rig.test", "k", spool=tmp_path, transport=transport, start=False)
        message = str(info.value)
        assert f"pid {os.getpid()}" in message and str(tmp_path) in message, message
        assert held_by(tmp_path) is not None
    finally:
        first.close()
    assert held_by(tmp_path) is None  # released with the client
    Client("http://rig.test", "k", spool=tmp_path, transport=transport, start=False).close()


def test_a_second_agent_says_who_holds_the_spool_and_exits_non_zero(
    tmp_path: Path, agents: list[AgentProcess], capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "trace.csv"
    path.write_text("x;y\n0;1\n0,5;2\n", encoding="utf-8")
    spool, url = tmp_path / "spool", f"http://127.0.0.1:{free_port()}"
    args = ["tail", str(path), "--stand", "profilometer", "--group", "profile"]
    args += ["--url", url, "--spool", str(spool)]
    agents.append(AgentProcess(args, tmp_path / "agent.log"))
    assert agents[0].first_line().startswith("local-")  # it runs, holding the spool
    started = time.monotonic()
    assert main(args) == 1  # a second agent on the same file and spool
    err = capsys.readouterr().err
    assert f"is in use by pid {agents[0].proc.pid}" in err and str(spool) in err, err
    assert f"rigclient tail {path}" in err, err  # and what it runs
    assert time.monotonic() - started < 10
    agents[0].kill9()  # the OS drops the lock with the process: no stale lock
    assert held_by(spool) is None
    assert main(["send", "--url", url, "--spool", str(spool), "--drain", "0"]) == 1
    assert "in use" not in capsys.readouterr().err
