"""Values that cannot be stored or shown, numbers and dates that break parsers, and lax
coercion: refused at the door with a 422 naming the field, never a 500, nothing stored
(issue 14, items 1, 3 and 8)."""

from __future__ import annotations

import json
import math
import sqlite3
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from rigserver.api.problems import renderable
from schemas.readings import NPZ_MEDIA_TYPE
from tests.api.conftest import READER, WRITER, auth
from tests.hardening.conftest import API, friction, is_problem, npz_body, open_run

JSON = {**auth(WRITER), "content-type": "application/json"}

# --- item 1: a new run with a value that cannot be stored or shown ----------------------

_OPEN = '{{"stand": "{stand}", "operator": "Ivanova", {extra}}}'
_UNSTORABLE_RUNS = [
    # (stand, the rest of the body as raw JSON, the field named)
    ("smts2", '"specimen": {"pin": NaN}', "specimen.pin"),
    ("smts2", '"specimen": {"pin": Infinity}', "specimen.pin"),
    ("smts2", '"specimen": {"pin": -Infinity}', "specimen.pin"),
    ("smts2", '"specimen": {"pin": 1e400}', "specimen.pin"),  # overflows a double
    ("smts2", '"specimen": {"pin": 9223372036854775808}', "specimen.pin"),  # 2^63
    ("smts2", '"test_plan": {"load_N": NaN}', "test_plan.load_N"),
    ("mtos", '"test_plan": {"steps": [100, Infinity]}', "test_plan.steps"),
    ("mtos", '"test_plan": {"steps": [100, -1e999]}', "test_plan.steps"),
    ("smts2", '"configuration": {"disc_radius": NaN}', "configuration.disc_radius"),
    ("smts2", '"configuration": {"disc_radius": 1e400}', "configuration.disc_radius"),
    ("smts2", '"configuration": {"pin": {"hardness": Infinity}}', "configuration.pin.hardness"),
    ("mtos", '"configuration": {"viscosity": {"alpha": NaN}}', "configuration.viscosity.alpha"),
    (
        "slide_bearing",
        '"configuration": {"manometer_z": [-0.4, -0.2, 0, NaN, 0.4]}',
        "configuration.manometer_z.3",
    ),
    ("smts2", '"title": "a\\u0000b"', "title"),
    ("smts2", '"title": "\\ud800"', "title"),
    ("smts2", '"notes": "\\udc00 lone"', "notes"),
    ("smts2", '"specimen": {"pin": "St3\\u0000"}', "specimen.pin"),
    ("smts2", '"specimen": {"a\\u0000": 1}', "specimen."),
    ("smts2", '"test_plan": {"\\ud83d": 1}', "test_plan."),
    ("smts2", '"configuration": {"pin": {"name": "St\\u0000"}}', "configuration.pin.name"),
    ("smts2", '"configuration": {"a\\u0000": 1}', "configuration."),
]


def _stored_runs(data: Path) -> int:
    with sqlite3.connect(data / "journal.sqlite") as db:
        return int(db.execute("SELECT COUNT(*) FROM runs").fetchone()[0])


@pytest.mark.parametrize(("stand", "extra", "field"), _UNSTORABLE_RUNS)
def test_unstorable_values_of_a_new_run_are_refused_naming_the_field(
    hdf5_client: TestClient, tmp_path: Path, stand: str, extra: str, field: str
) -> None:
    body = _OPEN.format(stand=stand, extra=extra).encode()
    r = hdf5_client.post(f"{API}/runs", content=body, headers=JSON)
    assert r.status_code == 422, r.text
    assert is_problem(r)
    assert r.json()["errors"][0]["field"].startswith(field), r.json()
    assert _stored_runs(tmp_path / "data") == 0
    assert not list((tmp_path / "data" / "runs").iterdir())
    assert hdf5_client.get(f"{API}/runs", headers=auth(READER)).json()["total"] == 0


@pytest.mark.parametrize(
    ("value", "field"),
    [
        (b"key\x00", "idempotency-key"),
        (b"caf\xc3\xa9", "idempotency-key"),  # not ASCII
        (b"two words", "idempotency-key"),
    ],
)
def test_unstorable_idempotency_keys_are_refused(
    hdf5_client: TestClient, tmp_path: Path, value: bytes, field: str
) -> None:
    body = b'{"stand": "smts2", "operator": "x"}'
    r = hdf5_client.post(f"{API}/runs", content=body, headers={**JSON, "Idempotency-Key": value})  # type: ignore[dict-item]
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["field"].endswith(field)
    assert _stored_runs(tmp_path / "data") == 0


