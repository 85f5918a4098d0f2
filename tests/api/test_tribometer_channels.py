"""A tribometer's friction record needs ``time`` and μ, or the friction force with the
normal load (issue 26): the other channels may be left out (stored as NaN), a batch with
neither is refused with a 422 that says what it needs, in every store's check too."""

from __future__ import annotations

import pytest
from fastapi.testclient import TestClient

from rigserver.storage._checks import check, prepare
from schemas.channels import check_columns
from schemas.stands import StandKind, default_stands
from tests.api.conftest import WRITER, auth

API = "/api/v1"

GROUP = default_stands()[StandKind.PIN_ON_DISC].group("friction")
NEEDS = (
    "group 'friction' needs time and friction_coefficient or time, friction_force and "
    "normal_load in every batch"
)


def _open(client: TestClient, stand: str = "pin_on_disc") -> str:
    body = {"stand": stand, "operator": "Petrova"}
    r = client.post(f"{API}/runs", json=body, headers=auth(WRITER))
    assert r.status_code == 201, r.text
    return str(r.json()["id"])


@pytest.mark.parametrize(
    "columns",
    [
        {"time": [0.0, 0.1], "friction_coefficient": [0.61, 0.6]},
        {"time": [0.0, 0.1], "friction_force": [3.0, 3.1], "normal_load": [5.0, 5.0]},
        {"time": [0.0], "friction_coefficient": [0.6], "laps": [0.0], "temperature": [23.0]},
    ],
)
def test_either_set_is_enough(columns: dict[str, list[float]]) -> None:
    assert check_columns(GROUP, columns) == []
    assert check(StandKind.PIN_ON_DISC, prepare("friction", columns)) is GROUP


@pytest.mark.parametrize(
    "columns",
    [
        {"time": [0.0], "friction_force": [3.0]},  # the force without the load
        {"friction_coefficient": [0.6]},  # no time
        {"time": [0.0], "distance": [0.0], "laps": [0.0]},
    ],
)
def test_a_batch_with_neither_set_is_refused(columns: dict[str, list[float]]) -> None:
    assert [v.message for v in check_columns(GROUP, columns)] == [NEEDS]
    with pytest.raises(ValueError, match="needs time and friction_coefficient"):
        check(StandKind.PIN_ON_DISC, prepare("friction", columns))


def test_the_service_stores_what_came_and_refuses_what_does_not(client: TestClient) -> None:
    run_id = _open(client, "reciprocating")
    url = f"{API}/runs/{run_id}/readings"
    good = {"time": [0.0, 0.1], "friction_coefficient": [0.61, -0.6], "position": [-5.0, 5.0]}
    r = client.post(
        url, json={"seq": 0, "group": "friction", "columns": good}, headers=auth(WRITER)
    )
    assert r.status_code == 201, r.text
    bad = {"time": [0.2], "friction_force": [3.0]}
    r = client.post(url, json={"seq": 1, "group": "friction", "columns": bad}, headers=auth(WRITER))
    assert r.status_code == 422
    assert r.json()["detail"].startswith(NEEDS)
    assert r.json()["errors"][0]["field"] == "columns"
    stored = client.get(url, params={"group": "friction"}, headers=auth(WRITER)).json()
    columns = stored["friction"]["columns"]
    assert columns["friction_coefficient"] == [0.61, -0.6]
    assert columns["friction_force"] == [None, None]  # not posted: NaN, null in JSON
