"""The pages' writing forms in process (no browser): ``/runs/new`` generated from the
stand's declaration and refused beside its fields by the API's own checks; the rows, finish
and abort posts of a run page guarded by the session's form token, the Origin and the key's
scope, each refusal one line of the page's language; the API still never takes the cookie."""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient

from rigserver.api.app import create_app
from rigserver.api.auth import ApiKey
from rigserver.api.settings import Settings
from rigserver.reports.i18n import Messages
from rigserver.storage import MemoryStore
from rigserver.web.entry import limit_refusal
from rigserver.web.new_run import parse_number
from schemas.channels import Channel, check_columns
from schemas.stands import StandKind, configure_stands
from tests.api.conftest import KEYS, READER, WRITER, auth

API = "/api/v1"
MTOS_READER = "mtos-reader-writer-000000"
LAB_CLEARANCE = 180e-6
"""The lab's slide-bearing clearance, m (its stands file), shown as the form's default."""


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    keys = [*KEYS, {"key": MTOS_READER, "scopes": ["read", "write:mtos"], "name": "MTOS PC"}]
    stands = configure_stands({"slide_bearing": {"clearance": LAB_CLEARANCE}})
    app = create_app(
        Settings(data_dir=tmp_path),
        MemoryStore(),
        [ApiKey.model_validate(k) for k in keys],
        stands,
    )
    with TestClient(app, raise_server_exceptions=False) as c:
        yield c


def login(client: TestClient, key: str) -> None:
    answer = client.post("/login", data={"key": key, "next": "/"}, follow_redirects=False)
    assert answer.status_code == 303


def token_of(page: str) -> str:
    found = re.search(r'name="form_token" value="([^"]+)"', page)
    assert found, "no form token on the page"
    return found[1]


def field(page: str, name: str) -> str:
    """The markup of the form's field ``name`` (its label, input and refusal)."""
    found = re.search(
        rf'<div class="field[^"]*">\s*<label[^>]*>(?:(?!</div>).)*name="{re.escape(name)}"'
        r"(?:(?!</div>).)*</div>",
        page,
        re.S,
    )
    assert found, f"no field {name}"
    return found[0]


def test_the_new_run_form_is_the_stands_declaration_with_its_passport(
    client: TestClient,
) -> None:
    login(client, WRITER)
    runs = client.get("/").text
    assert 'href="/runs/new?stand=slide_bearing&amp;lang=en"' in runs
    page = client.get("/runs/new?stand=slide_bearing&lang=ru").text
    assert '<form id="new-run"' in page
    for name in ("operator", "students", "title", "specimen.journal", "test_plan.limb_step_deg"):
        assert f'name="{name}"' in page
    # the clearance with its symbol and display unit, the lab's passport value as default
    clearance = field(page, "configuration.clearance")
    assert 'зазор (3.17) <span class="sym">h0</span>, мкм' in clearance
    assert 'value="180"' in clearance
    assert 'value="25,175"' in field(page, "configuration.bearing_radius")  # mm, a comma


def test_a_session_of_another_stands_key_gets_no_form(client: TestClient) -> None:
    login(client, READER)
    assert "/runs/new" not in client.get("/").text
    assert client.get("/runs/new?stand=mtos").status_code == 403
    login(client, MTOS_READER)
    links = re.findall(r'href="/runs/new\?stand=(\w+)', client.get("/").text)
    assert links == ["mtos"]
    refused = client.get("/runs/new?stand=smts2&lang=ru")
    assert refused.status_code == 403 and '<form id="new-run"' not in refused.text
    assert "У этого ключа нет права write:smts2" in refused.text


