"""Units that a run's configuration sets (the slide-bearing gauges read in at or atm) are
the units on its data: in the HDF5 file, the JSON and CSV readings and the stand."""

from __future__ import annotations

import io
from collections.abc import Iterator
from pathlib import Path

import h5py
import pytest
from fastapi.testclient import TestClient

from tests.api.conftest import READER, WRITER, auth
from tests.hardening.conftest import API, hdf5_app

ROW = {
    "limb_angle": [30.0],
    **{f"p{k}": [1.5] for k in range(1, 6)},
    "x": [2.0],
    "y": [1.0],
    "t1": [40.0],
    "t2": [45.0],
}


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    with TestClient(hdf5_app(tmp_path / "data"), raise_server_exceptions=False) as c:
        yield c


@pytest.mark.parametrize("gauge_unit", ["at", "atm"])
def test_the_gauges_unit_is_the_runs(client: TestClient, gauge_unit: str) -> None:
    body = {
        "stand": "slide_bearing",
        "operator": "Orlov",
        "configuration": {"gauge_unit": gauge_unit},
    }
    run_id = client.post(f"{API}/runs", json=body, headers=auth(WRITER)).json()["id"]
    batch = {"seq": 0, "group": "rows", "columns": ROW}
    assert (
        client.post(f"{API}/runs/{run_id}/readings", json=batch, headers=auth(WRITER)).status_code
        == 201
    )
    readings = f"{API}/runs/{run_id}/readings?group=rows"
    units = client.get(readings, headers=auth(READER)).json()["rows"]["units"]
    assert units["p1"] == gauge_unit and units["t1"] == "degC"
    csv_head = client.get(readings + "&format=csv", headers=auth(READER)).text.splitlines()[0]
    assert f"p3 [{gauge_unit}]" in csv_head
    data = client.get(f"{API}/runs/{run_id}/readings?format=hdf5", headers=auth(READER)).content
    with h5py.File(io.BytesIO(data)) as f:
        assert f["entry/rows/p5"].attrs["units"] == gauge_unit
    high = {"seq": 1, "group": "rows", "columns": {**ROW, "p2": [150.0]}}  # above 100
    refused = client.post(f"{API}/runs/{run_id}/readings", json=high, headers=auth(WRITER))
    assert refused.status_code == 422
    assert refused.json()["errors"][0]["limit"] == f"-1 <= value <= 100 {gauge_unit}"
