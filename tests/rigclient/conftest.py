"""The agent as its own process (its own process group, so that a test kills all of it)."""

from __future__ import annotations

import os
import queue
import signal
import subprocess
import sys
import threading
from collections.abc import Iterator, Sequence
from pathlib import Path

import pytest


class AgentProcess:
    """``rigclient ARGS`` in a subprocess; its output lines come through a queue."""

    def __init__(self, args: Sequence[str], log: Path) -> None:
        self.log = log
        with log.open("ab") as err:
            self.proc = subprocess.Popen(
                [sys.executable, "-m", "rigclient.cli", *args],
                stdout=subprocess.PIPE,
                stderr=err,
                stdin=subprocess.DEVNULL,
                start_new_session=True,
                env={**os.environ, "PYTHONUNBUFFERED": "1"},
            )
        self.lines: queue.Queue[str] = queue.Queue()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for raw in self.proc.stdout:
            self.lines.put(raw.decode().rstrip("\n"))

    def first_line(self, timeout: float = 30.0) -> str:
        try:
            return self.lines.get(timeout=timeout)
        except queue.Empty:
            raise AssertionError(f"no output in {timeout} s: {self.log.read_text()}") from None

    def output(self, timeout: float = 30.0) -> list[str]:
        """Every line of output, once the process has ended."""
        self.proc.wait(timeout)
        self._reader.join(timeout)
        return list(self.lines.queue)

    def signal(self, signum: int) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signum)

    def kill9(self) -> None:
        self.signal(signal.SIGKILL)
        self.proc.wait(10)

    def wait(self, timeout: float) -> int:
        return self.proc.wait(timeout)


@pytest.fixture
def agents() -> Iterator[list[AgentProcess]]:
    """Agents a test starts; whatever is left of them is killed at its end."""
    started: list[AgentProcess] = []
    yield started
    for agent in started:
        agent.signal(signal.SIGKILL)
        if agent.proc.poll() is None:
            agent.proc.wait(10)
        if agent.proc.stdout is not None:
            agent.proc.stdout.close()
