"""``rigserver serve`` stops cleanly on SIGTERM and Ctrl-C, a live stream open or not
(issue 14, item 7)."""

from __future__ import annotations

import signal
import threading
import time

import httpx
import pytest

from rigserver.cli import SHUTDOWN_GRACE
from tests.api.conftest import READER, Server, auth
from tests.api.test_http import post_run

API = "/api/v1"


def _hold_live_stream(url: str, run_id: str, opened: threading.Event) -> None:
    try:
        with httpx.stream(
            "GET", f"{url}{API}/runs/{run_id}/live", headers=auth(READER), timeout=60
        ) as r:
            opened.set()
            for _ in r.iter_lines():
                pass
    except httpx.HTTPError:
        pass  # the server went away: what this test does to it
    finally:
        opened.set()


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_serve_stops_on_a_signal_with_a_live_stream_open(
    server: Server, sig: signal.Signals
) -> None:
    run_id = post_run(server.url, "mtos")
    opened = threading.Event()
    viewer = threading.Thread(target=_hold_live_stream, args=(server.url, run_id, opened))
    viewer.start()
    assert opened.wait(30)
    assert server.proc is not None
    sent = time.monotonic()
    server.proc.send_signal(sig)  # the server alone, not its group
    status = server.proc.wait(timeout=SHUTDOWN_GRACE + 20)
    took = time.monotonic() - sent
    viewer.join(30)
    # SIGTERM: uvicorn stops, then dies of the signal as a well-behaved process does;
    # SIGINT: 130, or 0 where the test session ignores SIGINT (a background job)
    assert status in ((-signal.SIGTERM,) if sig is signal.SIGTERM else (130, 0))
    assert took < SHUTDOWN_GRACE + 10  # the stream (60 s) did not hold the shutdown
    assert "Traceback" not in server.log.read_text(errors="replace")
