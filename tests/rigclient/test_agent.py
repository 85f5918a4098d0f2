"""The agent on a file being written, against a fake server: batches, rotation, truncation,
partial lines, refused lines."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest

from rigclient import Client, RetryPolicy
from rigclient.agent import Agent, Batching, Outcome
from rigclient.spool import Spool
from tests.rigclient.fake import FakeServer

HEADER = "time [s];load [kN];speed [rpm];friction_moment [N*m];revolutions [100 rev]\n"
TIMEOUT = 20.0


def row(k: int) -> str:
    """Row k of an SMTs-2 friction record with decimal commas (load 0.3 kN = 300 N)."""
    return f"{k * 0.5:.1f};0,3;1000;{2.9 + 0.001 * k:.3f};{k // 10}\n".replace(".", ",")


def stored_times(server: FakeServer) -> list[float]:
    return [t for seq in sorted(server.stored) for t in server.stored[seq].get("time", [])]


def wait_for(condition: Callable[[], bool], timeout: float = TIMEOUT) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.02)


class Running:
    """An agent in a thread, on the file ``path``, posting to ``server`` through ``spool``."""

    def __init__(self, server: FakeServer, path: Path, spool: Path, idle: float = 0.8) -> None:
        self.client = Client(
            "http://rig.test",
            "key",
            spool=spool,
            transport=httpx.MockTransport(server),
            retry=RetryPolicy(base_delay=0.01, max_delay=0.05),
        )
        self.said: list[str] = []
        self.agent = Agent(
            self.client,
            path,
            stand="smts2",
            group="friction",
            mapping=None,
            metadata={"stand": "smts2", "operator": "Ivanova", "title": path.name},
            batching=Batching(rows=4, seconds=0.1, finish_after_idle=idle, poll=0.02),
            say=self.said.append,
        )
        self.stop = threading.Event()
        self.outcome: Outcome | None = None
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        self.outcome = self.agent.run(self.stop)

    def join(self) -> Outcome:
        self.thread.join(TIMEOUT)
        assert not self.thread.is_alive(), "the agent did not finish"
        assert self.client.wait(TIMEOUT)
        self.client.close()
        assert self.outcome is not None
        return self.outcome


@pytest.fixture
def server() -> Iterator[FakeServer]:
    yield FakeServer()


def write(path: Path, text: str, mode: str = "a") -> None:
    with path.open(mode, encoding="utf-8") as f:
        f.write(text)
        f.flush()


@pytest.mark.parametrize("how", ["renamed", "truncated"])
def test_a_rotated_file_is_followed(server: FakeServer, tmp_path: Path, how: str) -> None:
    path = tmp_path / "smts2.csv"
    write(path, HEADER + "".join(row(k) for k in range(10)), "w")
    agent = Running(server, path, tmp_path / "spool")
    wait_for(lambda: agent.agent.follower.is_open)  # a file renamed before is another file
    if how == "renamed":
        path.rename(tmp_path / "smts2.csv.1")  # rows not read yet are read from the old file
    else:  # copytruncate: what was not read before the truncation is gone, so wait for it
        wait_for(lambda: len(stored_times(server)) == 10)
    write(path, HEADER + "".join(row(k) for k in range(10, 20)), "w")
    outcome = agent.join()
    assert stored_times(server) == [k * 0.5 for k in range(20)]
    assert server.stored[0]["load"][0] == pytest.approx(300.0)  # kN -> N
    assert (outcome.rows, outcome.rejected, server.state) == (20, 0, "finished")
    change = "rotated" if how == "renamed" else "truncated"
    assert any(f"the file was {change}" in s for s in agent.said)


def test_a_partial_last_line_waits_for_its_end(server: FakeServer, tmp_path: Path) -> None:
    path = tmp_path / "smts2.csv"
    write(path, HEADER + row(0) + row(1), "w")
    agent = Running(server, path, tmp_path / "spool", idle=1.0)
    wait_for(lambda: len(stored_times(server)) == 2)
    half = len(row(2)) // 2
    write(path, row(2)[:half])
    time.sleep(0.4)  # longer than a batch's seconds: the half line is not taken
    assert len(stored_times(server)) == 2
    write(path, row(2)[half:] + row(3))
    agent.join()
    assert stored_times(server) == [0.0, 0.5, 1.0, 1.5]


def test_a_malformed_line_is_refused_by_file_line_column_and_the_rest_delivered(
    server: FakeServer, tmp_path: Path
) -> None:
    path = tmp_path / "smts2.csv"
    lines = [row(k) for k in range(8)]
    lines[4] = lines[4].replace("0,3", "0,3x", 1)  # file line 6 (the header is line 1)
    write(path, HEADER + "".join(lines), "w")
    agent = Running(server, path, tmp_path / "spool")
    outcome = agent.join()
    assert stored_times(server) == [k * 0.5 for k in range(8) if k != 4]
    assert outcome.rejected == 1
    message = f"{path}:6, column 'load [kN]': '0,3x' is not a number"
    assert any(message in s for s in agent.said)
    with Spool(tmp_path / "spool") as spool:
        (reject,) = spool.rejects(outcome.run.local_id)
    assert (reject.line, reject.column) == (6, "load [kN]") and message in reject.message


def test_rows_are_batched_by_count_and_by_time(server: FakeServer, tmp_path: Path) -> None:
    path = tmp_path / "smts2.csv"
    write(path, HEADER + "".join(row(k) for k in range(9)), "w")
    agent = Running(server, path, tmp_path / "spool")
    wait_for(lambda: len(stored_times(server)) == 9)  # 4 + 4 at once, the 9th after 0.1 s
    agent.join()
    sizes = [len(server.stored[s]["time"]) for s in sorted(server.stored)]
    assert sizes == [4, 4, 1]
    np.testing.assert_allclose(stored_times(server), np.arange(9) * 0.5)
