"""rigclient.http against an httpx.MockTransport: retries, duplicates, refusals, keys."""

from __future__ import annotations

import random
from datetime import UTC, datetime

import httpx
import numpy as np
import pytest

from rigclient.errors import ServerRefused, ServerUnavailable
from rigclient.http import Api, RetryPolicy, retry_after
from schemas.runs import RunCreate
from tests.rigclient.fake import RUN_ID, Clock, FakeServer, problem

BODY = RunCreate(stand="profilometer", operator="test")
COLUMNS = {"x": np.array([0.0, 1.0]), "y": np.zeros(2)}


def _api(server: FakeServer, clock: Clock, **policy: float) -> Api:
    return Api(
        "http://rig.test",
        "writer-key-00000000000000",
        transport=httpx.MockTransport(server),
        retry=RetryPolicy(**policy),  # type: ignore[arg-type]
        sleep=clock.sleep,
        clock=clock,
        seed=0,
    )


def test_503_with_retry_after_is_honoured_and_the_batch_stored_once() -> None:
    server, clock = FakeServer(), Clock()
    busy = problem(503, "Service unavailable", "the journal is busy, try later")
    busy.headers["Retry-After"] = "2"
    server.script = [lambda r: busy]
    api = _api(server, clock)
    receipt = api.post_columns(RUN_ID, 0, "profile", COLUMNS)
    assert clock.sleeps == [2.0]
    assert (receipt.seq, sorted(server.stored), api.retries) == (0, [0], 1)


def test_transport_errors_back_off_with_jitter_and_recover() -> None:
    server, clock = FakeServer(), Clock()

    def refuse(request: httpx.Request) -> httpx.Response:
        raise httpx.ConnectError("connection refused", request=request)

    server.script = [refuse, refuse]
    api = _api(server, clock, base_delay=0.5)
    api.post_columns(RUN_ID, 0, "profile", COLUMNS)
    # full jitter: U(0, 0.5) after the first failure, U(0, 1.0) after the second
    assert len(clock.sleeps) == 2
    assert 0.0 <= clock.sleeps[0] <= 0.5 and 0.0 <= clock.sleeps[1] <= 1.0
    assert api.retries == 2 and sorted(server.stored) == [0]


def test_a_retry_answered_as_duplicate_counts_as_delivered() -> None:
    server, clock = FakeServer(), Clock()

    def store_then_drop(request: httpx.Request) -> httpx.Response:
        server(request)  # the server stores the batch, the answer is lost on the way back
        raise httpx.ReadError("connection reset", request=request)

    server.script = [store_then_drop]
    receipt = _api(server, clock).post_columns(RUN_ID, 0, "profile", COLUMNS, binary=True)
    assert receipt.duplicate and sorted(server.stored) == [0]
    assert server.stored[0] == {"x": [0.0, 1.0], "y": [0.0, 0.0]}


def test_422_is_refused_at_once_with_the_problems_detail() -> None:
    server, clock = FakeServer(), Clock()
    detail = "y[1] = 1200 um is outside the limit: -1000 <= value <= 1000 um"
    server.script = [
        lambda r: problem(
            422,
            "Readings refused",
            detail,
            errors=[{"field": "columns.y[1]", "value": 1200.0, "message": detail}],
        ),
    ]
    with pytest.raises(ServerRefused, match=r"422 Readings refused: y\[1\] = 1200 um") as info:
        _api(server, clock).post_columns(RUN_ID, 0, "profile", COLUMNS)
    assert info.value.problem.errors[0].field == "columns.y[1]"
    assert clock.sleeps == [] and server.stored == {}


@pytest.mark.parametrize("status", [408, 429, 502, 503, 504])
def test_try_again_answers_are_retried(status: int) -> None:
    server, clock = FakeServer(), Clock()
    server.script = [lambda r: problem(status, "Later", "try again")]
    api = _api(server, clock)
    api.post_columns(RUN_ID, 0, "profile", COLUMNS)
    assert api.retries == 1 and sorted(server.stored) == [0]


def test_gives_up_after_the_attempts_with_the_cause_chained() -> None:
    server, clock = FakeServer(), Clock()

    def refuse(request: httpx.Request) -> httpx.Response:
        raise httpx.ConnectError("connection refused", request=request)

    server.script = [refuse] * 3
    with pytest.raises(ServerUnavailable, match="failed after 3 tries") as info:
        _api(server, clock, attempts=3).create_run(BODY, "key-1")
    assert isinstance(info.value.__cause__, httpx.ConnectError)
    assert len(clock.sleeps) == 2


def test_a_lost_finish_answer_is_accepted_once_the_run_is_finished() -> None:
    server, clock = FakeServer(), Clock()

    def finish_then_drop(request: httpx.Request) -> httpx.Response:
        server(request)
        raise httpx.RemoteProtocolError("server disconnected", request=request)

    server.script = [finish_then_drop]
    run = _api(server, clock).finish(RUN_ID)
    assert run.state.value == "finished"
    assert server.calls[-1] == f"GET /api/v1/runs/{RUN_ID}"


def test_a_lost_opening_answer_is_retried_with_the_same_key() -> None:
    server, clock = FakeServer(), Clock()
    keys: list[str] = []

    def open_then_drop(request: httpx.Request) -> httpx.Response:
        keys.append(request.headers["idempotency-key"])
        raise httpx.ReadTimeout("the answer was lost", request=request)

    def record_key(request: httpx.Request) -> None:
        keys.append(request.headers["idempotency-key"])

    server.script = [open_then_drop, record_key]
    run = _api(server, clock).create_run(BODY, "opening-1")
    assert run.id == RUN_ID
    assert keys == ["opening-1", "opening-1"]


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
    # Retry-After wins over the backoff, capped at max_retry_after
    assert policy.delay(5, rng, 7.0) == 7.0
    assert RetryPolicy(max_retry_after=3.0).delay(1, rng, 100.0) == 3.0
