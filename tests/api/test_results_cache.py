"""Results computed once per readings version, shared, bounded (issue 14, item 6)."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from datetime import UTC, datetime
from typing import Any

import pytest
from fastapi.testclient import TestClient
from pydantic import BaseModel

from rigserver.analysis import AnalysisResult
from rigserver.api import run_results
from rigserver.api.problems import ApiProblem
from rigserver.api.results_cache import ResultsCache, readings_version
from schemas.runs import Run
from schemas.stands import StandKind
from tests.api.conftest import READER, WRITER, auth
from tests.api.test_service import API, friction_batch, open_run


class _Values(BaseModel):
    stand: str = "smts2"
    n: int


def _run(run_id: str = "20261122T114026Z-0000abcd", batches: int = 1) -> Run:
    return Run(
        id=run_id,
        stand=StandKind.SMTS2,
        operator="test",
        configuration={},
        created=datetime(2026, 11, 22, tzinfo=UTC),
        batches=batches,
        rows={"friction": 10 * batches},
    )


class _Counting:
    """A computation that counts its calls and, when told to, waits for a gate."""

    def __init__(self, gate: threading.Event | None = None) -> None:
        self.calls = 0
        self.gate = gate
        self.started = threading.Event()
        self._lock = threading.Lock()

    def __call__(self) -> AnalysisResult:
        with self._lock:
            self.calls += 1
            n = self.calls
        self.started.set()
        if self.gate is not None:
            assert self.gate.wait(30)
        return AnalysisResult(values=_Values(n=n), key_results={"n": float(n)})


def _cache(workers: int = 2) -> ResultsCache:
    return ResultsCache(workers=workers, runs=8, retry_after=3)


def test_the_version_changes_with_every_batch() -> None:
    assert readings_version(_run(batches=1)) == readings_version(_run(batches=1))
    assert readings_version(_run(batches=1)) != readings_version(_run(batches=2))


def test_concurrent_requests_for_the_same_results_share_one_computation() -> None:
    cache, gate = _cache(), threading.Event()
    compute = _Counting(gate)
    run = _run()
    with ThreadPoolExecutor(8) as pool:
        futures = [pool.submit(lambda: cache.submit(run, compute).result()) for _ in range(8)]
        assert compute.started.wait(30)
        gate.set()
        payloads = [f.result(30).payload for f in futures]
    assert compute.calls == 1
    assert all(p == payloads[0] for p in payloads)
    cache.close()


def test_results_are_computed_again_only_when_readings_arrived() -> None:
    cache, compute = _cache(), _Counting()
    assert cache.submit(_run(batches=1), compute).result().payload["values"]["n"] == 1
    assert cache.submit(_run(batches=1), compute).result().payload["values"]["n"] == 1
    assert compute.calls == 1
    assert cache.submit(_run(batches=2), compute).result().payload["values"]["n"] == 2
    assert compute.calls == 2
    cache.close()


def test_a_cold_computation_beyond_the_workers_is_answered_503() -> None:
    cache, gate = _cache(workers=1), threading.Event()
    busy = _Counting(gate)
    first = cache.submit(_run("20261122T114026Z-0000aaaa"), busy)
    assert busy.started.wait(30)
    with pytest.raises(ApiProblem) as refused:
        cache.submit(_run("20261122T114026Z-0000bbbb"), _Counting())
    assert refused.value.problem.status == 503
    assert refused.value.headers == {"Retry-After": "3"}
    # the same results as the one under way are not refused: they wait for it
    same = cache.submit(_run("20261122T114026Z-0000aaaa"), _Counting())
    gate.set()
    assert same.result(30) is first.result(30)
    assert cache.submit(_run("20261122T114026Z-0000bbbb"), _Counting()).result(30)
    cache.close()


def test_a_failed_computation_is_not_kept() -> None:
    cache = _cache()

    def fail() -> AnalysisResult:
        raise ValueError("broken store")

    with pytest.raises(ValueError, match="broken store"):
        cache.submit(_run(), fail).result(30)
    compute = _Counting()
    assert cache.submit(_run(), compute).result(30).payload["values"]["n"] == 1
    cache.close()


def test_finish_takes_current_results_and_joins_one_under_way() -> None:
    cache, gate = _cache(), threading.Event()
    compute = _Counting(gate)
    flight = cache.submit(_run(), compute)
    assert compute.started.wait(30)
    with ThreadPoolExecutor(1) as pool:
        finishing = pool.submit(cache.for_finish, _run(), _Counting())
        gate.set()
        assert finishing.result(30) is flight.result(30)
    assert cache.for_finish(_run(), _Counting()) is flight.result()
    assert compute.calls == 1
    cache.close()


# --- over the API ----------------------------------------------------------------------


@pytest.fixture
def analyses(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The run ids of every analysis the service computes."""
    seen: list[str] = []
    real: Callable[..., AnalysisResult] = run_results.analyse

    def counting(run: Run, readings: run_results.StoredReadings, *lookup: Any) -> AnalysisResult:
        seen.append(run.id)
        time.sleep(0.3)  # long enough for concurrent requests to meet
        return real(run, readings, *lookup)

    monkeypatch.setattr(run_results, "analyse", counting)
    return seen


def test_polling_an_open_run_computes_once_per_new_batch(
    client: TestClient, analyses: list[str]
) -> None:
    run_id = open_run(client)
    r = client.post(
        f"{API}/runs/{run_id}/readings", json=friction_batch(0, 0.0), headers=auth(WRITER)
    )
    assert r.status_code == 201, r.text
    for _ in range(5):
        assert client.get(f"{API}/runs/{run_id}/results", headers=auth(READER)).status_code == 200
    assert analyses == [run_id]
    client.post(f"{API}/runs/{run_id}/readings", json=friction_batch(1, 10.0), headers=auth(WRITER))
    client.get(f"{API}/runs/{run_id}/results", headers=auth(READER))
    client.get(f"{API}/runs/{run_id}/results.csv", headers=auth(READER))
    assert analyses == [run_id, run_id]
    # finishing takes the current results: no third computation
    assert client.post(f"{API}/runs/{run_id}/finish", headers=auth(WRITER)).status_code == 200
    assert analyses == [run_id, run_id]


def test_two_concurrent_finishes_compute_once(client: TestClient, analyses: list[str]) -> None:
    run_id = open_run(client)
    r = client.post(
        f"{API}/runs/{run_id}/readings", json=friction_batch(0, 0.0), headers=auth(WRITER)
    )
    assert r.status_code == 201, r.text
    with ThreadPoolExecutor(2) as pool:
        answers = list(
            pool.map(
                lambda _: client.post(f"{API}/runs/{run_id}/finish", headers=auth(WRITER)),
                range(2),
            )
        )
    assert sorted(a.status_code for a in answers) == [200, 409]
    assert analyses == [run_id]