def test_a_new_run_is_refused_beside_its_field_and_opened_once(client: TestClient) -> None:
    login(client, WRITER)
    page = client.get("/runs/new?stand=slide_bearing").text
    form = {"form_token": token_of(page), "idempotency_key": "abc123", "operator": ""}
    url = "/runs/new?stand=slide_bearing&lang=en"

    empty = client.post(url, data=form)
    assert empty.status_code == 422
    assert 'aria-invalid="true"' in field(empty.text, "operator")
    assert "to be filled in" in field(empty.text, "operator")

    form |= {"operator": "Ivanova", "test_plan.limb_step_deg": "ten"}
    word = client.post(url, data=form)
    assert word.status_code == 422
    assert "“ten” is not a number" in field(word.text, "test_plan.limb_step_deg")

    # the stand's own schema refuses a clearance below zero, as POST /api/v1/runs does
    form |= {"test_plan.limb_step_deg": "10", "configuration.clearance": "-5"}
    bad = client.post(url, data=form)
    assert bad.status_code == 422
    refusal = field(bad.text, "configuration.clearance")
    assert 'aria-invalid="true"' in refusal and "greater than 0" in refusal
    assert 'value="-5"' in refusal  # as typed, to correct
    assert client.get(f"{API}/runs", headers=auth(READER)).json()["total"] == 0

    form |= {"configuration.clearance": "190,5", "students": "A. Ivanova\nB. Petrov"}
    opened = client.post(url, data=form, follow_redirects=False)
    assert opened.status_code == 303
    run_id = opened.headers["location"].split("/")[2].split("?")[0]
    again = client.post(url, data=form, follow_redirects=False)  # sent twice: one run
    assert again.headers["location"] == opened.headers["location"]
    run = client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()
    assert run["operator"] == "Ivanova" and run["test_plan"] == {"limb_step_deg": 10.0}
    assert run["configuration"]["clearance"] == pytest.approx(190.5e-6, rel=1e-12)
    # the passport values sent back unchanged are no overrides: the lab's value stays
    assert run["configuration"]["bearing_radius"] == 25.175e-3
    notes = client.get(f"{API}/runs/{run_id}/notes", headers=auth(READER)).json()
    assert notes["students"] == ["A. Ivanova", "B. Petrov"]


def open_run(client: TestClient, stand: str) -> str:
    made = client.post(
        f"{API}/runs", json={"stand": stand, "operator": "Ivanova"}, headers=auth(WRITER)
    )
    assert made.status_code == 201
    return str(made.json()["id"])


MASSES = {"seq": 7, "group": "measurements", "columns": {"pin_mass_before": [12.3456]}}


