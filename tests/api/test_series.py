"""``/series`` over the API: open a series, add runs, read the statistics, the CSV, the report
and the page; the scope and the rules of membership."""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterator

import numpy as np
import pytest
from fastapi.testclient import TestClient

from rigsim.simulators import simulate
from rigsim.simulators.smts2 import Smts2Settings
from schemas.stands import StandKind
from tests.api.conftest import MTOS_ONLY, READER, WRITER, auth, in_process
from tests.reports.simulated import post, tables

FRICTION = (0.38, 0.40, 0.43)


@pytest.fixture(scope="module")
def lab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[TestClient, list[str], str]]:
    """Three finished SMTs-2 runs (steady f 0.38, 0.40, 0.43) and one MTOS run."""
    with in_process(tmp_path_factory.mktemp("series")) as client:
        runs = [
            post(
                client,
                simulate(
                    StandKind.SMTS2,
                    Smts2Settings(revolutions=2000.0, friction_steady=f),
                    seed=40 + i,
                ),
                WRITER,
            )
            for i, f in enumerate(FRICTION)
        ]
        mtos = post(client, simulate(StandKind.MTOS, seed=3), WRITER)
        yield client, runs, mtos


def new_series(client: TestClient, **body: object) -> str:
    answer = client.post("/api/v1/series", json=body, headers=auth(WRITER))
    assert answer.status_code == 201, answer.text
    return str(answer.json()["id"])


def add(client: TestClient, series_id: str, run_id: str, level: str | None = None) -> int:
    body = {"run_id": run_id} | ({"level": level} if level else {})
    return client.post(
        f"/api/v1/series/{series_id}/runs", json=body, headers=auth(WRITER)
    ).status_code


def test_repeatability_series_statistics(lab: tuple[TestClient, list[str], str]) -> None:
    client, runs, _ = lab
    sid = new_series(client, name="Wear, groups 1-3", purpose="repeatability")
    assert [add(client, sid, r) for r in runs] == [201, 201, 201]
    detail = client.get(f"/api/v1/series/{sid}", headers=auth(READER)).json()
    assert detail["stand"] == "smts2"
    assert [r["run_id"] for r in detail["runs"]] == runs
    stats = {s["key"]: s for s in detail["statistics"]}
    friction = stats["friction_steady"]
    values = [v["value"] for v in friction["values"]]
    # Each run's figure is the one its own results give; the summary is computed on them.
    for run_id, value in zip(runs, values, strict=True):
        own = client.get(f"/api/v1/runs/{run_id}/results", headers=auth(READER)).json()
        assert own["values"]["friction_steady"] == value
    overall = friction["overall"]
    assert overall["n"] == 3
    assert overall["mean"] == pytest.approx(np.mean(values), rel=1e-12)
    assert overall["std"] == pytest.approx(np.std(values, ddof=1), rel=1e-12)
    half = 4.302652729911275 * np.std(values, ddof=1) / math.sqrt(3)  # t_{0.975,2} = 4.303
    assert overall["ci_low"] == pytest.approx(np.mean(values) - half, rel=1e-9)
    assert friction["repeatability_std"] == pytest.approx(overall["std"], rel=1e-12)
    assert friction["unit"] == "1" and "(2.8)" in friction["description"]
    assert "experimental.intensity" in stats


def test_comparison_needs_levels_and_compares_them(
    lab: tuple[TestClient, list[str], str],
) -> None:
    client, runs, _ = lab
    sid = new_series(client, name="Two pins", purpose="comparison", factor="material")
    assert add(client, sid, runs[0]) == 422  # a comparison's run needs its level
    assert add(client, sid, runs[0], "St3sp") == 201
    assert add(client, sid, runs[1], "St3sp") == 201
    assert add(client, sid, runs[2], "brass") == 201
    detail = client.get(f"/api/v1/series/{sid}", headers=auth(READER)).json()
    friction = next(s for s in detail["statistics"] if s["key"] == "friction_steady")
    assert [lv["level"] for lv in friction["levels"]] == ["St3sp", "brass"]
    assert friction["comparison"] is None  # one run of brass: nothing to test against
    assert friction["untested"] == "few_runs"
    assert any("two runs" in note for note in friction["notes"])


def test_membership_rules(lab: tuple[TestClient, list[str], str]) -> None:
    client, runs, mtos = lab
    sid = new_series(client, name="repeats", purpose="repeatability")
    assert add(client, sid, runs[0]) == 201
    assert add(client, sid, runs[0]) == 409  # a member already
    assert add(client, sid, mtos) == 409  # another stand
    assert add(client, sid, runs[1], "a level") == 422  # repeats have no levels
    assert add(client, sid, "20261125T000000Z-00000000") == 404
    other = new_series(client, name="another", purpose="repeatability")
    assert add(client, other, runs[0]) == 201  # a run may belong to several series
    gone = client.delete(f"/api/v1/series/{sid}/runs/{runs[0]}", headers=auth(WRITER))
    assert gone.status_code == 200 and gone.json()["members"] == []
    again = client.delete(f"/api/v1/series/{sid}/runs/{runs[0]}", headers=auth(WRITER))
    assert again.status_code == 404
    listed = client.get("/api/v1/series", headers=auth(READER)).json()
    assert {sid, other} <= {s["id"] for s in listed}


