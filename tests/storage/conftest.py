"""Stores under test and the runs and readings the tests post to them."""

from __future__ import annotations

from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray

from rigserver.storage import HDF5Store, MemoryStore, RunStore
from rigserver.storage.cluster.postgres import PostgresStore
from schemas.runs import Run, new_run_id
from schemas.stands import StandKind
from tests.hsds import hsds_service  # noqa: F401 (fixture)
from tests.postgres import postgres_server, postgres_url  # noqa: F401 (fixtures)

T0 = datetime(2024, 3, 1, 9, 0, tzinfo=UTC)


def make_run(
    stand: StandKind = StandKind.SMTS2,
    operator: str = "Ivanova",
    created: datetime = T0,
    **fields: object,
) -> Run:
    return Run.model_validate(
        {
            "id": new_run_id(created),
            "stand": stand,
            "operator": operator,
            "created": created,
            "configuration": {"disc_radius": 0.0225},
            **fields,
        }
    )


def friction(start: int, n: int) -> dict[str, NDArray[np.float64]]:
    """Rows ``start .. start+n-1`` of an SMTs-2 record; row k is a function of k alone."""
    k = np.arange(start, start + n, dtype=np.float64)
    return {
        "time": 0.5 * k,
        "load": 300.0 + k % 3,
        "speed": np.full(n, 1000.0),
        "friction_moment": 3.0 + k / 1000.0,
        "revolutions": k // 10,
    }


def open_store(deployment: str, tmp_path: Path, request: pytest.FixtureRequest) -> RunStore:
    """A store of the deployment: "memory", "hdf5" (embedded), "hdf5-backlog" (embedded,
    every batch written to its run file after its acknowledgement) or "postgres"
    (cluster)."""
    if deployment == "memory":
        return MemoryStore()
    if deployment == "hdf5":
        return HDF5Store(tmp_path / "data")
    if deployment == "hdf5-backlog":
        return HDF5Store(tmp_path / "data", backlog_rows=1)
    url = request.getfixturevalue("postgres_url")
    return PostgresStore(url, files_dir=tmp_path / "files")


@pytest.fixture(params=["memory", "hdf5", "hdf5-backlog", "postgres"])
def store(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[RunStore]:
    s = open_store(request.param, tmp_path, request)
    yield s
    s.close()
