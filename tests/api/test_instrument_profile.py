"""A posted profile's settings through the API (issue 37, item 4): the instrument's own
roughness profile, not filtered again, evaluated in its sampling lengths."""

from __future__ import annotations

import math

import pytest
from fastapi.testclient import TestClient

from rigsim.batches import Batch, SimulatedRun
from schemas.runs import RunCreate
from schemas.stands import StandKind
from tests.api.conftest import READER, WRITER, auth
from tests.core.test_iso_instrument import sine
from tests.reports.simulated import post


def test_a_posted_roughness_profile_through_the_api(client: TestClient) -> None:
    # the instrument's R profile of 4 mm (five sampling lengths of 0.8 mm), a sine of 2 µm
    # and 80 µm: Ra = 2A/π, iso.sections = 5, the instrument's λc reported
    x, z = sine(2e-6, 80e-6, 400, 50)
    body = RunCreate(
        stand=StandKind.PROFILOMETER,
        operator="Orlova",
        configuration={"profile_kind": "roughness", "sections": 5, "lambda_c": 0.8e-3},
    )
    columns = {"x": x / 1e-3, "y": z / 1e-6}
    sim: SimulatedRun[None] = SimulatedRun(body, (Batch("profile", columns, 0.0),), None)
    run_id = post(client, sim, WRITER)
    answer = client.get(f"/api/v1/runs/{run_id}/results", headers=auth(READER))
    assert answer.status_code == 200, answer.text
    iso = answer.json()["values"]["iso"]
    assert iso["sections"] == 5
    assert iso["lambda_c"] == pytest.approx(0.8e-3)
    assert iso["ra"] == pytest.approx(4e-6 / math.pi, rel=math.pi**2 / (3 * 400**2) * 1.01)
    assert iso["evaluation_length"] == pytest.approx(4e-3)
    assert "not filtered again" in iso["ends"]
