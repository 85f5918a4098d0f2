"""rigsim.client against an httpx.MockTransport: retries, duplicates, refusals, pacing."""

from __future__ import annotations

import io
import json
import random
from collections.abc import Callable
from datetime import UTC, datetime

import httpx
import numpy as np
import pytest

from rigsim.batches import Batch, SimulatedRun
from rigsim.client import LabClient, RetryPolicy, retry_after
from rigsim.errors import ServerRefused, ServerUnavailable
from schemas.readings import NPZ_MEDIA_TYPE
from schemas.runs import RunCreate

RUN_ID = "20261122T114026Z-1a2b3c4d"
BODY = RunCreate(stand="profilometer", operator="test")


def _sim(times: tuple[float, ...] = (0.0, 10.0, 20.0)) -> SimulatedRun[None]:
    batches = tuple(
        Batch(group="profile", columns={"x": np.array([t, t + 1.0]), "y": np.zeros(2)}, at=t)
        for t in times
    )
    return SimulatedRun(run_create=BODY, batches=batches, truth=None)


class FakeServer:
    """Just enough of rigserver: runs, readings stored once per seq, finish, results."""

    def __init__(self) -> None:
        self.stored: dict[int, dict[str, list[float]]] = {}
        self.state = "open"
        self.calls: list[str] = []
        self.script: list[Callable[[httpx.Request], httpx.Response | None]] = []

    def run_json(self) -> dict[str, object]:
        return {
            "id": RUN_ID,
            "stand": "profilometer",
            "state": self.state,
            "operator": "test",
            "configuration": {},
            "created": "2026-11-22T11:40:26Z",
        }

    def __call__(self, request: httpx.Request) -> httpx.Response:
        self.calls.append(f"{request.method} {request.url.path}")
        if self.script:
            answer = self.script.pop(0)(request)
            if answer is not None:
                return answer
        path = request.url.path
        if path == "/api/v1/runs":
            return httpx.Response(201, json=self.run_json())
        if path.endswith("/readings"):
            if request.headers["content-type"] == NPZ_MEDIA_TYPE:
                seq = int(request.url.params["seq"])
                group = request.url.params["group"]
                with np.load(io.BytesIO(request.content)) as npz:
                    columns = {k: npz[k].tolist() for k in npz.files}
            else:
                body = json.loads(request.content)
                seq, group, columns = body["seq"], body["group"], body["columns"]
            duplicate = seq in self.stored
            self.stored.setdefault(seq, columns)
            receipt = {
                "run_id": RUN_ID,
                "seq": seq,
                "group": group,
                "rows": len(next(iter(columns.values()))),
                "group_rows": 2 * len(self.stored),
                "duplicate": duplicate,
            }
            return httpx.Response(200 if duplicate else 201, json=receipt)
        if path.endswith("/finish"):
            if self.state != "open":
                return _problem(409, "Run is not open", f"run {RUN_ID} is already finished")
            self.state = "finished"
            return httpx.Response(200, json=self.run_json())
        if path.endswith("/results"):
            return httpx.Response(200, json={"stand": "profilometer", "values": {}, "units": {}})
        if path == f"/api/v1/runs/{RUN_ID}":
            return httpx.Response(200, json=self.run_json())
        return _problem(404, "Not found", path)


def _problem(status: int, title: str, detail: str, **extra: object) -> httpx.Response:
    body = {"title": title, "status": status, "detail": detail, **extra}
    return httpx.Response(status, json=body, headers={"content-type": "application/problem+json"})


class Clock:
    """A clock that only moves when the client sleeps."""

    def __init__(self) -> None:
        self.now = 0.0
        self.sleeps: list[float] = []

    def sleep(self, seconds: float) -> None:
        self.sleeps.append(seconds)
        self.now += seconds

    def __call__(self) -> float:
        return self.now


