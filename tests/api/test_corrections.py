"""Corrections over the API: PATCH and DELETE of a stored row, the list of corrections, the
readings as corrected and as typed, the results computed on the corrected values (also of a
finished run), the report's table, the scopes and the refusals."""

from __future__ import annotations

import io
import math
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import h5py
import pytest
from fastapi.testclient import TestClient

from rigserver.api.app import create_app
from rigserver.api.auth import ApiKey
from rigserver.api.settings import Settings
from rigserver.storage import HDF5Store
from schemas.stands import configure_stands
from tests.api.conftest import KEYS, MTOS_ONLY, MTOS_STEPS, READER, WRITER, auth
from tests.api.test_service import API, friction_batch, open_run
from tests.reports.rendered import pdf_text, squeezed


@pytest.fixture
def hdf5_client(tmp_path: Path) -> Iterator[TestClient]:
    """The service over the embedded store, rendering reports in process."""
    settings = Settings(data_dir=tmp_path, reports_on_finish=False)
    app = create_app(
        settings,
        HDF5Store(tmp_path / "data"),
        [ApiKey.model_validate(k) for k in KEYS],
        configure_stands(),
    )
    with TestClient(app, raise_server_exceptions=False) as c:
        yield c


def _mtos_run(client: TestClient, steps: dict[str, list[float]] = MTOS_STEPS) -> str:
    run_id = open_run(client, "mtos")
    for seq, (group, columns) in enumerate(
        [("measurements", {"x_zero": [0.0], "y_zero": [0.0]}), ("steps", steps)]
    ):
        body = {"seq": seq, "group": group, "columns": columns}
        r = client.post(f"{API}/runs/{run_id}/readings", json=body, headers=auth(WRITER))
        assert r.status_code == 201, r.text
    return run_id


def _patch(
    client: TestClient, run_id: str, group: str, index: int, body: dict[str, Any], key: str = WRITER
) -> Any:
    return client.patch(
        f"{API}/runs/{run_id}/readings/{group}/{index}", json=body, headers=auth(key)
    )


def _strike(client: TestClient, run_id: str, group: str, index: int, reason: str) -> Any:
    return client.request(
        "DELETE",
        f"{API}/runs/{run_id}/readings/{group}/{index}",
        json={"reason": reason},
        headers=auth(WRITER),
    )


def _values(client: TestClient, run_id: str) -> dict[str, Any]:
    r = client.get(f"{API}/runs/{run_id}/results", headers=auth(READER))
    assert r.status_code == 200, r.text
    values: dict[str, Any] = r.json()["values"]
    return values


def _friction(values: dict[str, Any]) -> list[float]:
    return [s["friction_measured"] for s in values["steps"]]


def test_two_corrections_of_one_cell_are_listed_and_the_typed_value_kept(
    client: TestClient,
) -> None:
    run_id = _mtos_run(client)
    first = _patch(client, run_id, "steps", 1, {"values": {"indicator": 0.06}, "reason": "misread"})
    assert first.status_code == 200, first.text
    assert first.json()["values"]["indicator"] == 0.06
    assert first.json()["original"]["indicator"] == 0.03
    second = _patch(client, run_id, "steps", 1, {"values": {"indicator": 0.05}, "reason": "again"})
    assert second.status_code == 200
    listed = client.get(f"{API}/runs/{run_id}/corrections", headers=auth(READER)).json()
    assert [
        (c["row"], c["channel"], c["was"], c["now"], c["unit"], c["reason"], c["by"])
        for c in listed["corrections"]
    ] == [
        (1, "indicator", 0.03, 0.06, "mm", "misread", "lab PC"),
        (1, "indicator", 0.06, 0.05, "mm", "again", "lab PC"),
    ]
    url = f"{API}/runs/{run_id}/readings?group=steps"
    corrected = client.get(url, headers=auth(READER)).json()["steps"]["columns"]["indicator"]
    typed = client.get(f"{url}&original=true", headers=auth(READER)).json()["steps"]["columns"]
    assert corrected == [0.02, 0.05, 0.04]
    assert typed["indicator"] == MTOS_STEPS["indicator"]
    csv = client.get(f"{url}&format=csv", headers=auth(READER)).text.splitlines()
    assert csv[2].split(",")[1] == "0.05"
    csv = client.get(f"{url}&format=csv&original=true", headers=auth(READER)).text.splitlines()
    assert csv[2].split(",")[1] == "0.03"
    for original, expected in (("false", 0.05), ("true", 0.03)):
        r = client.get(
            f"{API}/runs/{run_id}/readings?format=hdf5&original={original}", headers=auth(READER)
        )
        with h5py.File(io.BytesIO(r.content), "r") as f:
            assert f["entry/steps/indicator"][1] == expected
            assert list(f["entry/corrections/was"][()]) == [0.03, 0.06]
    assert client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()["corrections"] == 2


