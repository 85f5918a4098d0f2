"""Issue 22, item 1: a single unexpected answer never strands a run.

Only an answer that names the request itself as wrong (422 with the API's problem document)
refuses a batch; a proxy's page, a 500, a timeout, a broken connection, a key refused
(401/403) are tried again, said with the URL; a new ``--key`` applies to what is pending;
``rigclient retry`` and ``drop`` clear what a refusal left, and ``status`` says what they
would do.
"""

from __future__ import annotations

import json
import sqlite3
from collections.abc import Callable
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest

import rigclient.client
from rigclient import Client, RetryPolicy
from rigclient.cli import main
from rigclient.http import Api
from rigclient.spool import Spool
from tests.rigclient.fake import RUN_ID, FakeServer, problem

FAST = RetryPolicy(base_delay=0.01, max_delay=0.05)
HEADER = "time [s];load [kN];speed [rpm];friction_moment [N*m];revolutions [100 rev]\n"
READINGS = f"http://rig.test/api/v1/runs/{RUN_ID}/readings"


def row(k: int) -> str:
    return f"{k * 0.5:.1f};0,3;1000;{2.9 + 0.001 * k:.3f};{k // 10}\n".replace(".", ",")


def stored_times(server: FakeServer) -> list[float]:
    return [t for seq in sorted(server.stored) for t in server.stored[seq].get("time", [])]


class KeyedServer(FakeServer):
    """The fake server with keys: a request without an accepted key is answered 401."""

    def __init__(self, *keys: str) -> None:
        super().__init__()
        self.accepted = set(keys)

    def __call__(self, request: httpx.Request) -> httpx.Response:
        given = request.headers.get("authorization", "").removeprefix("Bearer ")
        if given not in self.accepted:
            self.calls.append(f"401 {request.method} {request.url.path}")
            return problem(401, "Unauthorized", "the API key is not known")
        return super().__call__(request)


def client_of(
    server: Callable[[httpx.Request], httpx.Response], spool: Path, **options: Any
) -> Client:
    """A client of ``server`` (a fake at http://rig.test) with the key "k", retrying fast."""
    transport = httpx.MockTransport(server)
    return Client("http://rig.test", "k", spool=spool, transport=transport, retry=FAST, **options)


def html_page(status: int, title: str) -> httpx.Response:
    page = f"<html><head><title>{title}</title></head><body><h1>{title}</h1></body></html>"
    return httpx.Response(status, text=page, headers={"content-type": "text/html"})


def on_readings(n: int, answer: Callable[[httpx.Request], httpx.Response]) -> Any:
    """A server script: the ``n``-th post of readings (1-based) gets ``answer``."""
    count = {"readings": 0}

    def script(request: httpx.Request) -> httpx.Response | None:
        if request.url.path.endswith("/readings"):
            count["readings"] += 1
            if count["readings"] == n:
                return answer(request)
        return None

    return script


@pytest.fixture
def routed(monkeypatch: pytest.MonkeyPatch) -> Callable[[FakeServer], None]:
    """Route the command line's client to a fake server (rigclient.client.Api gets its
    transport), with fast retries."""

    def route(server: FakeServer) -> None:
        class Routed(Api):
            def __init__(self, *args: Any, **kwargs: Any) -> None:
                kwargs["transport"] = httpx.MockTransport(server)
                kwargs["retry"] = FAST
                super().__init__(*args, **kwargs)

        monkeypatch.setattr(rigclient.client, "Api", Routed)

    return route


class Scripted(FakeServer):
    """The fake server with a script consulted on every request (not popped)."""

    def __init__(self, script: Callable[[httpx.Request], httpx.Response | None]) -> None:
        super().__init__()
        self.every = script

    def __call__(self, request: httpx.Request) -> httpx.Response:
        answer = self.every(request)
        if answer is not None:
            self.calls.append(f"{answer.status_code} {request.method} {request.url.path}")
            return answer
        return super().__call__(request)


def _import(path: Path, spool: Path, *extra: str) -> list[str]:
    args = ["import", str(path), "--stand", "smts2", "--group", "friction", "--rows", "100"]
    return [*args, "--url", "http://rig.test", "--spool", str(spool), *extra]


