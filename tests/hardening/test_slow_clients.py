"""A slow client cannot deny ingest to everyone (issue 14, item 5): a body has a time
limit (408), and admission to the ingest queue is fair across API keys, so one lab PC's
slow or stuck uploads leave room for the other stands. Over real HTTP with raw sockets
on loopback; every wait is bounded."""

from __future__ import annotations

import asyncio
import json
import socket
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import httpx
import pytest
from starlette.types import Message, Receive, Scope, Send

from rigserver.api.body_limit import BodyLimit
from rigserver.api.ingest_queue import IngestQueue
from rigserver.api.problems import ApiProblem
from rigserver.api.settings import Settings
from rigserver.storage import MemoryStore
from tests.api.conftest import KEYS, MTOS_ONLY, WRITER, Server, auth
from tests.hardening.conftest import API, json_batch, open_run

#: The other stand's lab PC, a key of its own.
OTHER = "other-stand-key-000000000"
#: Body time limit of the served service, s: long enough for the other PC's posts to be
#: made while the slow uploads hold their places, short enough for a test.
BODY_TIMEOUT = 4.0  # the server's --body-timeout below


def test_the_settings_take_the_body_timeout_and_key_share(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("RIG_BODY_TIMEOUT", "2.5")
    monkeypatch.setenv("RIG_INGEST_KEY_SHARE", "0.5")
    settings = Settings()
    assert (settings.body_timeout, settings.ingest_key_share) == (2.5, 0.5)


def test_one_key_holds_at_most_its_share_of_the_queue() -> None:
    """8 posts and 100 bytes at once, a quarter per key: 2 posts, 25 bytes."""
    queue = IngestQueue(
        MemoryStore(), lambda _: threading.Lock(),
        max_batches=8, max_bytes=100, share=0.25, retry_after=3,
    )  # fmt: skip

    def refused(size: int, key: str) -> ApiProblem:
        with pytest.raises(ApiProblem) as caught, queue.admit(size, key):
            pass
        return caught.value

    with queue.admit(10, "a") as a1, queue.admit(10, "a") as a2:
        a1.arrived(10)
        a2.arrived(10)
        problem = refused(1, "a")  # a third post of key a
        assert (problem.problem.status, problem.problem.title) == (503, "Ingest share used")
        assert problem.headers == {"Retry-After": "3"}
        with queue.admit(20, "b") as b1:  # key b has its own share
            b1.arrived(20)
            assert refused(6, "b").problem.title == "Ingest share used"  # 26 bytes > 25
            with queue.admit(5, "b") as b2:
                b2.arrived(5)
                assert queue.admitted == (4, 45)
    assert queue.admitted == (0, 0)
    with queue.admit(90, "a") as big:  # alone, a body over the key's bytes is admitted
        big.arrived(90)
        assert refused(1, "a").problem.title == "Ingest share used"
        assert queue.admitted == (1, 25)  # it counts for the key's share, no more
        with queue.admit(11, "b"):  # so the other keys keep the rest of the queue
            pass


def test_a_body_counts_by_the_bytes_that_have_arrived() -> None:
    """100 bytes at once, a quarter per key; a body that declares more than it sends holds
    what has come (issue 22, item 7)."""
    queue = IngestQueue(
        MemoryStore(), lambda _: threading.Lock(),
        max_batches=8, max_bytes=100, share=0.25, retry_after=3,
    )  # fmt: skip
    with queue.admit(64 << 20, "slow") as slow:  # declares 64 MiB, sends one byte
        slow.arrived(1)
        assert queue.admitted == (1, 1)
        for key in ("b", "c", "d"):  # every other key's post fits, of any size
            with queue.admit(25, key) as place:
                place.arrived(25)
        with queue.admit(0, "b") as b, queue.admit(0, "c") as c, queue.admit(0, "d") as d:
            for place in (b, c, d):  # chunked: counted as they arrive
                place.arrived(25)
            assert queue.admitted == (4, 76)
            with pytest.raises(ApiProblem) as caught, queue.admit(0, "e") as e:
                e.arrived(25)  # 101 bytes in: the queue is full
            assert caught.value.problem.title == "Ingest queue full"
            with queue.admit(0, "b") as more, pytest.raises(ApiProblem) as caught:
                more.arrived(1)  # 26 bytes of key b in two bodies
            assert caught.value.problem.title == "Ingest share used"
            slow.arrived(24)  # the slow body fills its key's share
            assert queue.admitted == (4, 100)
            with pytest.raises(ApiProblem) as caught, queue.admit(1, "e"):
                pass
            assert caught.value.problem.title == "Ingest queue full"
        slow.arrived(1000)  # alone of its key, it arrives whole: counted at its share
        assert queue.admitted == (1, 25)
    assert queue.admitted == (0, 0)


# --- the body's time limit, at the ASGI level --------------------------------------------


async def _echo(scope: Scope, receive: Receive, send: Send) -> None:
    """Reads the whole body, then answers 200 with its length."""
    size, more = 0, True
    while more:
        message = await receive()
        size += len(message.get("body", b""))
        more = message.get("more_body", False)
    await send({"type": "http.response.start", "status": 200, "headers": []})
    await send({"type": "http.response.body", "body": str(size).encode()})


def _never() -> Callable[[], object]:
    async def receive() -> Message:
        await asyncio.sleep(3600)
        raise AssertionError("unreachable")

    return receive


def _trickle() -> Callable[[], object]:
    async def receive() -> Message:
        await asyncio.sleep(0.05)
        return {"type": "http.request", "body": b"x", "more_body": True}

    return receive


def _in_time() -> Callable[[], object]:
    chunks = iter([b"a" * 10, b"b" * 10, b""])

    async def receive() -> Message:
        await asyncio.sleep(0.01)
        body = next(chunks)
        return {"type": "http.request", "body": body, "more_body": bool(body)}

    return receive


async def _answer(receive: Callable[[], object], timeout: float) -> tuple[int, bytes, float]:
    sent: list[Message] = []

    async def send(message: Message) -> None:
        sent.append(message)

    scope: Scope = {"type": "http", "method": "POST", "path": "/", "headers": []}
    start = time.monotonic()
    await asyncio.wait_for(
        BodyLimit(_echo, max_bytes=1000, timeout=timeout)(scope, receive, send),  # type: ignore[arg-type]
        timeout=30,
    )
    body = b"".join(m.get("body", b"") for m in sent if m["type"] == "http.response.body")
    return sent[0]["status"], body, time.monotonic() - start


@pytest.mark.parametrize(
    "receive", [_never, _trickle], ids=["a body that never comes", "a byte now and then"]
)
def test_a_body_slower_than_its_time_limit_is_408(
    receive: Callable[[], Callable[[], object]],
) -> None:
    status, body, took = asyncio.run(_answer(receive(), timeout=0.5))
    assert status == 408
    assert json.loads(body)["title"] == "Request body too slow"
    assert 0.5 <= took < 2.0


def test_a_body_in_time_is_read() -> None:
    assert asyncio.run(_answer(_in_time(), timeout=0.5))[:2] == (200, b"20")


# --- over real HTTP ------------------------------------------------------------------------


@pytest.fixture
def server(tmp_path: Path) -> Iterator[Server]:
    """8 posts at once, a quarter (2) per key; bodies within BODY_TIMEOUT."""
    keys = tmp_path / "keys.json"
    keys.write_text(json.dumps([*KEYS, {"key": OTHER, "scopes": ["read", "write:*"]}]))
    served = Server(
        tmp_path / "data",
        keys,
        args=("--ingest-queue", "8", "--ingest-key-share", "0.25", "--body-timeout", "4"),
    )
    served.start()
    try:
        yield served
    finally:
        served.stop()


def _slow_post(port: int, run_id: str, length: int, *, chunked: bool = False) -> socket.socket:
    """A post of the slow key whose headers and first bytes are sent, and no more."""
    sock = socket.create_connection(("127.0.0.1", port), timeout=BODY_TIMEOUT + 10)
    framing = "Transfer-Encoding: chunked" if chunked else f"Content-Length: {length}"
    head = (
        f"POST {API}/runs/{run_id}/readings HTTP/1.1\r\nHost: 127.0.0.1\r\n"
        f"Authorization: Bearer {WRITER}\r\nContent-Type: application/json\r\n{framing}\r\n\r\n"
    )
    sock.sendall(head.encode() + (b"5\r\n" if chunked else b"") + b'{"seq')
    return sock


def _status(sock: socket.socket) -> int:
    """The status of the answer on ``sock`` (within its timeout); the socket is closed."""
    data = b""
    with sock:
        while b"\r\n" not in data:
            chunk = sock.recv(4096)
            if not chunk:
                break
            data += chunk
    return int(data.split()[1])


def _other_stand_posts(url: str, posts: int) -> list[float]:
    """The other PC opens a run and posts ``posts`` batches: the seconds each took."""
    took = []
    with httpx.Client(base_url=url, timeout=30, headers=auth(OTHER)) as http:
        r = http.post(f"{API}/runs", json={"stand": "smts2", "operator": "Petrov"})
        assert r.status_code == 201, r.text
        run_id = r.json()["id"]
        for seq in range(posts):
            start = time.monotonic()
            r = http.post(f"{API}/runs/{run_id}/readings", json=json_batch(seq, seq * 5, 5))
            took.append(time.monotonic() - start)
            assert r.status_code == 201, r.text
    return took


@pytest.mark.parametrize(
    ("uploads", "length", "chunked"),
    [(64, 400, False), (1, 8 << 20, False), (3, 0, True)],
    ids=["64 slow small uploads", "one trickling large body", "chunked uploads that stall"],
)
def test_one_keys_slow_uploads_do_not_starve_another_stand(
    server: Server, uploads: int, length: int, chunked: bool
) -> None:
    with httpx.Client(base_url=server.url, timeout=30) as http:
        run_id = open_run(http)
    opened = time.monotonic()
    slow = [_slow_post(server.port, run_id, length, chunked=chunked) for _ in range(uploads)]
    try:
        time.sleep(0.3)  # the slow uploads are admitted (or refused) first
        took = _other_stand_posts(server.url, 10)
        during = time.monotonic() - opened
        statuses = [_status(sock) for sock in slow]
        answered = time.monotonic() - opened
    finally:
        for sock in slow:
            sock.close()
    assert during < BODY_TIMEOUT, "the other stand posted after the slow uploads timed out"
    assert max(took) < 2.0, took  # promptly: not held behind the slow uploads
    held = min(uploads, 2)  # the slow key's share of the queue
    assert sorted(statuses) == [408] * held + [503] * (uploads - held)
    assert answered < BODY_TIMEOUT + 5  # the held ones were let go at their time limit
    with httpx.Client(base_url=server.url, timeout=30) as http:
        run = http.get(f"{API}/runs/{run_id}", headers=auth(WRITER)).json()
    assert run["batches"] == 0


def test_a_trickling_body_that_declares_64_mib_leaves_the_queue_to_the_others(
    server: Server,
) -> None:
    """The MTOS PC's post declares the largest body (64 MiB, the whole queue's bytes) and
    sends a byte every 0.5 s: it holds the bytes that came, so the other stand's posts are
    all taken meanwhile (they were 503 until its time ran out), and it is let go at its
    time limit (issue 22, item 7)."""
    with httpx.Client(base_url=server.url, timeout=30) as http:
        r = http.post(
            f"{API}/runs", json={"stand": "mtos", "operator": "x"}, headers=auth(MTOS_ONLY)
        )
        assert r.status_code == 201, r.text
        mtos_run = r.json()["id"]
    sock = socket.create_connection(("127.0.0.1", server.port), timeout=BODY_TIMEOUT + 10)
    head = (
        f"POST {API}/runs/{mtos_run}/readings HTTP/1.1\r\nHost: 127.0.0.1\r\n"
        f"Authorization: Bearer {MTOS_ONLY}\r\nContent-Type: application/json\r\n"
        f"Content-Length: {64 << 20}\r\n\r\n"
    )
    sock.sendall(head.encode())
    stop = threading.Event()

    def trickle() -> None:
        for byte in b'{"seq": 0, "group": "steps", "columns": {' * 100:
            if stop.wait(0.5):
                return
            try:
                sock.sendall(bytes([byte]))
            except OSError:  # answered and closed
                return

    dripping = threading.Thread(target=trickle)
    dripping.start()
    opened = time.monotonic()
    try:
        time.sleep(0.5)  # the upload is admitted first
        took = _other_stand_posts(server.url, 10)  # each asserts its 201
        during = time.monotonic() - opened
        status = _status(sock)
        answered = time.monotonic() - opened
    finally:
        stop.set()
        dripping.join()
        sock.close()
    assert during < BODY_TIMEOUT, "the other stand posted after the slow upload timed out"
    assert max(took) < 2.0, took
    assert status == 408
    assert answered < BODY_TIMEOUT + 5