def _client(server: FakeServer, clock: Clock, **policy: float) -> LabClient:
    return LabClient(
        "http://rig.test",
        "writer-key-00000000000000",
        transport=httpx.MockTransport(server),
        retry=RetryPolicy(**policy),  # type: ignore[arg-type]
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


@pytest.mark.parametrize(
    ("status", "title"), [(503, "Service unavailable"), (408, "Request body too slow")]
)
def test_503_with_retry_after_is_honoured_and_the_batch_stored_once(
    status: int, title: str
) -> None:
    server, clock = FakeServer(), Clock()
    busy = _problem(status, title, "the journal is busy, try later")
    busy.headers["Retry-After"] = "2"
    server.script = [lambda r: None, lambda r: busy]  # the run opens, the first batch waits
    outcome = _client(server, clock).run(_sim())
    assert clock.sleeps == [2.0]
    assert sorted(server.stored) == [0, 1, 2]
    assert outcome.retries == 1


def test_transport_errors_back_off_with_jitter_and_recover() -> None:
    server, clock = FakeServer(), Clock()

    def refuse(request: httpx.Request) -> httpx.Response:
        raise httpx.ConnectError("connection refused", request=request)

    server.script = [lambda r: None, refuse, refuse]
    outcome = _client(server, clock, base_delay=0.5).run(_sim())
    # full jitter: U(0, 0.5) after the first failure, U(0, 1.0) after the second
    assert len(clock.sleeps) == 2
    assert 0.0 <= clock.sleeps[0] <= 0.5 and 0.0 <= clock.sleeps[1] <= 1.0
    assert outcome.retries == 2 and sorted(server.stored) == [0, 1, 2]


def test_a_retry_answered_as_duplicate_counts_as_delivered() -> None:
    server, clock = FakeServer(), Clock()

    def store_then_drop(request: httpx.Request) -> httpx.Response:
        server(request)  # the server stores the batch, the answer is lost on the way back
        raise httpx.ReadError("connection reset", request=request)

    server.script = [lambda r: None, store_then_drop]
    outcome = _client(server, clock).run(_sim())
    assert outcome.receipts[0].duplicate and outcome.duplicates == 1
    assert sorted(server.stored) == [0, 1, 2]


def test_422_stops_the_run_with_the_problems_detail() -> None:
    server, clock = FakeServer(), Clock()
    detail = "y[1] = 1200 um is outside the limit: -1000 <= value <= 1000 um"
    server.script = [
        lambda r: None,
        lambda r: _problem(
            422,
            "Readings refused",
            detail,
            errors=[{"field": "columns.y[1]", "value": 1200.0, "message": detail}],
        ),
    ]
    with pytest.raises(ServerRefused, match=r"422 Readings refused: y\[1\] = 1200 um") as info:
        _client(server, clock).run(_sim())
    assert info.value.problem.errors[0].field == "columns.y[1]"
    assert clock.sleeps == [] and server.stored == {}


def test_gives_up_after_the_attempts_with_the_cause_chained() -> None:
    server, clock = FakeServer(), Clock()

    def refuse(request: httpx.Request) -> httpx.Response:
        raise httpx.ConnectError("connection refused", request=request)

    server.script = [refuse] * 3
    with pytest.raises(ServerUnavailable, match="failed after 3 tries") as info:
        _client(server, clock, attempts=3).create_run(BODY)
    assert isinstance(info.value.__cause__, httpx.ConnectError)
    assert len(clock.sleeps) == 2


def test_a_lost_finish_answer_is_accepted_once_the_run_is_finished() -> None:
    server, clock = FakeServer(), Clock()

    def finish_then_drop(request: httpx.Request) -> httpx.Response:
        server(request)
        raise httpx.RemoteProtocolError("server disconnected", request=request)

    server.script = [finish_then_drop]
    run = _client(server, clock).finish(RUN_ID)
    assert run.state.value == "finished"
    assert server.calls[-1] == f"GET /api/v1/runs/{RUN_ID}"


def test_pacing_at_ten_times_the_stand() -> None:
    server, clock = FakeServer(), Clock()
    _client(server, clock).run(_sim((0.0, 10.0, 20.0)), speed=10.0)
    # batches due at 0, 1 and 2 s of wall time
    assert clock.sleeps == pytest.approx([1.0, 1.0])


def test_binary_batches_arrive_as_npz() -> None:
    server, clock = FakeServer(), Clock()
    _client(server, clock).run(_sim(), binary=True)
    assert server.stored[2] == {"x": [20.0, 21.0], "y": [0.0, 0.0]}


def test_retry_after_as_an_http_date() -> None:
    now = datetime(2026, 11, 22, 11, 40, 0, tzinfo=UTC)
    response = httpx.Response(429, headers={"Retry-After": "Sun, 22 Nov 2026 11:40:07 GMT"})
    assert retry_after(response, now) == pytest.approx(7.0)
    assert retry_after(httpx.Response(429, headers={"Retry-After": "3"})) == 3.0
    assert retry_after(httpx.Response(429)) is None
    assert retry_after(httpx.Response(429, headers={"Retry-After": "soon"})) is None


def test_backoff_doubles_up_to_its_cap() -> None:
    policy = RetryPolicy(base_delay=0.2, max_delay=1.0)
    rng = random.Random(1)
    for attempt, cap in ((1, 0.2), (2, 0.4), (3, 0.8), (4, 1.0), (9, 1.0)):
        delays = [policy.backoff(attempt, rng) for _ in range(200)]
        assert min(delays) >= 0.0 and max(delays) <= cap
        assert max(delays) > 0.8 * cap  # the jitter spans the interval


def test_speed_must_be_positive() -> None:
    with pytest.raises(ValueError, match="speed must be > 0"):
        _client(FakeServer(), Clock()).run(_sim(), speed=0.0)


def test_a_lost_opening_answer_is_retried_with_the_same_key() -> None:
    server, clock = FakeServer(), Clock()
    keys: list[str] = []

    def open_then_drop(request: httpx.Request) -> httpx.Response:
        keys.append(request.headers["idempotency-key"])
        raise httpx.ReadTimeout("the answer was lost", request=request)

    def record_key(request: httpx.Request) -> None:
        keys.append(request.headers["idempotency-key"])

    server.script = [open_then_drop, record_key]
    run = _client(server, clock).create_run(BODY)
    assert run.id == RUN_ID
    assert len(keys) == 2 and keys[0] == keys[1]
    server.script = [record_key]
    _client(server, clock).create_run(BODY)  # another run: another key
    assert keys[2] != keys[0]