def test_one_500_page_on_the_third_batch_of_a_1000_row_import_stores_every_row(
    tmp_path: Path, routed: Callable[[FakeServer], None], capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "smts2.csv"
    path.write_text(HEADER + "".join(row(k) for k in range(1000)), encoding="utf-8")
    server = Scripted(on_readings(3, lambda r: html_page(500, "500 Internal Server Error")))
    routed(server)
    code = main(_import(path, tmp_path / "spool", "--key", "k", "--drain", "20"))
    _out, err = capsys.readouterr()
    assert code == 0, err
    assert stored_times(server) == [k * 0.5 for k in range(1000)]  # every row, once, in order
    assert server.state == "finished"
    # said plainly: what happened, and to which URL
    assert "500 Internal Server Error" in err and READINGS in err, err
    assert "not the API's answer" in err, err


@pytest.mark.parametrize(
    "answer",
    [
        pytest.param(lambda r: html_page(500, "Internal Server Error"), id="500-html"),
        pytest.param(lambda r: problem(500, "Internal error", "a bug"), id="500-problem"),
        pytest.param(lambda r: html_page(502, "Bad Gateway"), id="502-html"),
        pytest.param(lambda r: html_page(404, "Not Found"), id="404-html-from-a-proxy"),
        pytest.param(lambda r: html_page(422, "Unprocessable"), id="422-html-from-a-proxy"),
        pytest.param(lambda r: html_page(200, "Welcome to the lab network"), id="200-html"),
        pytest.param(lambda r: problem(401, "Unauthorized", "key unknown"), id="401"),
        pytest.param(lambda r: problem(403, "Forbidden", "lacks write:x"), id="403"),
        pytest.param(lambda r: problem(409, "Conflict", "busy"), id="409"),
        pytest.param(lambda r: problem(400, "Bad request", "?"), id="400"),
        pytest.param(
            lambda r: (_ for _ in ()).throw(httpx.ReadTimeout("no answer", request=r)),
            id="read-timeout",
        ),
        pytest.param(
            lambda r: (_ for _ in ()).throw(httpx.RemoteProtocolError("closed", request=r)),
            id="connection-broke",
        ),
    ],
)
def test_only_the_apis_422_refuses_a_batch_every_other_failure_is_tried_again(
    tmp_path: Path, answer: Callable[[httpx.Request], httpx.Response]
) -> None:
    server = FakeServer()
    server.script = [lambda r: None, answer]  # the opening, then batch 0 fails once
    said: list[str] = []
    with client_of(server, tmp_path, say=said.append) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        for k in range(3):
            run.post("profile", {"x": [3.0 * k, 3.0 * k + 1], "y": [0.0, 1.0]})
        run.finish()
        assert client.wait(10), client.status()
        record = run.status()
    assert record.state == "delivered" and record.refused is None
    assert sorted(server.stored) == [0, 1, 2] and server.state == "finished"
    assert any(READINGS in s for s in said), said  # the failure was said, with the URL


def test_the_apis_422_refuses_the_batch_and_keeps_it(tmp_path: Path) -> None:
    server = FakeServer()
    server.script = [lambda r: None, lambda r: problem(422, "Readings refused", "y[1] too high")]
    said: list[str] = []
    with client_of(server, tmp_path, say=said.append) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", {"x": [0.0, 1.0], "y": [0.0, 1.0]})
        assert not client.wait(10)
        record = run.status()
    assert record.state == "refused" and record.pending == 1
    assert any("422 Readings refused: y[1] too high" in s and READINGS in s for s in said), said


def test_a_wrong_key_then_the_right_key_delivers(
    tmp_path: Path, routed: Callable[[FakeServer], None], capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "smts2.csv"
    path.write_text(HEADER + "".join(row(k) for k in range(250)), encoding="utf-8")
    spool = tmp_path / "spool"
    server = KeyedServer("right-key")
    routed(server)
    assert main(_import(path, spool, "--key", "wrong-key", "--drain", "1")) == 1
    err = capsys.readouterr().err
    assert "401 Unauthorized" in err and "http://rig.test/api/v1/runs" in err, err
    assert "--key" in err, err  # what to do about it
    assert server.stored == {}
    # the same command with the right key: the run in the spool goes on, with the new key
    assert main(_import(path, spool, "--key", "right-key", "--drain", "20")) == 0
    err = capsys.readouterr().err
    assert stored_times(server) == [k * 0.5 for k in range(250)], err
    assert server.state == "finished" and len(set(server.keys)) == 1
    with Spool(spool) as opened:
        (record,) = opened.runs()  # one run, not the file twice
    assert record.state == "delivered"


def test_a_key_refused_mid_run_is_tried_again_until_the_server_takes_it(tmp_path: Path) -> None:
    server = KeyedServer("k")
    with client_of(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", {"x": [0.0, 1.0], "y": [0.0, 1.0]})
        assert client.wait(10)
        server.accepted = {"another"}  # the key was revoked on the server
        run.post("profile", {"x": [2.0, 3.0], "y": [0.0, 1.0]})
        run.finish()
        assert not client.wait(0.5)
        status = client.status()
        assert status.waiting is not None and "401 Unauthorized" in status.waiting
        assert run.status().refused is None and run.status().last_error is not None
        server.accepted = {"k", "another"}  # ... and given back its scope
        assert client.wait(10)
    assert sorted(server.stored) == [0, 1] and server.state == "finished"


def test_a_new_key_applies_to_what_is_pending(tmp_path: Path) -> None:
    server = KeyedServer("new")
    transport = httpx.MockTransport(server)
    with Client("http://rig.test", "old", spool=tmp_path, transport=transport, retry=FAST) as c:
        run = c.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", {"x": [0.0, 1.0], "y": [0.0, 1.0]})
        run.finish()
        assert not c.wait(0.5)
    with Client("http://rig.test", "new", spool=tmp_path, transport=transport, retry=FAST) as c:
        assert c.wait(10)
    assert sorted(server.stored) == [0] and server.state == "finished"


def _refused_run(tmp_path: Path) -> tuple[FakeServer, str]:
    """A run of 4 batches (3 rows each) whose second batch the server refused (422)."""
    server = FakeServer()
    refusal = problem(422, "Readings refused", "y[1] = 1200 um is outside the limit")
    server.script = [lambda r: None, lambda r: None, lambda r: refusal]
    with client_of(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov", title="trace 7")
        for k in range(4):
            run.post("profile", {"x": 3.0 * k + np.arange(3.0), "y": np.zeros(3)})
        run.finish()
        assert not client.wait(10)
    return server, run.local_id


def test_status_says_what_retry_and_drop_would_do_and_retry_requeues(
    tmp_path: Path, routed: Callable[[FakeServer], None], capsys: pytest.CaptureFixture[str]
) -> None:
    server, _local_id = _refused_run(tmp_path)
    assert main(["status", "--spool", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "refused" in out and "422" in out
    assert f"rigclient retry {RUN_ID}" in out and "3 batches (9 rows)" in out, out
    assert f"rigclient drop {RUN_ID}" in out, out
    assert main(["status", "--spool", str(tmp_path), "--json"]) == 0
    (report,) = json.loads(capsys.readouterr().out)
    assert report["rows_pending"] == 9 and report["state"] == "refused"
    # the server's limit is fixed; the batches are queued again and delivered
    routed(server)
    assert main(["retry", RUN_ID, "--spool", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    assert "3 batches (9 rows)" in err and "queued again" in err, err
    assert main(["send", "--url", "http://rig.test", "--spool", str(tmp_path)]) == 0
    capsys.readouterr()
    assert sorted(server.stored) == [0, 1, 2, 3] and server.state == "finished"
    joined = np.concatenate([server.stored[k]["x"] for k in range(4)])
    np.testing.assert_array_equal(joined, np.arange(12.0))


def test_drop_drops_what_is_pending_and_says_how_many_rows(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _server, local_id = _refused_run(tmp_path)
    assert main(["drop", local_id, "--spool", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    assert "dropped 3 batches (9 rows)" in err and "the server keeps" in err, err
    with Spool(tmp_path) as spool:
        (record,) = spool.runs()
    assert (record.state, record.pending, record.done) == ("dropped", 0, True)
    assert main(["drop", "no-such-run", "--spool", str(tmp_path)]) == 1
    assert "no run no-such-run" in capsys.readouterr().err


# --- an existing spool, written by the rigclient before this one ---------------------------

OLD_SCHEMA = """
CREATE TABLE runs (local_id TEXT PRIMARY KEY, stand TEXT NOT NULL, body TEXT NOT NULL,
    idempotency_key TEXT NOT NULL, server_id TEXT, next_seq INTEGER NOT NULL DEFAULT 0,
    acknowledged INTEGER NOT NULL DEFAULT 0, finish_queued INTEGER NOT NULL DEFAULT 0,
    finished INTEGER NOT NULL DEFAULT 0, refused TEXT, refused_what TEXT, created REAL NOT NULL);
CREATE TABLE batches (local_id TEXT NOT NULL, seq INTEGER NOT NULL, grp TEXT NOT NULL,
    rows INTEGER NOT NULL, payload BLOB NOT NULL, created REAL NOT NULL,
    PRIMARY KEY (local_id, seq));
CREATE TABLE sources (key TEXT PRIMARY KEY, local_id TEXT NOT NULL, path TEXT NOT NULL,
    device INTEGER NOT NULL, inode INTEGER NOT NULL, position INTEGER NOT NULL,
    line INTEGER NOT NULL);
CREATE TABLE rejects (local_id TEXT NOT NULL, file TEXT NOT NULL, line INTEGER NOT NULL,
    col TEXT NOT NULL, message TEXT NOT NULL, created REAL NOT NULL);
"""


def old_spool(directory: Path, refusal: dict[str, Any]) -> None:
    """A spool as the old rigclient left it: a run stopped at batch 1 by ``refusal``."""
    from rigclient.http import npz_bytes

    directory.mkdir(parents=True, exist_ok=True)
    db = sqlite3.connect(directory / "spool.sqlite")
    db.executescript(OLD_SCHEMA)
    body = json.dumps({"stand": "profilometer", "operator": "Petrov", "title": "old"})
    db.execute(
        "INSERT INTO runs VALUES ('local-old', 'profilometer', ?, 'key-1', ?, 3, 1, 1, 0, ?, "
        "'batch 1', 1.0)",
        (body, RUN_ID, json.dumps(refusal)),
    )
    for seq in (1, 2):
        payload = npz_bytes({"x": [3.0 * seq, 3.0 * seq + 1], "y": [0.0, 0.0]})
        db.execute(
            "INSERT INTO batches VALUES ('local-old', ?, 'profile', 2, ?, 1.0)", (seq, payload)
        )
    db.commit()
    db.close()


def test_an_old_spool_stopped_by_a_500_is_delivered_after_the_upgrade(tmp_path: Path) -> None:
    old_spool(tmp_path, {"title": "Internal Server Error", "status": 500, "detail": "<html>"})
    server = FakeServer()
    server.stored[0] = {"x": [0.0, 1.0], "y": [0.0, 0.0]}
    with client_of(server, tmp_path) as client:
        assert client.wait(10), client.status()
    assert sorted(server.stored) == [0, 1, 2] and server.state == "finished"


def test_an_old_spool_refused_by_a_422_stays_refused(tmp_path: Path) -> None:
    old_spool(tmp_path, {"title": "Readings refused", "status": 422, "detail": "y too high"})
    with Spool(tmp_path) as spool:
        (record,) = spool.runs()
    assert record.state == "refused" and record.pending == 2 and record.rows_pending == 4


def test_a_proxy_page_in_place_of_the_finish_is_not_taken_for_it(tmp_path: Path) -> None:
    """Found by the state machine: a 200 page from a proxy counted as the finish."""
    server = Scripted(
        lambda r: html_page(200, "Welcome") if r.url.path.endswith("/finish") else None
    )
    with client_of(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", {"x": [0.0, 1.0], "y": [0.0, 1.0]})
        run.finish()
        assert not client.wait(0.5)  # not finished while the proxy answers for the server
        assert "not the finished run" in str(run.status().last_error)
        server.every = lambda r: None
        assert client.wait(10)
    assert server.state == "finished"