def test_the_results_follow_the_corrected_reading(client: TestClient) -> None:
    """f_e = k·Δl·l1/(l2·N) (4.13)-(4.16): the step's f_e grows with the corrected Δl in
    proportion, and equals that of a run whose Δl was typed right the first time."""
    run_id = _mtos_run(client)
    before = _friction(_values(client, run_id))
    _patch(client, run_id, "steps", 1, {"values": {"indicator": 0.06}, "reason": "misread"})
    after = _friction(_values(client, run_id))
    assert after[1] == pytest.approx(before[1] * 0.06 / 0.03, rel=1e-12)
    assert after[0] == before[0] and after[2] == before[2]
    right = _mtos_run(client, {**MTOS_STEPS, "indicator": [0.02, 0.06, 0.04]})
    assert _values(client, run_id) == _values(client, right)
    # a row struck out is left out of the results
    assert _strike(client, run_id, "steps", 2, "typed twice").json()["struck"] is True
    assert _friction(_values(client, run_id)) == after[:2]
    data = client.get(f"{API}/runs/{run_id}/readings?group=steps", headers=auth(READER)).json()
    assert data["steps"]["rows"] == 2 and data["steps"]["struck"] == [2]


def test_a_finished_run_corrected_gets_new_results_a_flag_and_a_report_table(
    hdf5_client: TestClient,
) -> None:
    """I_h = h/L with h = Δm/(ρ·π·r²) (2.9)-(2.13): the pin's mass after the test corrected
    after the run was finished gives the wear of the corrected mass loss."""
    client = hdf5_client
    run_id = open_run(client)
    batch = friction_batch(0, 0, n=40)
    batch["columns"]["revolutions"] = [i * 150 / 39 for i in range(40)]  # type: ignore[index]
    client.post(f"{API}/runs/{run_id}/readings", json=batch, headers=auth(WRITER))
    m = {"pin_mass_before": [12.5], "pin_mass_after": [12.47], "disc_ra": [0.78]}
    body = {"seq": 1, "group": "measurements", "columns": m}
    client.post(f"{API}/runs/{run_id}/readings", json=body, headers=auth(WRITER))
    assert client.post(f"{API}/runs/{run_id}/finish", headers=auth(WRITER)).status_code == 200
    assert not client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()[
        "corrected_after_finish"
    ]
    fix = {"values": {"pin_mass_after": 12.48}, "reason": "the balance was not zeroed"}
    r = _patch(client, run_id, "measurements", 0, fix)
    assert r.status_code == 200, r.text
    run = client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()
    assert run["state"] == "finished" and run["corrected_after_finish"] is True
    v = _values(client, run_id)
    r2, revolutions = 0.0225, 150 * 100  # the counter in hundreds
    L = 2 * math.pi * r2 * revolutions
    h = 0.02e-3 / 7800 / (math.pi * 0.005**2)  # 12.5 g - 12.48 g
    assert v["experimental"]["intensity"] == pytest.approx(h / L, rel=1e-9)
    measured = client.get(f"{API}/runs/{run_id}/readings?group=measurements", headers=auth(READER))
    assert measured.json()["measurements"]["values"]["pin_mass_after"] == 12.48
    for lang, words in (
        ("en", ("Corrections", "corrected after it was finished", "12.47", "12.48")),
        ("ru", ("Исправления", "исправлен после завершения", "12,47", "12,48")),
    ):
        page = client.get(f"{API}/runs/{run_id}/report.html?lang={lang}", headers=auth(READER))
        assert page.status_code == 200, page.text
        text = re.sub(r"\s+", " ", re.sub(r"<[^>]+>", " ", page.text))
        assert "the balance was not zeroed" in text
        for word in words:
            assert word in text, (lang, word)
    # the PDF prints the same table (its text as poppler reads it)
    pdf = client.get(f"{API}/runs/{run_id}/report.pdf", headers=auth(READER))
    assert pdf.status_code == 200
    printed = squeezed(pdf_text(pdf.content))
    for word in ("Corrections", "12.47", "12.48", "thebalancewasnotzeroed", "Was", "Now"):
        assert squeezed(word) in printed, word


