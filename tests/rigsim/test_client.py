"""rigsim.client against an httpx.MockTransport: a whole run, its pacing, its batches.

The retries, duplicates and refusals are rigclient's (tests/rigclient/test_http.py).
"""

from __future__ import annotations

import httpx
import numpy as np
import pytest

from rigsim.batches import Batch, SimulatedRun
from rigsim.client import LabClient, RetryPolicy
from schemas.runs import RunCreate
from tests.rigclient.fake import RUN_ID, Clock, FakeServer, problem

BODY = RunCreate(stand="profilometer", operator="test")


def _sim(times: tuple[float, ...] = (0.0, 10.0, 20.0)) -> SimulatedRun[None]:
    batches = tuple(
        Batch(group="profile", columns={"x": np.array([t, t + 1.0]), "y": np.zeros(2)}, at=t)
        for t in times
    )
    return SimulatedRun(run_create=BODY, batches=batches, truth=None)


def _client(server: FakeServer, clock: Clock) -> LabClient:
    return LabClient(
        "http://rig.test",
        "writer-key-00000000000000",
        transport=httpx.MockTransport(server),
        retry=RetryPolicy(),
        sleep=clock.sleep,
        clock=clock,
        seed=0,
    )


def test_a_whole_run_posts_every_batch_once_in_order() -> None:
    server, clock = FakeServer(), Clock()
    outcome = _client(server, clock).run(_sim())
    assert sorted(server.stored) == [0, 1, 2]
    assert server.stored[1] == {"x": [10.0, 11.0], "y": [0.0, 0.0]}
    assert server.calls[0] == "POST /api/v1/runs"
    assert server.calls[-2:] == [
        f"POST /api/v1/runs/{RUN_ID}/finish",
        f"GET /api/v1/runs/{RUN_ID}/results",
    ]
    assert outcome.run.state.value == "finished"
    assert [r.seq for r in outcome.receipts] == [0, 1, 2]
    assert (outcome.retries, outcome.duplicates, clock.sleeps) == (0, 0, [])


def test_a_busy_server_is_waited_for_and_counted() -> None:
    server, clock = FakeServer(), Clock()
    busy = problem(503, "Service unavailable", "the journal is busy, try later")
    busy.headers["Retry-After"] = "2"
    server.script = [lambda r: None, lambda r: busy]  # the run opens, the first batch waits
    outcome = _client(server, clock).run(_sim())
    assert clock.sleeps == [2.0] and outcome.retries == 1
    assert sorted(server.stored) == [0, 1, 2]


def test_each_run_opens_with_its_own_idempotency_key() -> None:
    server, clock = FakeServer(), Clock()
    keys: list[str] = []

    def record_key(request: httpx.Request) -> None:
        keys.append(request.headers["idempotency-key"])

    server.script = [record_key]
    _client(server, clock).create_run(BODY)
    server.script = [record_key]
    _client(server, clock).create_run(BODY)
    assert len(keys) == 2 and keys[0] != keys[1]


def test_pacing_at_ten_times_the_stand() -> None:
    server, clock = FakeServer(), Clock()
    _client(server, clock).run(_sim((0.0, 10.0, 20.0)), speed=10.0)
    # batches due at 0, 1 and 2 s of wall time
    assert clock.sleeps == pytest.approx([1.0, 1.0])


def test_binary_batches_arrive_as_npz() -> None:
    server, clock = FakeServer(), Clock()
    _client(server, clock).run(_sim(), binary=True)
    assert server.stored[2] == {"x": [20.0, 21.0], "y": [0.0, 0.0]}


def test_speed_must_be_positive() -> None:
    with pytest.raises(ValueError, match="speed must be > 0"):
        _client(FakeServer(), Clock()).run(_sim(), speed=0.0)
