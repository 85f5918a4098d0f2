"""Overload: the bounded ingest queue answers 503 with Retry-After instead of growing memory,
and lab PCs that honour it deliver everything."""

from __future__ import annotations

import threading
from pathlib import Path

import httpx
import numpy as np
import pytest

from rigserver.api.ingest_queue import IngestQueue
from rigserver.api.problems import ApiProblem
from rigserver.storage import MemoryStore
from rigsim.batches import Batch
from rigsim.client import LabClient, RetryPolicy
from tests.api.conftest import READER, WRITER, auth
from tests.hardening.conftest import API, friction, is_problem, npz_body, open_run, serve

MB = 1 << 20


def memory_mb(pid: int) -> tuple[float, float]:
    """(VmRSS, VmHWM) of a process, MB."""
    found = {}
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        key, _, value = line.partition(":")
        found[key] = value
    return int(found["VmRSS"].split()[0]) / 1024, int(found["VmHWM"].split()[0]) / 1024


def test_admission_is_bounded_in_batches_and_bytes() -> None:
    queue = IngestQueue(
        MemoryStore(), lambda run_id: threading.Lock(), max_batches=3, max_bytes=10, retry_after=7
    )

    def refused(size: int) -> ApiProblem:
        with pytest.raises(ApiProblem) as caught, queue.admit(size):
            pass
        return caught.value

    with queue.admit(4) as first, queue.admit(4) as second:
        first.arrived(4)  # bytes count as they arrive
        second.arrived(4)
        assert queue.admitted == (2, 8)
        problem = refused(4)  # 12 bytes > 10
        assert (problem.problem.status, problem.headers) == (503, {"Retry-After": "7"})
        assert "at most 3 (10 bytes)" in problem.problem.detail
        with queue.admit(2) as third:  # 10 bytes, 3 batches: the limits, not past them
            third.arrived(2)
            refused(0)  # a fourth batch
    assert queue.admitted == (0, 0)
    with queue.admit(50) as alone:  # alone, a body over the byte budget is admitted
        alone.arrived(50)
        refused(1)
    assert queue.admitted == (0, 0)


@pytest.mark.slow
def test_a_burst_of_large_posts_gets_503_and_memory_stays_bounded(tmp_path: Path) -> None:
    """16 clients post 8 MB batches at once to a server that admits 16 MB: the others are
    answered 503 with Retry-After before their bodies are read; what was acknowledged is
    stored; the server's peak memory grows by a fraction of the 128 MB posted at once."""
    server = serve(  # one key posts: its share is the whole queue
        tmp_path,
        "--ingest-queue",
        "4",
        "--ingest-queue-bytes",
        str(16 * MB),
        "--ingest-key-share",
        "1",
    )
    clients, rows, rounds = 16, 200_000, 3  # 5 channels x 8 B x 200 000 rows = 8 MB
    try:
        with httpx.Client(base_url=server.url, timeout=60) as http:
            runs = [open_run(http) for _ in range(clients)]
        bodies = [npz_body(friction(k * rows, rows)) for k in range(rounds)]
        idle, _ = memory_mb(server.proc.pid)  # type: ignore[union-attr]
        answers: list[list[httpx.Response]] = [[] for _ in range(clients)]
        start = threading.Barrier(clients)

        def client(i: int) -> None:
            with httpx.Client(timeout=60) as http:
                start.wait()
                for seq, body in enumerate(bodies):
                    answers[i].append(
                        http.post(
                            f"{server.url}{API}/runs/{runs[i]}/readings",
                            params={"seq": seq, "group": "friction"},
                            content=body,
                            headers={**auth(WRITER), "content-type": "application/x-npz"},
                        )
                    )

        threads = [threading.Thread(target=client, args=(i,)) for i in range(clients)]
        for t in threads:
            t.start()
        for t in threads:
            t.join(120)
        _, peak = memory_mb(server.proc.pid)  # type: ignore[union-attr]
        every = [r for a in answers for r in a]
        assert {r.status_code for r in every} <= {201, 503}
        refused = [r for r in every if r.status_code == 503]
        assert refused, "no post was refused"
        for r in refused:
            assert is_problem(r)
            assert r.headers["retry-after"] == "1"
            assert r.json()["title"] == "Ingest queue full"
        with httpx.Client(base_url=server.url, timeout=60) as http:
            for i, run_id in enumerate(runs):
                stored = http.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()
                acked = [r.json()["group_rows"] for r in answers[i] if r.status_code == 201]
                assert stored["rows"]["friction"] == len(acked) * rows
        # unbounded, 16 bodies of 8 MB at once and their arrays would take ~400 MB
        assert peak - idle < 200, (idle, peak)
    finally:
        server.stop()


@pytest.mark.slow
def test_lab_pcs_honouring_retry_after_deliver_everything(tmp_path: Path) -> None:
    """Eight LabClients post through a queue of two batches: many 503s, no loss."""
    server = serve(tmp_path, "--ingest-queue", "2")
    n, rows = 8, 2000
    try:
        errors: list[BaseException] = []
        retries = [0] * n
        runs: list[str] = [""] * n

        def lab_pc(i: int) -> None:
            policy = RetryPolicy(base_delay=0.05, max_delay=0.5)
            try:
                with LabClient(server.url, WRITER, retry=policy, seed=i) as client:
                    with httpx.Client(base_url=server.url, timeout=30) as http:
                        runs[i] = open_run(http)
                    for seq in range(15):
                        cols = friction(seq * rows, rows)
                        batch = Batch(group="friction", columns=cols, at=0.0)
                        client.post_batch(runs[i], seq, batch, binary=seq % 2 == 0)
                    retries[i] = client.retries
            except BaseException as exc:
                errors.append(exc)

        threads = [threading.Thread(target=lab_pc, args=(i,)) for i in range(n)]
        for t in threads:
            t.start()
        for t in threads:
            t.join(120)
        assert errors == []
        assert sum(retries) > 0, "the queue never filled"
        with httpx.Client(base_url=server.url, timeout=60) as http:
            for run_id in runs:
                data = http.get(
                    f"{API}/runs/{run_id}/readings?group=friction", headers=auth(READER)
                ).json()["friction"]["columns"]
                np.testing.assert_array_equal(data["time"], np.arange(15 * rows))
    finally:
        server.stop()
