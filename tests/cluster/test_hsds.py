"""HSDS behind the cluster: kill -9 of HSDS while clients post loses nothing acknowledged
(PostgreSQL acknowledges), reads that need HSDS answer 503 with Retry-After meanwhile, and
materialisation resumes when it is back: every row is then in HSDS and reads equal."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from typing import cast

import numpy as np
import psycopg
import pytest

from rigserver import cluster
from rigserver.storage.cluster.hsds import HsdsArrays
from rigserver.storage.servers.hsdsserver import LocalHsds, hsds_missing
from tests.cluster.test_cluster import (
    Cluster,
    batch,
    friction_of,
    open_run,
    post,
    running,
    stored_times,
)
from tests.hsds import NO_HSDS

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def with_hsds() -> Iterator[Cluster]:
    why = hsds_missing()
    if why is not None:
        pytest.skip(NO_HSDS.format(why))
    yield from running(hsds_reads=True)


def materialised(c: Cluster, run_id: str) -> int:
    with psycopg.connect(c.postgres.url) as conn:
        row = conn.execute(
            "SELECT rows FROM rig_hsds_marks WHERE run_id = %s AND grp = 'friction'", (run_id,)
        ).fetchone()
    return 0 if row is None else int(row[0])


def wait_materialised(c: Cluster, run_id: str, rows: int, seconds: float = 60.0) -> None:
    deadline = time.monotonic() + seconds
    while materialised(c, run_id) < rows:
        assert time.monotonic() < deadline, f"{rows} rows not materialised in {seconds} s"
        time.sleep(0.1)


def test_hsds_killed_posts_acknowledged_reads_503_then_everything_materialised(
    with_hsds: Cluster,
) -> None:
    c = with_hsds
    hsds = cluster.hsds_of(c.directory)
    assert isinstance(hsds, LocalHsds)
    run_id = open_run(c, c.urls[0])
    for seq in range(10):
        assert post(c, c.urls[seq % 2], run_id, seq).status_code == 201
    wait_materialised(c, run_id, 100)  # ten batches of ten rows
    assert stored_times(c, c.urls[1], run_id) == [float(t) for t in range(100)]

    statuses: list[int] = []

    def client() -> None:  # posts on, through the kill and the restart
        for seq in range(10, 50):
            statuses.append(post(c, c.urls[seq % 2], run_id, seq).status_code)
            time.sleep(0.02)

    poster = threading.Thread(target=client)
    poster.start()
    try:
        time.sleep(0.1)
        hsds.kill()
        down_at = materialised(c, run_id)
        r = friction_of(c, c.urls[0], run_id)
        assert r.status_code == 503, r.text
        assert r.headers["content-type"].startswith("application/problem+json")
        assert int(r.headers["Retry-After"]) >= 0
        time.sleep(1.0)  # nothing is marked materialised while HSDS is down
        assert materialised(c, run_id) == down_at
    finally:
        poster.join(60)
        hsds.restart()
    assert statuses == [201] * 40  # every post acknowledged by PostgreSQL
    # HSDS starts its nodes again on a loaded machine (CI runs -n auto): time for that
    wait_materialised(c, run_id, 500, seconds=180)
    posted = [cast(dict[str, list[float]], batch(s)["columns"]) for s in range(50)]
    expected = {k: np.concatenate([cols[k] for cols in posted]) for k in posted[0]}
    for url in c.urls:
        assert stored_times(c, url, run_id) == list(expected["time"])
    in_hsds = HsdsArrays(hsds.settings).read(run_id, "friction", list(expected), 0, 500)
    for name, values in expected.items():
        np.testing.assert_array_equal(in_hsds[name], values)
