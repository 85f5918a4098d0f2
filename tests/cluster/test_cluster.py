"""Several rigserver workers on one PostgreSQL (``scripts/cluster``): any worker takes any
post, the others read it and stream it live, a run ends once; kill -9 of a worker and a
restart of PostgreSQL lose nothing acknowledged."""

from __future__ import annotations

import json
import os
import shutil
import signal
import tempfile
import threading
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import httpx
import pytest

from rigserver import cluster
from rigserver.storage.servers.pgserver import LocalPostgres, NoPostgres
from tests.postgres import NO_POSTGRES

API = "/api/v1"
pytestmark = pytest.mark.slow


@dataclass
class Cluster:
    directory: Path
    urls: list[str]
    key: str

    @property
    def headers(self) -> dict[str, str]:
        return {"Authorization": f"Bearer {self.key}"}

    @property
    def postgres(self) -> LocalPostgres:
        state = json.loads((self.directory / "cluster.json").read_text())
        return LocalPostgres(self.directory / "postgres", int(state["postgres_port"]))

    def pid(self, n: int) -> int:
        return int((self.directory / f"worker-{n}.pid").read_text())


@pytest.fixture(scope="module")
def two_workers() -> Iterator[Cluster]:
    yield from running(hsds_reads=False)


def running(*, hsds_reads: bool) -> Iterator[Cluster]:
    """Two workers (``scripts/cluster up``) until the generator is closed."""
    top = Path(tempfile.mkdtemp(prefix="rig-cluster-test-"))
    top.chmod(0o711)
    directory = top / "c"
    try:
        urls = cluster.up(directory, 2, hsds_reads=hsds_reads)
    except NoPostgres as exc:
        shutil.rmtree(top, ignore_errors=True)
        pytest.skip(NO_POSTGRES.format(exc))
    key = json.loads((directory / "keys.json").read_text())[0]["key"]
    try:
        yield Cluster(directory, urls, key)
    finally:
        cluster.down(directory)
        shutil.rmtree(top, ignore_errors=True)


def open_run(c: Cluster, url: str) -> str:
    r = httpx.post(
        f"{url}{API}/runs", json={"stand": "smts2", "operator": "cluster"}, headers=c.headers
    )
    assert r.status_code == 201, r.text
    return str(r.json()["id"])


def batch(seq: int, n: int = 10) -> dict[str, object]:
    """Batch ``seq``: rows ``seq*n .. seq*n+n-1``, time increasing across batches."""
    t0 = seq * n
    return {
        "seq": seq,
        "group": "friction",
        "columns": {
            "time": [float(t0 + i) for i in range(n)],
            "load": [300.0] * n,
            "speed": [1000.0] * n,
            "friction_moment": [2.5] * n,
            "revolutions": [float(t0 + i) for i in range(n)],
        },
    }


def post(c: Cluster, url: str, run_id: str, seq: int) -> httpx.Response:
    return httpx.post(
        f"{url}{API}/runs/{run_id}/readings", json=batch(seq), headers=c.headers, timeout=10
    )


def friction_of(c: Cluster, url: str, run_id: str) -> httpx.Response:
    """The run's friction readings as JSON, asked of the worker at ``url``."""
    return httpx.get(
        f"{url}{API}/runs/{run_id}/readings",
        params={"format": "json", "group": "friction"},
        headers=c.headers,
        timeout=30,
    )


def stored_times(c: Cluster, url: str, run_id: str) -> list[float]:
    r = friction_of(c, url, run_id)
    assert r.status_code == 200, r.text
    return [float(v) for v in r.json()["friction"]["columns"]["time"]]


def test_any_worker_takes_any_post_and_every_worker_reads_it(two_workers: Cluster) -> None:
    c = two_workers
    run_id = open_run(c, c.urls[0])
    for seq in range(6):  # alternate the workers, as a load balancer would
        r = post(c, c.urls[seq % 2], run_id, seq)
        assert r.status_code == 201, r.text
    again = post(c, c.urls[1], run_id, 0)  # the retry of a batch the other worker took
    assert again.status_code == 200 and again.json()["duplicate"] is True
    expected = [float(t) for t in range(60)]  # six batches of 10 rows, times 0..59
    for url in c.urls:
        assert stored_times(c, url, run_id) == expected
        run = httpx.get(f"{url}{API}/runs/{run_id}", headers=c.headers).json()
        assert run["rows"]["friction"] == 60 and run["batches"] == 6