@pytest.mark.parametrize(
    ("key", "status"), [(None, 401), (READER, 403), (MTOS_ONLY, 403), (WRITER, 201)]
)
def test_writes_need_the_series_scope(
    lab: tuple[TestClient, list[str], str], key: str | None, status: int
) -> None:
    client, _, _ = lab
    answer = client.post(
        "/api/v1/series",
        json={"name": "x", "purpose": "repeatability"},
        headers=auth(key) if key else {},
    )
    assert answer.status_code == status, answer.text
    if status == 403:
        assert "write:series" in answer.json()["detail"]


@pytest.mark.parametrize(
    ("body", "field"),
    [
        ({"name": "", "purpose": "repeatability"}, "name"),
        ({"name": "x", "purpose": "sweep"}, "purpose"),
        ({"name": "x", "purpose": "comparison"}, "factor"),
        ({"name": "x", "purpose": "repeatability", "factor": "oil"}, "factor"),
    ],
)
def test_bad_series_is_refused_naming_the_field(
    lab: tuple[TestClient, list[str], str], body: dict[str, str], field: str
) -> None:
    client, _, _ = lab
    answer = client.post("/api/v1/series", json=body, headers=auth(WRITER))
    assert answer.status_code == 422
    assert field in answer.text


def test_unknown_series_is_404(lab: tuple[TestClient, list[str], str]) -> None:
    client, _, _ = lab
    for path in ("/api/v1/series/s-000000000000", "/api/v1/series/nonsense"):
        assert client.get(path, headers=auth(READER)).status_code == 404


def test_runs_csv_one_row_per_run(lab: tuple[TestClient, list[str], str]) -> None:
    client, runs, _ = lab
    sid = new_series(client, name="csv", purpose="repeatability")
    for r in runs:
        add(client, sid, r)
    answer = client.get(f"/api/v1/series/{sid}/runs.csv", headers=auth(READER))
    assert answer.status_code == 200 and answer.headers["content-type"].startswith("text/csv")
    rows = list(csv.DictReader(io.StringIO(answer.text)))
    assert [r["run_id"] for r in rows] == runs
    detail = client.get(f"/api/v1/series/{sid}", headers=auth(READER)).json()
    friction = next(s for s in detail["statistics"] if s["key"] == "friction_steady")
    assert [float(r["friction_steady [1]"]) for r in rows] == [
        v["value"] for v in friction["values"]
    ]


@pytest.mark.parametrize("lang", ["en", "ru"])
def test_report_and_page_in_both_languages(
    lab: tuple[TestClient, list[str], str], lang: str
) -> None:
    client, runs, _ = lab
    sid = new_series(client, name="report", purpose="repeatability")
    for r in runs:
        add(client, sid, r)
    report = client.get(f"/api/v1/series/{sid}/report.html?lang={lang}", headers=auth(READER))
    assert report.status_code == 200 and report.headers["content-language"] == lang
    headers = [t.header[0] for t in tables(report.text) if t.header]
    assert ("Result" if lang == "en" else "Результат") in headers
    assert "<svg" in report.text  # the overlay of the friction curves
    page = client.get(f"/series/{sid}?lang={lang}", headers=auth(READER))
    assert page.status_code == 200 and 'id="series-body"' in page.text
    assert 'data-refresh="0"' in page.text  # every run is finished: nothing to refresh
    listing = client.get(f"/series?lang={lang}", headers=auth(READER))
    assert f'href="/series/{sid}?lang={lang}"' in listing.text


def test_report_pdf(lab: tuple[TestClient, list[str], str]) -> None:
    client, runs, _ = lab
    sid = new_series(client, name="pdf", purpose="repeatability")
    add(client, sid, runs[0])
    answer = client.get(f"/api/v1/series/{sid}/report.pdf", headers=auth(READER))
    assert answer.status_code == 200 and answer.content.startswith(b"%PDF")


@pytest.mark.parametrize(
    ("body", "field"),
    [
        ('{"name": "a\\u0000b", "purpose": "repeatability"}', "name"),
        ('{"name": "\\ud800", "purpose": "repeatability"}', "name"),
        ('{"name": "x", "purpose": "comparison", "factor": "oil\\u0000"}', "factor"),
        ('{"name": "x", "purpose": "repeatability", "notes": "\\udc00"}', "notes"),
        ('{"name": "x", "name": "y", "purpose": "repeatability"}', "name"),  # duplicate key
    ],
)
def test_unstorable_series_values_are_refused_and_nothing_stored(
    lab: tuple[TestClient, list[str], str], body: str, field: str
) -> None:
    client, _, _ = lab
    before = len(client.get("/api/v1/series", headers=auth(READER)).json())
    answer = client.post(
        "/api/v1/series",
        content=body.encode(),
        headers={**auth(WRITER), "content-type": "application/json"},
    )
    assert answer.status_code == 422, answer.text
    assert field in answer.text
    assert len(client.get("/api/v1/series", headers=auth(READER)).json()) == before
