"""Run arrays in HSDS: the materialiser copies the journal into a domain per run, in row
order, marks what HSDS has flushed, and reads take the materialised rows from HSDS."""

from __future__ import annotations

import time
from pathlib import Path
from urllib.parse import quote

import numpy as np
import psycopg
import pytest

from rigserver.storage.cluster.hsds import HsdsArrays
from rigserver.storage.cluster.hsds_settings import HsdsSettings
from rigserver.storage.cluster.postgres import PostgresStore
from rigserver.storage.errors import StorageUnavailable
from rigserver.storage.servers.hsdsserver import LocalHsds
from tests.storage.conftest import friction, make_run

pytestmark = pytest.mark.slow


def unanswered(tmp_path: Path) -> HsdsSettings:
    """An endpoint nobody listens on."""
    socket = quote(str(tmp_path / "none.sock"), safe="")
    return HsdsSettings(
        endpoint=f"http+unix://{socket}", username="rig", password="x", bucket="rig"
    )


def marks(url: str, run_id: str) -> dict[str, tuple[int, int]]:
    with psycopg.connect(url) as conn:
        rows = conn.execute(
            "SELECT grp, rows, batches FROM rig_hsds_marks WHERE run_id = %s", (run_id,)
        ).fetchall()
    return {str(g): (int(r), int(b)) for g, r, b in rows}


def wait_for_marks(url: str, run_id: str, rows: int, seconds: float = 30.0) -> None:
    deadline = time.monotonic() + seconds
    while marks(url, run_id).get("friction", (0, 0))[0] < rows:
        assert time.monotonic() < deadline, f"not materialised in {seconds} s"
        time.sleep(0.1)


def test_batches_reach_hsds_in_order_and_reads_span_both(
    postgres_url: str, hsds_service: LocalHsds, tmp_path: Path
) -> None:
    settings = hsds_service.settings
    with PostgresStore(postgres_url, files_dir=tmp_path, hsds=settings, hsds_reads=True) as store:
        run = store.create_run(make_run())
        for seq in range(5):  # batches of 7 rows: chunk boundaries fall inside batches
            store.append(run.id, seq, "friction", friction(7 * seq, 7))
        wait_for_marks(postgres_url, run.id, 35)
        assert marks(postgres_url, run.id) == {"friction": (35, 5)}
        # the domain holds exactly the journal's rows
        domain = HsdsArrays(hsds_service.settings).read(
            run.id, "friction", list(friction(0, 0)), 0, 35
        )
        expected = friction(0, 35)
        for name, values in expected.items():
            np.testing.assert_array_equal(domain[name], values)
        # stop materialising, append more: a read spans HSDS (rows < 35) and the journal
        assert store._materialiser is not None
        store._materialiser.stop()
        store._materialiser = None
        store.append(run.id, 5, "friction", friction(35, 9))
        got = store.read(run.id, "friction", ["time", "friction_moment"], 30, 40)
        np.testing.assert_array_equal(got["time"], friction(30, 10)["time"])
        np.testing.assert_array_equal(got["friction_moment"], friction(30, 10)["friction_moment"])
        assert marks(postgres_url, run.id) == {"friction": (35, 5)}


def test_a_read_needing_hsds_while_it_is_down_is_unavailable(
    postgres_url: str, tmp_path: Path
) -> None:
    """An endpoint nobody listens on: the journal-only part reads, the rest is 503."""
    nowhere = unanswered(tmp_path)
    with PostgresStore(postgres_url, files_dir=tmp_path, hsds=nowhere, hsds_reads=True) as store:
        run = store.create_run(make_run())
        store.append(run.id, 0, "friction", friction(0, 10))
        np.testing.assert_array_equal(
            store.read(run.id, "friction", ["time"])["time"], friction(0, 10)["time"]
        )
        with psycopg.connect(postgres_url) as conn:  # as if materialised before HSDS went
            conn.execute("INSERT INTO rig_hsds_marks VALUES (%s, 'friction', 10, 1)", (run.id,))
        with pytest.raises(StorageUnavailable, match="HSDS"):
            store.read(run.id, "friction", ["time"])
        assert marks(postgres_url, run.id) == {"friction": (10, 1)}


def test_by_default_reads_come_from_the_journal_whatever_hsds_holds(
    postgres_url: str, tmp_path: Path
) -> None:
    """Without hsds_reads a read never asks HSDS (here: nobody listens), marks or not."""
    nowhere = unanswered(tmp_path)
    with PostgresStore(postgres_url, files_dir=tmp_path, hsds=nowhere) as store:
        run = store.create_run(make_run())
        store.append(run.id, 0, "friction", friction(0, 10))
        with psycopg.connect(postgres_url) as conn:
            conn.execute("INSERT INTO rig_hsds_marks VALUES (%s, 'friction', 10, 1)", (run.id,))
        got = store.read(run.id, "friction", ["time", "load"], 2, 8)
        np.testing.assert_array_equal(got["time"], friction(2, 6)["time"])
        np.testing.assert_array_equal(got["load"], friction(2, 6)["load"])
