"""An .eln archive carries a run's corrections: exported with the values as typed and the
table of corrections in the run file, imported with both, the results the same."""

from __future__ import annotations

import io
import zipfile
from typing import Any

import h5py
from fastapi.testclient import TestClient

from rigsim.simulators import simulate
from schemas.stands import StandKind
from tests.api.conftest import READER, WRITER, auth
from tests.eln.conftest import Lab, export, import_archive, members
from tests.reports.simulated import post

API = "/api/v1"


def _get(client: TestClient, path: str) -> Any:
    answer = client.get(f"{API}{path}", headers=auth(READER))
    assert answer.status_code == 200, answer.text
    return answer.json()


def test_the_corrections_travel_with_the_archive(lab: Lab) -> None:
    source, target = lab.source, lab.target
    run_id = post(source, simulate(StandKind.MTOS, seed=36), WRITER)
    typed = _get(source, f"/runs/{run_id}/readings?group=steps")["steps"]["columns"]
    fix = {"values": {"indicator": typed["indicator"][1] * 1.5}, "reason": "misread"}
    answer = source.patch(f"{API}/runs/{run_id}/readings/steps/1", json=fix, headers=auth(WRITER))
    assert answer.status_code == 200, answer.text
    answer = source.request(
        "DELETE",
        f"{API}/runs/{run_id}/readings/steps/3",
        json={"reason": "typed twice"},
        headers=auth(WRITER),
    )
    assert answer.status_code == 200, answer.text
    archive = export(source, f"{API}/runs/{run_id}/export.eln")
    # the archive's CSV of the steps has the corrected values, the row struck out left out
    (csv,) = [v for k, v in members(archive).items() if k.endswith("/steps.csv")]
    lines = csv.decode().splitlines()
    assert len(lines) == 1 + len(typed["indicator"]) - 1
    answer = import_archive(target, archive)
    assert answer.status_code == 201, answer.text
    imported = answer.json()
    assert imported["corrections"] == 2
    theirs = _get(source, f"/runs/{run_id}/corrections")["corrections"]
    ours = _get(target, f"/runs/{imported['id']}/corrections")["corrections"]
    assert ours == theirs
    for query in ("", "&original=true"):
        path = f"/readings?group=steps{query}"
        assert _get(target, f"/runs/{imported['id']}{path}") == _get(
            source, f"/runs/{run_id}{path}"
        )
    assert (
        _get(target, f"/runs/{imported['id']}/results")["values"]
        == _get(source, f"/runs/{run_id}/results")["values"]
    )
    # and the imported run's own archive holds the same table
    again = export(target, f"{API}/runs/{imported['id']}/export.eln")
    (h5,) = [v for k, v in members(again).items() if k.endswith(".h5")]
    with h5py.File(io.BytesIO(h5), "r") as f:
        assert list(f["entry/corrections/reason"].asstr()[()]) == ["misread", "typed twice"]
    assert zipfile.is_zipfile(io.BytesIO(again))