def test_live_stream_on_one_worker_shows_what_another_stored(two_workers: Cluster) -> None:
    c = two_workers
    run_id = open_run(c, c.urls[0])
    assert post(c, c.urls[0], run_id, 0).status_code == 201
    seen: list[float] = []

    def watch() -> None:
        with httpx.stream(
            "GET",
            f"{c.urls[1]}{API}/runs/{run_id}/live",
            params={"group": "friction"},
            headers=c.headers,
            timeout=30,
        ) as r:
            for line in r.iter_lines():
                if line.startswith("data:") and '"columns"' in line:
                    seen.extend(json.loads(line[5:])["columns"]["time"])
                if len(seen) >= 20:
                    return

    watcher = threading.Thread(target=watch)
    watcher.start()
    time.sleep(0.5)
    assert post(c, c.urls[0], run_id, 1).status_code == 201  # posted to the other worker
    watcher.join(timeout=30)
    assert not watcher.is_alive()
    assert seen == [float(t) for t in range(20)]


def test_a_run_ends_once_whichever_workers_are_asked(two_workers: Cluster) -> None:
    c = two_workers
    run_id = open_run(c, c.urls[0])
    assert post(c, c.urls[1], run_id, 0).status_code == 201

    def finish(url: str) -> int:
        return httpx.post(
            f"{url}{API}/runs/{run_id}/finish", headers=c.headers, timeout=30
        ).status_code

    with ThreadPoolExecutor(6) as pool:
        codes = list(pool.map(finish, c.urls * 3))
    assert sorted(codes) == [200] + [409] * 5, codes
    assert post(c, c.urls[0], run_id, 1).status_code == 409  # ended: no more readings
    assert post(c, c.urls[1], run_id, 0).json()["duplicate"] is True


def test_kill_9_of_a_worker_while_clients_post_to_all_loses_nothing(two_workers: Cluster) -> None:
    """Each client posts to its worker and, on a failure, retries the same seq on the next
    worker (a load balancer's failover); worker 2 is killed mid-way, then restarted."""
    c = two_workers
    batches = 40
    runs = [open_run(c, c.urls[0]) for _ in c.urls]
    acked: dict[str, list[int]] = {run_id: [] for run_id in runs}
    killed = threading.Event()

    def client(k: int) -> None:
        run_id = runs[k]
        for seq in range(batches):
            target = k
            while True:
                try:
                    r = post(c, c.urls[target], run_id, seq)
                except httpx.TransportError:
                    target = (target + 1) % len(c.urls)
                    continue
                if r.status_code in (200, 201):
                    acked[run_id].append(seq)
                    break
                assert r.status_code == 503, r.text  # not yet: retry
                time.sleep(0.1)
            if seq == batches // 3 and k == 1:
                killed.wait(10)

    threads = [threading.Thread(target=client, args=(k,)) for k in range(len(c.urls))]
    for t in threads:
        t.start()
    time.sleep(0.3)
    os.killpg(c.pid(2), signal.SIGKILL)
    killed.set()
    for t in threads:
        t.join(timeout=120)
    assert not any(t.is_alive() for t in threads)
    cluster.stop_worker(c.directory / "worker-2.pid")  # collects the killed process
    c.urls[1] = cluster.start_worker(c.directory, 2, c.postgres.url)
    expected = [float(t) for t in range(10 * batches)]
    for run_id in runs:
        assert acked[run_id] == list(range(batches))
        for url in c.urls:
            assert stored_times(c, url, run_id) == expected  # each batch exactly once
            run = httpx.get(f"{url}{API}/runs/{run_id}", headers=c.headers).json()
            assert run["batches"] == batches


def test_postgres_restarted_posts_answer_503_meanwhile_nothing_lost(two_workers: Cluster) -> None:
    c = two_workers
    run_id = open_run(c, c.urls[0])
    assert post(c, c.urls[0], run_id, 0).status_code == 201
    pg = c.postgres
    pg.stop("immediate")  # as a crash: nothing flushed beyond what committed
    try:
        for url in c.urls:
            down = post(c, url, run_id, 1)
            assert down.status_code == 503, down.text
            assert down.headers["content-type"].startswith("application/problem+json")
            assert int(down.headers["Retry-After"]) > 0
    finally:
        pg.start()
    started = time.monotonic()
    while True:  # the workers' pools connect again (a client retries after Retry-After)
        r = post(c, c.urls[1], run_id, 1)
        if r.status_code != 503 or time.monotonic() > started + 30:
            break
        time.sleep(0.2)
    assert r.status_code == 201, r.text
    assert time.monotonic() - started < 15, "the worker took long to reconnect"
    for url in c.urls:
        assert stored_times(c, url, run_id) == [float(t) for t in range(20)]
