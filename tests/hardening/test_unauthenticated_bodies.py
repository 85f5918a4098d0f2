"""Bodies without a key are bounded at their route's own limit before they are read (issue
22, item 8): ``POST /login`` read the whole body (up to 64 MiB) before its 4 KiB check,
and 16 unauthenticated connections held the server's RSS at 1.2 GB. Now a Content-Length
over the route's limit is answered 413 before a byte of the body is read, a chunked body
is cut at the limit, and the server's memory stays where it was. Over real HTTP with raw
sockets on loopback; every wait is bounded."""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from rigserver.api.app import ANONYMOUS_BODY_BYTES
from rigserver.api.routes.pages import LOGIN_BODY_BYTES
from tests.api.conftest import READER, Server, auth
from tests.hardening.conftest import API, hdf5_app, is_problem, keys_file
from tests.hardening.test_overload import memory_mb

MB = 1 << 20
#: Connections at once, and the bytes each sends of the 64 MiB it declares.
CONNECTIONS, SENT = 16, 8 * MB


@pytest.fixture
def server(tmp_path: Path) -> Iterator[Server]:
    """Reads are public: the calculators take posts without a key too."""
    served = Server(tmp_path / "data", keys_file(tmp_path), public_reads=True)
    served.start()
    try:
        yield served
    finally:
        served.stop()


def _post(
    port: int, path: str, *, chunked: bool, sent: threading.Barrier, statuses: list[int]
) -> None:
    """A post to ``path`` without a key declaring 64 MiB (or chunked), sending up to
    :data:`SENT` bytes of it while the server reads, then waiting at ``sent`` (twice: the
    server's memory is measured in between); the answer's status (0 for none in time) is
    appended to ``statuses``."""
    with socket.create_connection(("127.0.0.1", port), timeout=20) as sock:
        framing = "Transfer-Encoding: chunked" if chunked else f"Content-Length: {64 * MB}"
        head = (
            f"POST {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nOrigin: http://127.0.0.1:{port}"
            f"\r\nContent-Type: application/x-www-form-urlencoded\r\n{framing}\r\n\r\n"
        )
        sock.sendall(head.encode())
        piece = b"key=" + b"k" * (64 * 1024 - 4)
        if chunked:
            piece = f"{len(piece):x}\r\n".encode() + piece + b"\r\n"
        try:
            for _ in range(SENT // (64 * 1024)):
                sock.sendall(piece)
        except OSError:  # answered and closed: the rest is not read
            pass
        sent.wait(60)
        sent.wait(60)
        data = b""
        try:
            while b"\r\n" not in data:
                chunk = sock.recv(4096)
                if not chunk:
                    break
                data += chunk
        except OSError:
            pass
    statuses.append(int(data.split()[1]) if data.startswith(b"HTTP/") else 0)


@pytest.mark.parametrize("chunked", [False, True], ids=["Content-Length", "chunked"])
@pytest.mark.parametrize("path", ["/login", f"{API}/models/wear/theoretical"])
def test_unauthenticated_large_bodies_are_413_and_memory_stays_bounded(
    server: Server, path: str, chunked: bool
) -> None:
    assert server.proc is not None
    idle, _ = memory_mb(server.proc.pid)
    statuses: list[int] = []
    sent = threading.Barrier(CONNECTIONS + 1)
    posts = [
        threading.Thread(
            target=_post,
            args=(server.port, path),
            kwargs={"chunked": chunked, "sent": sent, "statuses": statuses},
        )
        for _ in range(CONNECTIONS)
    ]
    for post in posts:
        post.start()
    sent.wait(60)  # every connection has sent what it could, and is open
    time.sleep(0.5)
    held, _ = memory_mb(server.proc.pid)
    sent.wait(60)
    for post in posts:
        post.join(60)
    # read whole, the 16 x 8 MiB sent would be 128 MiB held
    assert held - idle < 32, (idle, held)
    assert statuses == [413] * CONNECTIONS, statuses


def test_each_route_has_its_own_limit_without_a_key(tmp_path: Path) -> None:
    """The login form takes 4 KiB, any other request without a key 64 KiB, one with a key
    the server's ``max_body_bytes``; the 413 names the limit."""
    app = hdf5_app(tmp_path / "data", public_reads=True)
    with TestClient(app, raise_server_exceptions=False) as client:
        origin = {"origin": "http://testserver"}
        r = client.post("/login", content=b"key=" + b"k" * LOGIN_BODY_BYTES, headers=origin)
        assert r.status_code == 413 and is_problem(r)
        assert f"exceeds {LOGIN_BODY_BYTES} bytes" in r.json()["detail"]
        r = client.post("/login", content=b"key=wrong", headers=origin)
        assert r.status_code == 401  # a form within the limit is read
        body = b'{"load": 300' + b" " * ANONYMOUS_BODY_BYTES + b"}"
        path = f"{API}/models/wear/theoretical"
        r = client.post(path, content=body, headers={"content-type": "application/json"})
        assert r.status_code == 413 and is_problem(r)
        assert f"exceeds {ANONYMOUS_BODY_BYTES} bytes" in r.json()["detail"]
        keyed = {"content-type": "application/json", **auth(READER)}
        assert client.post(path, content=body, headers=keyed).status_code == 200
