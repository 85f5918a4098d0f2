"""The report and download routes over HTTP (in process, in-memory store)."""

from __future__ import annotations

import csv
import io
import json
import zipfile
from datetime import datetime

import numpy as np
import pytest
from fastapi.testclient import TestClient

from schemas.labels import SMTS2
from schemas.stands import StandKind
from tests.api.conftest import READER, auth
from tests.reports.simulated import simulated

API = "/api/v1"


def test_report_html_in_english_and_russian(served: tuple[TestClient, dict[str, str]]) -> None:
    client, ids = served
    url = f"{API}/runs/{ids['smts2']}/report.html"
    english = client.get(url, headers=auth(READER))
    assert english.status_code == 200
    assert english.headers["content-type"].startswith("text/html")
    assert english.headers["content-language"] == "en"
    assert "Lab work 2." in english.text
    for russian in (
        client.get(url, params={"lang": "ru"}, headers=auth(READER)),
        client.get(url, headers={**auth(READER), "Accept-Language": "ru-RU,ru;q=0.9,en;q=0.5"}),
    ):
        assert russian.headers["content-language"] == "ru"
        assert "Лабораторная работа № 2." in russian.text
    refused = client.get(url, params={"lang": "de"}, headers=auth(READER))
    assert refused.status_code == 422
    assert refused.headers["content-type"].startswith("application/problem+json")


def test_report_of_an_open_run_on_the_readings_so_far(
    served: tuple[TestClient, dict[str, str]],
) -> None:
    client, ids = served
    answer = client.get(f"{API}/runs/{ids['open']}/report.html", headers=auth(READER))
    assert answer.status_code == 200
    assert "The run is still open" in answer.text
    assert "Table 3.3." in answer.text


def test_report_pdf_is_an_a4_download(served: tuple[TestClient, dict[str, str]]) -> None:
    client, ids = served
    answer = client.get(f"{API}/runs/{ids['smts2']}/report.pdf?lang=ru", headers=auth(READER))
    assert answer.status_code == 200
    assert answer.headers["content-type"] == "application/pdf"
    disposition = answer.headers["content-disposition"]
    assert disposition == f'attachment; filename="{ids["smts2"]}-report-ru.pdf"'
    assert answer.content.startswith(b"%PDF-")


def test_results_csv_rows_carry_values_and_units(
    served: tuple[TestClient, dict[str, str]],
) -> None:
    client, ids = served
    results = client.get(f"{API}/runs/{ids['smts2']}/results", headers=auth(READER)).json()
    answer = client.get(f"{API}/runs/{ids['smts2']}/results.csv", headers=auth(READER))
    assert answer.headers["content-type"].startswith("text/csv")
    rows = {r["path"]: r for r in csv.DictReader(io.StringIO(answer.text))}
    steady = rows["friction_steady"]
    assert steady["Quantity"] == "friction coefficient, steady part (2.8)"
    assert float(steady["Value"]) == float(f"{results['values']['friction_steady']:.4g}")
    mass = rows["experimental.mass_loss"]  # kg stored, mg shown (the manual's)
    assert (mass["Symbol"], mass["Unit"]) == ("Δm", "mg")
    assert float(mass["Value"]) == float(
        f"{results['values']['experimental']['mass_loss'] * 1e6:.4g}"
    )
    assert rows["theoretical.contact"]["Value"] == "elastic"
    assert not [p for p in rows if p.startswith("friction.")]  # no plot series
    # one row per scalar result: at most one per declared label (the 4 000 plot points of
    # the friction record and the per-row tables are elsewhere)
    assert len(rows) == len(set(rows)) <= len(SMTS2)
    excel = client.get(
        f"{API}/runs/{ids['smts2']}/results.csv?dialect=excel-ru", headers=auth(READER)
    )
    assert excel.content.startswith("\ufeff".encode())
    ru = list(csv.reader(io.StringIO(excel.text.lstrip("\ufeff")), delimiter=";"))
    assert ru[0][:4] == ["Величина", "Обозначение", "Значение", "Ед."]
    by_path = {r[-1]: r for r in ru[1:]}
    assert by_path["experimental.mass_loss"][2] == mass["Value"].replace(".", ",")