def test_a_typed_row_needs_the_sessions_token_and_scope(client: TestClient) -> None:
    run_id = open_run(client, "smts2")
    rows = f"/runs/{run_id}/rows?lang=ru"
    assert client.post(rows, json=MASSES).status_code == 401  # no session
    login(client, MTOS_READER)
    page = client.get(f"/runs/{run_id}").text
    assert "entry-measurements" not in page  # no form for a stand it may not write
    token = token_of(client.get("/runs/new?stand=mtos").text)
    refused = client.post(rows, json=MASSES, headers={"X-Rig-Form": token})
    assert refused.status_code == 403
    assert refused.json()["message"] == (
        "У этого ключа нет права write:smts2: он не может записывать прогоны этого стенда."
    )

    login(client, WRITER)
    page = client.get(f"/runs/{run_id}").text
    assert '<form id="entry-measurements"' in page and 'name="pin_mass_before"' in page
    token = token_of(page)
    forged = client.post(rows, json=MASSES, headers={"X-Rig-Form": "x" * 43})
    assert forged.status_code == 403
    assert (
        forged.json()["message"] == "Форма не принадлежит сеансу этой страницы: обновите страницу."
    )
    elsewhere = client.post(
        rows, json=MASSES, headers={"X-Rig-Form": token, "Origin": "https://evil.example"}
    )
    assert elsewhere.status_code == 403
    # the API never takes the session's cookie, whatever the page's token
    api = client.post(f"{API}/runs/{run_id}/readings", json=MASSES, headers={"X-Rig-Form": token})
    assert api.status_code == 401
    assert client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()["batches"] == 0

    stored = client.post(rows, json=MASSES, headers={"X-Rig-Form": token})
    assert stored.status_code == 201 and stored.json()["duplicate"] is False
    again = client.post(rows, json=MASSES, headers={"X-Rig-Form": token})  # a retry
    assert again.status_code == 200 and again.json()["duplicate"] is True
    beyond = {"seq": 8, "group": "measurements", "columns": {"pin_mass_after": [1500.0]}}
    limit = client.post(f"/runs/{run_id}/rows?lang=en", json=beyond, headers={"X-Rig-Form": token})
    assert limit.status_code == 422
    # worded as the page words the cell as it is typed (entry.js), in the page's language
    assert limit.json()["message"] == "Refused: m₂ = 1500 g is above the limit 1000 g"
    russian = client.post(rows, json=beyond, headers={"X-Rig-Form": token})
    assert russian.json()["message"] == "Отклонено: m₂ = 1500 г выше предела 1000 г"
    assert client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()["batches"] == 1

    # finish: a form of the page with the token; then the run takes no more rows
    finish = f"/runs/{run_id}/finish?lang=ru"
    assert client.post(finish, data={}, follow_redirects=False).status_code == 403
    done = client.post(finish, data={"form_token": token}, follow_redirects=False)
    assert done.status_code == 303 and done.headers["location"] == f"/runs/{run_id}?lang=ru"
    assert client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()["state"] == "finished"
    # its page keeps the rows received, to be corrected, but takes no new row
    finished = client.get(f"/runs/{run_id}").text
    assert '<form id="entry-measurements"' in finished and "<tfoot hidden>" in finished
    assert 'id="finish"' not in finished and "The run is finished" in finished
    late = client.post(rows, json={**MASSES, "seq": 9}, headers={"X-Rig-Form": token})
    assert late.status_code == 409
    assert late.json()["message"] == "Прогон уже закрыт: новых строк он не принимает."


@pytest.mark.parametrize(
    ("typed", "number"),
    [
        ("1,5", 1.5),  # a decimal comma
        (" -2,0 ", -2.0),
        ("\u22123", -3.0),  # the minus sign a Russian keyboard layout may give
        ("1e-5", 1e-5),
        ("1,2,3", None),
        ("inf", None),
        ("nan", None),
        ("1e400", None),  # beyond a double: refused, as the API refuses it
        ("", None),
    ],
)
def test_a_number_as_typed(typed: str, number: float | None) -> None:
    assert parse_number(typed) == number


@pytest.mark.parametrize(
    ("stand", "group", "columns", "line"),
    [
        ("slide_bearing", "rows", {"p3": [-1.5]}, "p₃ = -1,5 атм ниже предела -1 атм"),
        (
            "smts2",
            "friction",
            {"speed": [400.0]},
            "n = 400 об/мин: ожидается одно из 300, 500, 1000 об/мин",
        ),
        (
            "pin_on_disc",
            "wear_track",
            {"trace": [2.5]},
            "номер трассы (по одной на место вдоль дорожки) = 2,5: ожидается целое число",
        ),
        ("profilometer", "profile", {"x": [2.0, 1.0]}, None),  # an order: the API's words
    ],
)
def test_a_refused_reading_in_the_words_of_the_page(
    stand: str, group: str, columns: dict[str, list[float]], line: str | None
) -> None:
    declared = configure_stands()[StandKind(stand)]
    decl = declared.group(group)
    assert decl is not None
    rows = len(next(iter(columns.values())))

    def holding(c: Channel) -> float:  # a value within the channel's limit
        return c.limit.nominal[0] if c.limit.nominal else max(c.limit.low or 0.0, 1.0)

    full = {c.name: columns.get(c.name, [holding(c)] * rows) for c in decl.channels}
    violations = check_columns(decl, {k: np.asarray(v) for k, v in full.items()}, {})
    assert violations, "the API refuses these readings"
    assert limit_refusal(Messages("ru"), declared, violations[0]) == line