# --- item 3: parsing never ends in a 500 -------------------------------------------------

_ARABIC_12 = "%D9%A1%D9%A2"  # ١٢, Arabic-Indic digits
_FULLWIDTH_1 = "%EF%BC%91"  # １
_SUPERSCRIPT_2 = "%C2%B2"  # ², which str.isdigit() takes and int() refuses
_LONG = "9" * 5000  # beyond sys.get_int_max_str_digits()

_QUERIES = [
    "/api/v1/runs?since=0001-01-01T00:00:00%2B01:00",
    "/api/v1/runs?until=9999-12-31T23:59:59-01:00",
    "/api/v1/runs?since=%D9%A2%D9%A0%D9%A2%D9%A6-01-01T00:00:00Z",
    f"/api/v1/runs?limit={_ARABIC_12}",
    f"/api/v1/runs?limit={_FULLWIDTH_1}",
    f"/api/v1/runs?offset={_LONG}",
    "/api/v1/runs?operator=%00",
    "/?since=0001-01-01",
    "/?until=9999-12-31",
    f"/?since=%D9%A1%D9%A2%D9%A3%D9%A4-01-01&until={_FULLWIDTH_1}999-01-01",
    f"/?offset={_LONG}",
    f"/?offset={_SUPERSCRIPT_2}",
    "/?operator=%00",
    "/login?next=%00",
    "/api/v1/runs/{run}/readings?start=" + _ARABIC_12,
    "/api/v1/runs/{run}/readings?stop=" + _LONG,
    "/api/v1/runs/{run}/readings?group=%00",
    "/api/v1/runs/{run}/live?from=" + _SUPERSCRIPT_2,
]


@pytest.mark.parametrize("query", _QUERIES)
def test_hostile_query_parameters_are_answered_without_a_500(
    hdf5_client: TestClient, query: str
) -> None:
    run_id = open_run(hdf5_client)
    r = hdf5_client.get(query.format(run=run_id), headers=auth(READER))
    assert r.status_code < 500, r.text
    if r.status_code >= 400:
        assert is_problem(r)


@pytest.mark.parametrize("last_event_id", ["²".encode(), "١".encode(), b"1" * 5000, b"-1"])
def test_hostile_last_event_ids_are_422(hdf5_client: TestClient, last_event_id: bytes) -> None:
    run_id = open_run(hdf5_client)
    headers = {**auth(READER), "Last-Event-ID": last_event_id}
    r = hdf5_client.get(f"{API}/runs/{run_id}/live", headers=headers)  # type: ignore[arg-type]
    assert r.status_code == 422, r.text
    assert is_problem(r)


@pytest.mark.parametrize("seq", [_SUPERSCRIPT_2, _ARABIC_12, _FULLWIDTH_1, _LONG, "1e3", "+1"])
def test_binary_batches_with_a_hostile_seq_are_422(hdf5_client: TestClient, seq: str) -> None:
    run_id = open_run(hdf5_client)
    r = hdf5_client.post(
        f"{API}/runs/{run_id}/readings?seq={seq}&group=friction",
        content=npz_body(friction(0, 3)),
        headers={**auth(WRITER), "content-type": NPZ_MEDIA_TYPE},
    )
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["field"] == "seq"
    assert _rows(hdf5_client, run_id) == 0


# --- item 3: an error that echoes a hostile input still renders --------------------------


@pytest.mark.parametrize(
    ("path", "body"),
    [
        (f"{API}/models/wear/theoretical", b'{"load": NaN}'),
        (f"{API}/models/wear/theoretical", b'{"load": -Infinity}'),
        (f"{API}/models/bearing/friction", b'{"chi": 1e400}'),
        (f"{API}/models/bearing/friction", b'{"chi": ' + b"9" * 400 + b"}"),
        (f"{API}/runs", b'{"stand": "smts2", "operator": "\\ud800"}'),
        (f"{API}/runs", b'{"stand": "\\udfff", "operator": "x"}'),
        (f"{API}/runs", b'{"stand": "smts2", "operator": "x", "\\ud800": 1}'),
        (f"{API}/runs", b'{"stand": "smts2", "operator": "x", "configuration": {"\\ud800": 1}}'),
        (
            f"{API}/runs/{{run}}/readings",
            b'{"seq": 0, "group": "friction", "columns": {"\\ud800": [1]}}',
        ),
    ],
)
def test_problems_echoing_non_finite_numbers_or_lone_surrogates_render(
    hdf5_client: TestClient, path: str, body: bytes
) -> None:
    run_id = open_run(hdf5_client)
    r = hdf5_client.post(path.format(run=run_id), content=body, headers=JSON)
    assert r.status_code == 422, r.text
    assert is_problem(r)
    json.loads(r.content.decode("utf-8"))  # valid UTF-8, valid JSON


