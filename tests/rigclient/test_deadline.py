"""Issue 22, item 5: a wrong URL fails loudly and fast, and every request has a deadline.

A server that answers one byte every few seconds cannot hold the sender beyond the
deadline of a try (httpx's timeouts are per read); ``rigclient import`` to a port with
nothing listening says "connection refused" and the URL at once and exits non-zero; rigsim
says what fails instead of a frozen bar.
"""

from __future__ import annotations

import contextlib
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from rigclient import Client, RetryPolicy, ServerUnavailable
from rigclient.http import Api, TryLater
from rigsim.client import LabClient
from rigsim.simulators import SIMULATORS
from schemas.stands import StandKind
from tests.processes import spawn, stop
from tests.rigclient.conftest import AgentProcess
from tests.rigclient.test_lock import free_port


class Dripping:
    """A server that reads a request, then answers one byte every ``every`` s: the status
    line and headers too (``headers=True``), or only the body."""

    def __init__(self, every: float, *, headers: bool) -> None:
        self.every, self.headers = every, headers
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.url = f"http://127.0.0.1:{self.sock.getsockname()[1]}"
        self.stopping = threading.Event()
        self.threads: list[threading.Thread] = []
        self.accepting = threading.Thread(target=self._accept, daemon=True)
        self.accepting.start()

    def _accept(self) -> None:
        self.sock.settimeout(0.1)
        while not self.stopping.is_set():
            try:
                conn, _ = self.sock.accept()
            except TimeoutError:
                continue
            except OSError:
                return
            thread = threading.Thread(target=self._drip, args=(conn,), daemon=True)
            thread.start()
            self.threads.append(thread)

    def _drip(self, conn: socket.socket) -> None:
        with conn:
            conn.settimeout(5)
            with contextlib.suppress(OSError):
                data = b""
                while b"\r\n\r\n" not in data:
                    data += conn.recv(65536)
                body = b'{"id": "x"}' + b" " * 1000
                head = b"HTTP/1.1 200 OK\r\ncontent-type: application/json\r\n"
                head += b"content-length: %d\r\n\r\n" % len(body)
                if not self.headers:
                    conn.sendall(head)
                for k in range(len(head) * self.headers + len(body)):
                    if self.stopping.wait(self.every):
                        return
                    whole = head + body if self.headers else body
                    conn.sendall(whole[k : k + 1])

    def close(self) -> None:
        self.stopping.set()
        self.sock.close()
        self.accepting.join(5)
        for thread in self.threads:
            thread.join(5)


@pytest.fixture(params=[False, True], ids=["body", "headers"])
def dripping(request: pytest.FixtureRequest) -> Iterator[Dripping]:
    server = Dripping(0.2, headers=request.param)
    yield server
    server.close()


def test_an_answer_dripping_one_byte_at_a_time_cannot_hold_a_try_past_its_deadline(
    dripping: Dripping,
) -> None:
    # each byte comes within the read timeout (0.2 s < 1 s): only a total deadline ends it
    with Api(dripping.url, timeout=1.0, deadline=1.5) as api:
        started = time.monotonic()
        answer = api.attempt("GET", "/runs/x")
        spent = time.monotonic() - started
    assert isinstance(answer, TryLater), answer
    assert "no complete answer within 1.5 s" in answer.reason, answer.reason
    assert f"GET {dripping.url}/api/v1/runs/x" in answer.reason
    assert spent < 3.0, spent  # the drip alone would take 1 000 x 0.2 s


def test_the_sender_says_the_deadline_and_goes_on(dripping: Dripping, tmp_path: Path) -> None:
    said: list[str] = []
    fast = RetryPolicy(base_delay=0.01, max_delay=0.05)
    with Client(
        dripping.url, "k", spool=tmp_path, retry=fast, timeout=1.0, deadline=1.0, say=said.append
    ) as client:
        client.open_run(stand="profilometer", operator="Petrov")
        deadline = time.monotonic() + 5
        while not said and time.monotonic() < deadline:
            time.sleep(0.05)
    assert said and "no complete answer within 1 s" in said[0], said
    assert f"POST {dripping.url}/api/v1/runs" in said[0]


def test_import_to_a_port_with_nothing_listening_says_so_at_once_and_exits_non_zero(
    tmp_path: Path, agents: list[AgentProcess]
) -> None:
    path = tmp_path / "trace.csv"
    path.write_text("x;y\n0;1\n0,5;2\n", encoding="utf-8")
    url, log = f"http://127.0.0.1:{free_port()}", tmp_path / "agent.log"
    args = ["import", str(path), "--stand", "profilometer", "--group", "profile", "--url", url]
    args += ["--spool", str(tmp_path / "spool"), "--id-wait", "30", "--drain", "3"]
    started = time.monotonic()
    agents.append(AgentProcess(args, log))
    assert agents[-1].first_line().startswith("local-")  # at once, not after --id-wait
    said = log.read_text()
    assert f"POST {url}/api/v1/runs: connection refused" in said, said
    assert time.monotonic() - started < 15  # Python's start, then the first try
    assert agents[-1].wait(30) == 1  # the drain ended with the rows undelivered
    said = log.read_text()
    assert "not delivered yet: 1 batch (2 rows) and the finish wait in the spool" in said, said


def test_rigsim_says_what_fails_instead_of_a_frozen_bar(tmp_path: Path) -> None:
    url = f"http://127.0.0.1:{free_port()}"
    told: list[str] = []

    def refuse(request: httpx.Request) -> httpx.Response:
        raise httpx.ConnectError("[Errno 111] Connection refused", request=request)

    fast = RetryPolicy(base_delay=0.01, max_delay=0.02, attempts=3)
    sim = SIMULATORS[StandKind.PROFILOMETER].simulate(
        SIMULATORS[StandKind.PROFILOMETER].settings(), 1
    )
    client = LabClient(url, transport=httpx.MockTransport(refuse), retry=fast, report=told.append)
    with client, pytest.raises(ServerUnavailable, match="connection refused"):
        client.run(sim)
    assert told and told[0].startswith(f"POST {url}/api/v1/runs: connection refused"), told


def test_the_rigsim_command_says_what_fails_at_once(tmp_path: Path) -> None:
    url = f"http://127.0.0.1:{free_port()}"
    out = tmp_path / "rigsim.out"
    with out.open("wb") as sink:
        proc = spawn(
            [sys.executable, "-m", "rigsim.cli", "run", "--stand", "profilometer", "--url", url],
            stdout=sink,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
        )
    try:
        deadline = time.monotonic() + 20
        while "connection refused" not in out.read_text() and time.monotonic() < deadline:
            time.sleep(0.1)
        said = out.read_text()
        # the first contact, before the run is opened (issue 39, item 11)
        assert f"GET {url}/api/v1/stands: connection refused" in said, said
    finally:
        stop(proc)