def test_a_correction_needs_the_stands_write_scope(client: TestClient) -> None:
    run_id = open_run(client)  # an SMTs-2 run
    client.post(
        f"{API}/runs/{run_id}/readings", json=friction_batch(0, 0, n=5), headers=auth(WRITER)
    )
    body = {"values": {"load": 301.0}, "reason": "misread"}
    refused = _patch(client, run_id, "friction", 1, body, key=MTOS_ONLY)
    assert refused.status_code == 403
    assert "write:smts2" in refused.json()["detail"]
    assert _patch(client, run_id, "friction", 1, body, key=READER).status_code == 403
    anonymous = client.patch(f"{API}/runs/{run_id}/readings/friction/1", json=body)
    assert anonymous.status_code == 401
    assert (
        client.get(f"{API}/runs/{run_id}/corrections", headers=auth(READER)).json()["corrections"]
        == []
    )


@pytest.mark.parametrize(
    ("index", "body", "field", "words"),
    [
        (
            1,
            {"values": {"indicator": 12.5}, "reason": "r"},
            "values.indicator",
            "0 <= value <= 10 mm",
        ),
        (1, {"values": {"indicator": "0.5"}, "reason": "r"}, "values.indicator", "number"),
        (1, {"values": {"indicator": True}, "reason": "r"}, "values.indicator", "number"),
        (1, {"values": {"wear": 0.5}, "reason": "r"}, "values.wear", "no channel 'wear'"),
        (1, {"values": {"indicator": 0.5}, "reason": " "}, "reason", "say why"),
        (1, {"values": {"indicator": 0.5}, "reason": "x" * 501}, "reason", "at most 500"),
        (1, {"values": {"indicator": 0.5}}, "reason", "required"),
        (1, {"values": {}, "reason": "r"}, "values", ""),
        (9, {"values": {"indicator": 0.5}, "reason": "r"}, "index", "0 <= index < 3"),
    ],
)
def test_a_bad_correction_is_refused_naming_the_field(
    client: TestClient, index: int, body: dict[str, Any], field: str, words: str
) -> None:
    run_id = _mtos_run(client)
    r = _patch(client, run_id, "steps", index, body)
    assert r.status_code == 422, r.text
    error = r.json()["errors"][0]
    assert error["field"] == field
    assert words in r.json()["detail"]
    assert client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()["corrections"] == 0


def test_the_run_page_says_the_run_was_corrected_after_it_finished(client: TestClient) -> None:
    run_id = _mtos_run(client)
    assert client.post(f"{API}/runs/{run_id}/finish", headers=auth(WRITER)).status_code == 200
    _patch(client, run_id, "steps", 0, {"values": {"indicator": 0.025}, "reason": "misread"})
    for lang, words in (("en", "corrected after it was finished"), ("ru", "исправлен после")):
        page = client.get(f"/runs/{run_id}?lang={lang}", headers=auth(READER))
        assert page.status_code == 200, page.text
        state = re.search(r'id="run-state">([^<]*)<', page.text)
        assert state is not None and words in state.group(1)
        assert 'id="run-corrections">1 (' in page.text