def test_renderable_leaves_nothing_json_cannot_hold() -> None:
    hostile = {"a\ud800": [math.nan, -math.inf, "\udfff", {"k": math.inf}], "n": 10**400}
    text = json.dumps(renderable(hostile), allow_nan=False, ensure_ascii=False)
    assert json.loads(text.encode("utf-8")) == {
        "a\ufffd": ["nan", "-inf", "\ufffd", {"k": "inf"}],
        "n": 10**400,
    }


# --- item 8: the wire is strict ------------------------------------------------------------


def _rows(client: TestClient, run_id: str) -> int:
    run = client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()
    return sum(run["rows"].values())


_ONE = '"time": [0], "load": [300], "speed": [1000], "friction_moment": [2.5]'


def _batch(seq: str, revolutions: str, more: str = "") -> str:
    """A one-row friction batch with ``seq`` and ``revolutions`` as given (raw JSON)."""
    return f'{{"seq": {seq},{more} "columns": {{{_ONE}, "revolutions": {revolutions}}}}}'


_LAX_BATCHES = [
    # (raw body, the field named)
    (_batch('"1"', "[0]", ' "group": "friction",'), "seq"),
    (_batch("true", "[0]", ' "group": "friction",'), "seq"),
    (_batch("1.0", "[0]", ' "group": "friction",'), "seq"),
    (_batch("1", '["0"]', ' "group": "friction",'), "columns.revolutions.0"),
    (_batch("1", '["1.5"]', ' "group": "friction",'), "columns.revolutions.0"),
    (_batch("1", "[false]", ' "group": "friction",'), "columns.revolutions.0"),
    (_batch("1", "[0]", ' "seq": 2, "group": "friction",'), "seq"),
    (_batch("1", '[0], "load": [301]', ' "group": "friction",'), "columns.load"),
    (_batch("1", "[0]", ' "group": "friction", "group": "friction",'), "group"),
]


@pytest.mark.parametrize(("body", "field"), _LAX_BATCHES)
def test_lax_or_duplicated_values_in_a_batch_are_refused(
    hdf5_client: TestClient, body: str, field: str
) -> None:
    run_id = open_run(hdf5_client)
    r = hdf5_client.post(f"{API}/runs/{run_id}/readings", content=body.encode(), headers=JSON)
    assert r.status_code == 422, r.text
    assert is_problem(r)
    assert r.json()["errors"][0]["field"] == field, r.json()
    assert _rows(hdf5_client, run_id) == 0


@pytest.mark.parametrize(
    ("path", "body", "field"),
    [
        (f"{API}/runs", '{"stand": "smts2", "operator": "a", "operator": "b"}', "operator"),
        (
            f"{API}/runs",
            '{"stand": "smts2", "operator": "a", "specimen": {"pin": "x", "pin": "y"}}',
            "specimen.pin",
        ),
        (
            f"{API}/runs",
            '{"stand": "smts2", "operator": "a", '
            '"configuration": {"pin": {"name": "x", "name": "y"}}}',
            "configuration.pin.name",
        ),
        (f"{API}/models/wear/theoretical", '{"load": 300, "load": 200}', "load"),
        (
            f"{API}/runs",
            '{"stand": "smts2", "operator": "a", "specimen": {"n": ' + _LONG + "}}",
            "body",
        ),
    ],
)
def test_duplicate_keys_in_json_bodies_are_refused(
    hdf5_client: TestClient, tmp_path: Path, path: str, body: str, field: str
) -> None:
    r = hdf5_client.post(path, content=body.encode(), headers=JSON)
    assert r.status_code == 422, r.text
    assert is_problem(r)
    assert r.json()["errors"][0]["field"] == field, r.json()
    assert _stored_runs(tmp_path / "data") == 0
