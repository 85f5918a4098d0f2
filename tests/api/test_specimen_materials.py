"""Materials as data (issue 37, item 5): a tribometer run's specimen names its materials and
the theory takes their properties from the materials table; a material the table does not
hold borrows none (the results ask for its properties); a configuration that gives them
wins."""

from __future__ import annotations

import math
from typing import Any

import pytest
from fastapi.testclient import TestClient

from rigserver.analysis.specimens import TRIBOMETER
from rigserver.core.tribometer import effective_modulus, hertz_ball_on_flat
from schemas.materials import MATERIALS, material_named, properties
from schemas.stands import SpecimenMaterial
from tests.api.conftest import READER, WRITER, auth

#: A short record: 3 N, μ = 0.4, no distance (the planned speed's).
ROWS = 40


def _results(client: TestClient, **body: Any) -> dict[str, Any]:
    headers = auth(WRITER)
    opened = client.post(
        "/api/v1/runs",
        json={"stand": "pin_on_disc", "operator": "Orlova", **body},
        headers=headers,
    )
    assert opened.status_code == 201, opened.text
    run_id = opened.json()["id"]
    columns = {
        "time": [float(i) for i in range(ROWS)],
        "friction_coefficient": [0.4] * ROWS,
        "normal_load": [3.0] * ROWS,
    }
    batch = {"seq": 0, "group": "friction", "columns": columns}
    assert client.post(f"/api/v1/runs/{run_id}/readings", json=batch, headers=headers).is_success
    assert client.post(f"/api/v1/runs/{run_id}/finish", headers=headers).is_success
    answer = client.get(f"/api/v1/runs/{run_id}/results", headers=auth(READER))
    assert answer.status_code == 200, answer.text
    values: dict[str, Any] = answer.json()["values"]
    return values


def _p0(ball: str, disc: str) -> float:
    # Johnson (4.22)-(4.23) of the table's properties, a 6 mm ball under 3 N
    b, d = MATERIALS[ball], MATERIALS[disc]
    modulus = effective_modulus(
        youngs_1=b.youngs_modulus,
        poisson_1=b.poisson,
        youngs_2=d.youngs_modulus,
        poisson_2=d.poisson,
    )
    return hertz_ball_on_flat(load=3.0, ball_radius=3e-3, modulus=modulus).max_pressure


def test_the_named_materials_properties_are_used(client: TestClient) -> None:
    v = _results(client, specimen={"ball": "Si3N4", "disc": "brass"})
    assert v["hertz"]["max_pressure"] == pytest.approx(_p0("Si3N4", "CuZn40Pb2"), rel=1e-12)
    # not the stand's default pair (Al2O3 on 100Cr6)
    assert not math.isclose(v["hertz"]["max_pressure"], _p0("Al2O3", "100Cr6"), rel_tol=1e-3)
    assert TRIBOMETER.pending not in v["pending"]


def test_an_unknown_material_asks_for_its_properties(client: TestClient) -> None:
    v = _results(client, specimen={"ball": "Si3N4", "disc": "unobtainium 7"})
    assert v["hertz"] is None
    assert TRIBOMETER.pending in v["pending"]


def test_the_configuration_wins_over_the_table(client: TestClient) -> None:
    steel = properties("100Cr6", SpecimenMaterial)
    assert steel is not None
    given = {"disc": steel.model_dump()}
    v = _results(client, specimen={"ball": "Si3N4", "disc": "brass"}, configuration=given)
    assert v["hertz"]["max_pressure"] == pytest.approx(_p0("Si3N4", "100Cr6"), rel=1e-12)


@pytest.mark.parametrize(
    ("name", "found"),
    [
        ("ШХ15", "100Cr6"),
        ("  aisi   52100 ", "100Cr6"),
        ("Латунь", "CuZn40Pb2"),
        ("Л63", "CuZn37"),
        ("al2o3", "Al2O3"),
        ("ВСт3пс", "St3sp"),
    ],
)
def test_the_table_knows_the_labs_spellings(name: str, found: str) -> None:
    material = material_named(name)
    assert material is not None and material.name == found
