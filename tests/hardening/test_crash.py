"""kill -9 of the server at random moments while several clients post: after each restart
every acknowledged batch is stored exactly once, and every run file opens."""

from __future__ import annotations

import random
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import TypeVar

import h5py
import httpx
import numpy as np
import pytest

from tests.api.conftest import READER, WRITER, auth
from tests.hardening.conftest import API, friction, npz_body, open_run, serve

ROUNDS = 5  # each round a kill and a restart (~5 s); storage/test_crash.py kills the stores too
SEED = 20261122
T = TypeVar("T")


@dataclass
class Client:
    """A lab PC posting one form of batch, retrying each until acknowledged; every
    ``finish_every`` batches it finishes its run and opens another."""

    form: str  # "single" (one-row JSON), "json" or "npz"
    rows: int
    finish_every: int = 0
    runs: dict[str, int] = field(default_factory=dict)  # run id -> batches acknowledged
    finished: list[str] = field(default_factory=list)

    def batch(self, http: httpx.Client, run_id: str, seq: int) -> httpx.Response:
        columns = friction(seq * self.rows, self.rows)
        url = f"{API}/runs/{run_id}/readings"
        if self.form == "npz":
            return http.post(
                url,
                params={"seq": seq, "group": "friction"},
                content=npz_body(columns),
                headers={**auth(WRITER), "content-type": "application/x-npz"},
            )
        lists = {k: v.tolist() for k, v in columns.items()}
        body = {"seq": seq, "group": "friction", "columns": lists}
        return http.post(url, json=body, headers=auth(WRITER))

    def run(self, url: str, stop: threading.Event) -> None:
        with httpx.Client(base_url=url, timeout=5) as http:
            run_id = retry(lambda: open_run(http), stop)
            while run_id is not None and not stop.is_set():
                self.runs[run_id] = 0
                for seq in range(self.finish_every or 10**9):
                    post = partial(self.batch, http, run_id, seq)
                    if retry(lambda post=post: self._acked(post()), stop) is None:  # type: ignore[misc]
                        return
                    self.runs[run_id] = seq + 1
                if retry(partial(self._finish, http, run_id), stop) is None:
                    return
                self.finished.append(run_id)
                run_id = retry(lambda: open_run(http), stop)

    @staticmethod
    def _acked(r: httpx.Response) -> bool:
        if r.status_code in (200, 201):
            return True
        assert r.status_code == 503, r.text  # a restarting store, or the queue
        raise httpx.TransportError("retry")

    @staticmethod
    def _finish(http: httpx.Client, run_id: str) -> bool:
        r = http.post(f"{API}/runs/{run_id}/finish", headers=auth(WRITER))
        if r.status_code == 409:  # its first answer was lost to a kill
            r = http.get(f"{API}/runs/{run_id}", headers=auth(READER))
            assert r.json()["state"] == "finished", r.text
            return True
        if r.status_code == 503:
            raise httpx.TransportError("retry")
        assert r.status_code == 200, r.text
        return True


def retry(call: Callable[[], T], stop: threading.Event) -> T | None:
    """``call()`` until it gets through (None once stopped): the server may be down."""
    while not stop.is_set():
        try:
            return call()
        except httpx.TransportError:
            time.sleep(0.02)
    return None


@pytest.mark.slow
def test_kill_9_at_random_moments_loses_and_duplicates_nothing(tmp_path: Path) -> None:
    rng = random.Random(SEED)
    server = serve(tmp_path)
    clients = [
        Client("single", 1),
        Client("single", 1),
        Client("json", 200, finish_every=25),
        Client("npz", 5000),
        Client("npz", 20_000, finish_every=8),
    ]
    stop = threading.Event()
    errors: list[BaseException] = []

    def work(client: Client) -> None:
        try:
            client.run(server.url, stop)
        except BaseException as exc:
            errors.append(exc)

    threads = [threading.Thread(target=work, args=(c,)) for c in clients]
    try:
        for t in threads:
            t.start()
        for _ in range(ROUNDS):
            time.sleep(rng.uniform(0.1, 0.8))
            server.kill()
            server.start()
        time.sleep(0.5)
        stop.set()
        for t in threads:
            t.join(30)
        assert errors == []
        assert not any(t.is_alive() for t in threads)
        server.kill()  # and once more, with nothing in flight
        server.start()
        with httpx.Client(base_url=server.url, timeout=60) as http:
            for client in clients:
                assert sum(client.runs.values()) > 0, f"{client.form}: nothing acknowledged"
                for run_id, acked in client.runs.items():
                    run = http.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()
                    state = "finished" if run_id in client.finished else "open"
                    assert run["state"] == state
                    # the batch in flight at the end may be stored without its answer
                    stored = run["rows"]["friction"] // client.rows
                    assert stored in (acked, acked + 1), (client.form, stored, acked)
                    times = [
                        http.get(
                            f"{API}/runs/{run_id}/readings",
                            params={"group": "friction", "start": start, "stop": start + 10**6},
                            headers=auth(READER),
                        ).json()["friction"]["columns"]["time"]
                        for start in range(0, stored * client.rows, 10**6)
                    ]
                    # each batch once, in order: time is the row number
                    expected = np.arange(stored * client.rows, dtype=float)
                    np.testing.assert_array_equal(np.concatenate([[], *times]), expected)
    finally:
        stop.set()
        server.stop()
    # every run file opens (a run whose POST /runs answer was lost is open and empty)
    files = sorted(Path(server.data_dir, "runs").glob("*.h5"))
    assert {p.stem for p in files} >= {r for c in clients for r in c.runs}
    for path in files:
        with h5py.File(path, "r") as f:
            time_column = f["entry/friction/time"][()]
            np.testing.assert_array_equal(time_column, np.arange(len(time_column), dtype=float))
            finished = bool(f["entry"].attrs.get("finalized", False))
            assert finished == any(path.stem in c.finished for c in clients)
