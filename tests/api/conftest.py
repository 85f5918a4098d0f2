"""The service in process (TestClient over an in-memory store) and over real HTTP."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import httpx
import pytest
from fastapi.testclient import TestClient

from rigserver.api.app import create_app
from rigserver.api.auth import ApiKey
from rigserver.api.settings import Settings
from rigserver.storage import MemoryStore
from schemas.stands import configure_stands
from tests.processes import spawn, stop

READER = "reader-key-00000000000000"
WRITER = "writer-key-00000000000000"
MTOS_ONLY = "mtos-writer-key-000000000"

KEYS = [
    {"key": READER, "scopes": ["read"], "name": "instructor"},
    {"key": WRITER, "scopes": ["read", "write:*"], "name": "lab PC"},
    {"key": MTOS_ONLY, "scopes": ["write:mtos"], "name": "MTOS PC"},
]

#: MTOS steps as in the README's curl example.
MTOS_STEPS: dict[str, list[float]] = {
    "load": [500.0, 1000.0, 1500.0],
    "indicator": [0.02, 0.03, 0.04],
    "x": [-40.0, -30.0, -20.0],
    "y": [-40.0, -30.0, -20.0],
    "t1": [30.0, 30.0, 30.0],
    "t2": [33.0, 35.0, 37.0],
    "t3": [36.0, 38.0, 40.0],
    "t4": [36.0, 38.0, 40.0],
    "t5": [36.0, 38.0, 40.0],
    "regime": [1.0, 1.0, 1.0],
}


def auth(key: str) -> dict[str, str]:
    return {"Authorization": f"Bearer {key}"}


def read_columns(url: str, run_id: str, group: str) -> dict[str, list[float]]:
    """A stored run's channel group as columns, read over HTTP from the server at ``url``
    (the single measurements as one-value columns: their latest values)."""
    r = httpx.get(
        f"{url}/api/v1/runs/{run_id}/readings",
        params={"group": group},
        headers=auth(READER),
        timeout=60,
    )
    r.raise_for_status()
    found = r.json()[group]
    if "values" in found:  # the single measurements: the latest value of each, by name
        return {name: [value] for name, value in found["values"].items()}
    columns: dict[str, list[float]] = found["columns"]
    return columns


def in_process(data_dir: Path, **settings: Any) -> TestClient:
    """The service in process over an in-memory store, with the test keys (:data:`KEYS`) and
    these ``settings``; the client answers a server error as a 500 (it raises nothing)."""
    keys = [ApiKey.model_validate(k) for k in KEYS]
    app = create_app(
        Settings(data_dir=data_dir, **settings), MemoryStore(), keys, configure_stands()
    )
    return TestClient(app, raise_server_exceptions=False)


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    with in_process(tmp_path) as c:
        yield c


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class Server:
    """``rigserver serve`` in a subprocess on a free loopback port."""

    def __init__(
        self,
        data_dir: Path,
        keys_file: Path,
        *,
        public_reads: bool = False,
        args: Sequence[str] = (),
        env: Mapping[str, str] | None = None,
        cwd: Path | None = None,
    ) -> None:
        self.data_dir = data_dir
        self.keys_file = keys_file
        self.public_reads = public_reads
        self.args = list(args)  # more `rigserver serve` options
        self.env = dict(env or {})  # more environment
        self.cwd = cwd  # where `python -m` finds the packages first (a copy of them)
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        self.log = data_dir.parent / "rigserver.log"
        self.proc: subprocess.Popen[bytes] | None = None

    def start(self) -> None:
        cmd = [sys.executable, "-m", "rigserver.cli", "serve", "--port", str(self.port)]
        cmd += ["--data-dir", str(self.data_dir), "--keys-file", str(self.keys_file)]
        cmd += ["--log-level", "warning"] + (["--public-reads"] if self.public_reads else [])
        cmd += self.args
        env = {**os.environ, "PYTHONUNBUFFERED": "1", **self.env}
        with self.log.open("ab") as log:
            self.proc = spawn(cmd, env=env, stdout=log, stderr=log, cwd=self.cwd)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                self.stop()
                tail = self.log.read_text(errors="replace")[-2000:]
                raise RuntimeError(f"rigserver exited: {tail}")
            try:
                httpx.get(f"{self.url}/api/v1/stands", headers=auth(READER), timeout=1)
                return
            except httpx.TransportError:
                time.sleep(0.1)
        self.stop()
        raise RuntimeError("rigserver did not start in 30 s")

    def kill(self) -> None:
        """kill -9 of the server's process group (a crash)."""
        if self.proc:
            stop(self.proc, sig=signal.SIGKILL)

    def stop(self) -> None:
        """SIGTERM to the server's process group, SIGKILL if it has not stopped in time."""
        if self.proc:
            stop(self.proc)


@contextlib.contextmanager
def served(root: Path, *, public_reads: bool = False, args: Sequence[str] = ()) -> Iterator[Server]:
    """A :class:`Server` on a fresh data directory below ``root`` with the test keys
    (:data:`KEYS`), stopped when the block ends."""
    keys_file = root / "keys.json"
    keys_file.write_text(json.dumps(KEYS))
    srv = Server(root / "data", keys_file, public_reads=public_reads, args=args)
    srv.start()
    try:
        yield srv
    finally:
        srv.stop()