def test_export_zip_has_every_group_and_the_results(
    served: tuple[TestClient, dict[str, str]],
) -> None:
    client, ids = served
    run_id = ids["smts2"]
    answer = client.get(f"{API}/runs/{run_id}/export.zip", headers=auth(READER))
    assert answer.status_code == 200
    assert answer.headers["content-type"] == "application/zip"
    archive = zipfile.ZipFile(io.BytesIO(answer.content))
    assert sorted(archive.namelist()) == sorted(
        f"{run_id}/{name}"
        for name in ("run.json", "results.json", "results.csv", "friction.csv", "measurements.csv")
    )
    made = datetime(*archive.getinfo(f"{run_id}/run.json").date_time)
    assert made.year >= 2026  # the real time, not 1980
    weighed = list(csv.DictReader(io.StringIO(archive.read(f"{run_id}/measurements.csv").decode())))
    posted = simulated(StandKind.SMTS2).sim.columns("measurements")
    assert {r["channel"]: float(r["value"]) for r in weighed} == {
        name: float(values[~np.isnan(values)][-1]) for name, values in posted.items()
    }  # one named value per channel, no NaN padding
    sim = simulated(StandKind.SMTS2).sim
    friction = list(csv.reader(io.StringIO(archive.read(f"{run_id}/friction.csv").decode())))
    assert friction[0][0] == "time [s]"
    assert len(friction) == 1 + sim.rows("friction")
    assert [float(x) for x in friction[-1]] == [
        float(sim.columns("friction")[c.split(" ")[0]][-1]) for c in friction[0]
    ]
    same = client.get(
        f"{API}/runs/{run_id}/readings?group=friction&format=csv", headers=auth(READER)
    )
    assert archive.read(f"{run_id}/friction.csv").decode() == same.text  # one CSV format
    stored = client.get(f"{API}/runs/{run_id}/results", headers=auth(READER)).json()
    assert json.loads(archive.read(f"{run_id}/results.json")) == stored


def test_export_zip_has_a_csv_per_table(served: tuple[TestClient, dict[str, str]]) -> None:
    client, ids = served
    run_id = ids["mtos"]
    answer = client.get(f"{API}/runs/{run_id}/export.zip", headers=auth(READER))
    archive = zipfile.ZipFile(io.BytesIO(answer.content))
    steps = list(csv.reader(io.StringIO(archive.read(f"{run_id}/results_steps.csv").decode())))
    stored = client.get(f"{API}/runs/{run_id}/results", headers=auth(READER)).json()
    assert len(steps) == 1 + len(stored["values"]["steps"])
    assert "eccentricity ratio (4.11), χ" in steps[0]
    assert "film thickness, hₘᵢₙ [µm]" in steps[0]  # µm, not m
    assert not any("[0]" in h for h in steps[0])


@pytest.mark.parametrize("path", ["report.html", "report.pdf", "results.csv", "export.zip"])
def test_reads_need_a_key(served: tuple[TestClient, dict[str, str]], path: str) -> None:
    client, ids = served
    answer = client.get(f"{API}/runs/{ids['smts2']}/{path}")
    assert answer.status_code == 401
    assert "read" in answer.json()["detail"]


def test_measurements_are_named_single_values_in_json(
    served: tuple[TestClient, dict[str, str]],
) -> None:
    client, ids = served
    answer = client.get(
        f"{API}/runs/{ids['smts2']}/readings?group=measurements", headers=auth(READER)
    )
    found = answer.json()["measurements"]
    posted = simulated(StandKind.SMTS2).sim.columns("measurements")
    assert found["values"] == {
        name: float(values[~np.isnan(values)][-1]) for name, values in posted.items()
    }  # no null padding: one value per channel
    assert found["units"] == {"pin_mass_before": "g", "pin_mass_after": "g", "disc_ra": "um"}
