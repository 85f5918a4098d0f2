"""rigclient.Client over a fake server: the spool acknowledges, the sender delivers."""

from __future__ import annotations

import time
from pathlib import Path

import httpx
import numpy as np
import pytest

from rigclient import Client, InputError, RetryPolicy, SpoolFull, SpoolLimits
from rigclient.cli import main
from rigclient.spool import Spool
from tests.rigclient.fake import RUN_ID, FakeServer, problem

FAST = RetryPolicy(base_delay=0.01, max_delay=0.05)


def _client(server: FakeServer, spool: Path, **kwargs: object) -> Client:
    return Client(
        "http://rig.test",
        "writer-key-00000000000000",
        spool=spool,
        transport=httpx.MockTransport(server),
        retry=FAST,
        seed=0,
        **kwargs,  # type: ignore[arg-type]
    )


def _profile(start: float, rows: int = 3) -> dict[str, np.ndarray]:
    x = start + np.arange(rows, dtype=float)
    return {"x": x, "y": np.sin(x)}


def test_post_is_durable_before_the_network_and_delivered_in_order_later(
    tmp_path: Path,
) -> None:
    server = FakeServer()
    server.down = True
    with _client(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov", title="no network")
        assert run.local_id.startswith("local-") and run.server_id is None
        seqs = [run.post("profile", _profile(3.0 * k)) for k in range(4)]
        run.finish()
        assert seqs == [0, 1, 2, 3]
        assert not client.wait(0.3)
        status = client.status()
        assert status.pending == 4 and status.retries > 0
        assert status.waiting is not None and "ConnectError" in status.waiting
        server.down = False
        assert client.wait(10)
        assert run.server_id == RUN_ID and server.state == "finished"
    assert sorted(server.stored) == [0, 1, 2, 3]
    joined = np.concatenate([server.stored[k]["x"] for k in range(4)])
    np.testing.assert_array_equal(joined, np.arange(12.0))
    assert server.calls[-1] == f"POST /api/v1/runs/{RUN_ID}/finish"
    # the readings were posted in seq order, the finish after the last one
    posts = [c for c in server.calls if c.endswith("/readings")]
    assert len(posts) == 4


def test_a_restart_on_the_same_spool_resumes_with_the_same_opening_key(tmp_path: Path) -> None:
    server = FakeServer()

    def open_then_go_down(request: httpx.Request) -> httpx.Response:
        server(request)  # the server opens the run; the answer is lost, the network goes
        server.down = True
        raise httpx.ReadError("connection reset", request=request)

    server.script = [open_then_go_down]
    with _client(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", _profile(0.0))
        assert not client.wait(0.3)
    # the agent is gone (as after a kill or a reboot) and starts again on the same spool
    server.down = False
    with _client(server, tmp_path) as client:
        again = client.run(run.local_id)
        again.post("profile", _profile(3.0))
        again.finish()
        assert client.wait(10)
    assert len(server.keys) == 2 and server.keys[0] == server.keys[1]
    assert sorted(server.stored) == [0, 1] and server.state == "finished"


def test_a_duplicate_receipt_counts_as_delivered(tmp_path: Path) -> None:
    server = FakeServer()

    def store_then_drop(request: httpx.Request) -> httpx.Response:
        server(request)
        raise httpx.ReadError("connection reset", request=request)

    server.script = [lambda r: None, store_then_drop]  # the opening, then the first batch
    with _client(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", _profile(0.0))
        run.finish()
        assert client.wait(10)
        assert client.status().duplicates == 1
        assert run.status().acknowledged == 1 and run.status().state == "delivered"


def test_a_refused_batch_stops_its_run_and_stays_in_the_spool(tmp_path: Path) -> None:
    server = FakeServer()
    detail = "y[1] = 1200 um is outside the limit: -1000 <= value <= 1000 um"
    refusal = problem(422, "Readings refused", detail)
    server.script = [lambda r: None, lambda r: None, lambda r: refusal]
    with _client(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        for k in range(3):
            run.post("profile", _profile(3.0 * k))
        run.finish()
        assert not client.wait(10)  # returns as soon as only a refusal is left
        record = run.status()
    assert record.state == "refused" and record.refused_what == "batch 1"
    assert record.refused is not None and record.refused["detail"] == detail
    assert (record.acknowledged, record.pending) == (1, 2)  # nothing dropped
    assert sorted(server.stored) == [0] and server.state == "open"
    # the spool still holds the refused batch and the next one, as posted
    with Spool(tmp_path) as spool:
        pending = spool.next_batch(run.local_id)
    assert pending is not None and pending.seq == 1


def test_a_refused_opening_is_kept_with_the_servers_problem(tmp_path: Path) -> None:
    server = FakeServer()
    detail = "configuration.spring_rate: a number is needed"
    server.script = [lambda r: problem(422, "Run refused", detail)]
    with _client(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", _profile(0.0))
        assert not client.wait(10)
        record = run.status()
    assert record.refused_what == "opening" and record.refused is not None
    assert record.refused["detail"] == detail and record.pending == 1


def test_a_key_refused_at_the_opening_is_tried_again(tmp_path: Path) -> None:
    """403 is not the opening's fault: tried again (a key changed on the server)."""
    server = FakeServer()
    server.script = [lambda r: problem(403, "Forbidden", "the key lacks write:profilometer")]
    with _client(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", _profile(0.0))
        assert client.wait(10)
        assert run.status().refused is None and run.status().last_error is None
    assert sorted(server.stored) == [0]


def test_retry_after_is_honoured(tmp_path: Path) -> None:
    server = FakeServer()
    busy = problem(503, "Service unavailable", "the journal is busy")
    busy.headers["Retry-After"] = "1"
    times: list[float] = []

    def busy_once(request: httpx.Request) -> httpx.Response:
        times.append(time.monotonic())
        return busy

    def stamp(request: httpx.Request) -> None:
        times.append(time.monotonic())

    server.script = [lambda r: None, busy_once, stamp]
    with _client(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", _profile(0.0))
        assert client.wait(10)
    assert times[1] - times[0] >= 0.95  # the backoff alone would be <= 0.01 s


def test_the_spool_size_bound_is_a_clear_error(tmp_path: Path) -> None:
    server = FakeServer()
    server.down = True
    limits = SpoolLimits(max_bytes=2000)
    with _client(server, tmp_path, limits=limits) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        with pytest.raises(SpoolFull, match=r"limit \(max_bytes\) is 0\.0 MB"):
            for k in range(100):
                run.post("profile", _profile(3.0 * k))
        assert 0 < run.status().pending < 100  # what was acknowledged is kept


def test_the_spool_age_bound_is_a_clear_error(tmp_path: Path) -> None:
    server = FakeServer()
    server.down = True
    with _client(server, tmp_path, limits=SpoolLimits(max_age=0.2)) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", _profile(0.0))
        time.sleep(0.3)
        with pytest.raises(SpoolFull, match=r"limit \(max_age\)"):
            run.post("profile", _profile(3.0))


def test_names_are_checked_before_spooling(tmp_path: Path) -> None:
    with _client(FakeServer(), tmp_path, start=False) as client:
        with pytest.raises(InputError, match="run's stand"):
            client.open_run(stand="lathe", operator="Petrov")
        run = client.open_run(stand="profilometer", operator="Petrov")
        with pytest.raises(InputError, match="no channel group 'friction'"):
            run.post("friction", {"x": [1.0]})
        with pytest.raises(InputError, match="got z"):
            run.post("profile", {"x": [1.0], "y": [2.0], "z": [3.0]})
        with pytest.raises(InputError, match="channel 'y' is missing"):
            run.post("profile", {"x": [1.0]})
        assert run.status().batches == 0


def test_batches_go_as_json_columns_when_asked(tmp_path: Path) -> None:
    server = FakeServer()
    seen: list[str] = []

    def content_type(request: httpx.Request) -> None:
        seen.append(request.headers["content-type"])

    server.script = [lambda r: None, content_type]
    with _client(server, tmp_path, binary=False) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", _profile(0.0))
        assert client.wait(10)
    assert seen == ["application/json"]
    assert server.stored[0]["x"] == [0.0, 1.0, 2.0]


def test_status_lists_pending_acknowledged_and_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    server = FakeServer()
    server.script = [lambda r: None, lambda r: problem(422, "Readings refused", "y[0] too high")]
    with _client(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov", title="trace 7")
        run.post("profile", _profile(0.0))
        run.post("profile", _profile(3.0))
        assert not client.wait(10)
    assert main(["status", "--spool", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "trace 7" in out and "refused" in out and "batch 0: 422 y[0] too high" in out
    assert main(["status", "--spool", str(tmp_path / "nowhere")]) == 1
    assert "no spool in" in capsys.readouterr().err


def test_tail_with_the_server_out_of_reach_prints_the_local_id_and_keeps_the_rows(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "trace.csv"
    path.write_text("x;y\n0;1\n0,5;2\n", encoding="utf-8")
    spool = tmp_path / "spool"
    args = ["tail", str(path), "--stand", "profilometer", "--group", "profile", "--id-wait", "1"]
    args += ["--url", "http://127.0.0.1:9", "--spool", str(spool)]  # nothing listens there
    assert main([*args, "--finish-after-idle", "0.5", "--drain", "0.5"]) == 1  # not delivered
    out, err = capsys.readouterr()
    assert out.startswith("local-") and "1 batch (2 rows) and the finish wait in the spool" in err
    assert "POST http://127.0.0.1:9/api/v1/runs: connection refused" in err
    with Spool(spool) as opened:
        (record,) = opened.runs()
    assert (record.pending, record.finish_queued, record.server_id) == (1, True, None)


def test_an_answer_that_is_not_the_apis_is_tried_again(tmp_path: Path) -> None:
    """A proxy's HTML page where the receipt should be: not delivered, tried again."""
    server = FakeServer()
    page = httpx.Response(200, text="<html>Welcome to the lab network</html>")
    server.script = [lambda r: None, lambda r: page]
    with _client(server, tmp_path) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        run.post("profile", _profile(0.0))
        assert client.wait(10)
        assert client.status().retries == 1
    assert sorted(server.stored) == [0]
