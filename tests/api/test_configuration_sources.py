"""Where every configuration value came from (issue 37, item 5): the values a run's opening
gives are marked by who gave them (the operator, or the file and its map); the rest are the
stand's defaults, printed only as "not given: the stand's default", and a result resting on
one says so."""

from __future__ import annotations

from html import unescape
from typing import Any

import numpy as np
import pytest
from fastapi.testclient import TestClient

from rigclient.summary import result_notes
from rigserver.analysis.tribometer import NOTE_SPEED_DEFAULT
from rigserver.reports.i18n import Lang, Messages
from rigserver.reports.run_report import configuration_rows
from schemas.runs import Run
from tests.api.conftest import READER, WRITER, auth


def _open(client: TestClient, **body: Any) -> Run:
    answer = client.post(
        "/api/v1/runs",
        json={"stand": "pin_on_disc", "operator": "Orlova", **body},
        headers=auth(WRITER),
    )
    assert answer.status_code == 201, answer.text
    return Run.model_validate(answer.json())


def test_the_given_values_are_marked_by_who_gave_them(client: TestClient) -> None:
    run = _open(client, configuration={"plan": {"load": 3.0}, "track_radius": 0.005})
    assert run.configuration_given == {"plan.load": "operator", "track_radius": "operator"}
    assert run.from_default("plan.speed") and not run.from_default("plan.load")
    by_file = _open(client, configuration={"plan": {"load": 3.0}}, given_by="file")
    assert by_file.configuration_given == {"plan.load": "file"}


def test_a_default_is_printed_as_one(client: TestClient) -> None:
    run = _open(client, configuration={"plan": {"load": 3.0}})
    langs: list[tuple[Lang, str]] = [("en", "not given: the stand's default"), ("ru", "не задано")]
    for lang, said in langs:
        rows = {str(row.words): row.value for row in configuration_rows(Messages(lang), run)}
        load = next(shown for words, shown in rows.items() if "load" in words or "нагруз" in words)
        speed = next(
            shown
            for words, shown in rows.items()
            if "sliding speed" in words or "скорость" in words
        )
        assert said not in load and load.startswith("3")
        assert speed.startswith(said), speed


def _post_record(client: TestClient, run: Run) -> dict[str, Any]:
    n = 50
    columns = {"time": np.arange(n, dtype=float).tolist(), "friction_coefficient": [0.4] * n}
    headers = auth(WRITER)
    body = {"seq": 0, "group": "friction", "columns": columns}
    answer = client.post(f"/api/v1/runs/{run.id}/readings", json=body, headers=headers)
    assert answer.status_code == 201, answer.text
    assert client.post(f"/api/v1/runs/{run.id}/finish", headers=headers).status_code == 200
    results = client.get(f"/api/v1/runs/{run.id}/results", headers=auth(READER))
    assert results.status_code == 200, results.text
    found: dict[str, Any] = results.json()
    return found


def test_a_distance_from_the_default_speed_says_so(client: TestClient) -> None:
    # no distance, no laps: the planned speed times time; the speed nobody gave is the
    # stand's default, said in the results, the report's notes and rigclient's summary
    run = _open(client, configuration={"plan": {"load": 3.0}})
    defaulted = _post_record(client, run)
    assert NOTE_SPEED_DEFAULT in defaulted["values"]["notes"]
    assert f"note: {NOTE_SPEED_DEFAULT}" in result_notes(defaulted)
    report = client.get(f"/api/v1/runs/{run.id}/report.html", headers=auth(READER))
    assert report.status_code == 200, report.text
    assert "not given: the stand's default" in unescape(report.text)
    assert "the sliding distance rests on the planned speed" in unescape(report.text)
    given = _post_record(client, _open(client, configuration={"plan": {"speed": 0.05}}))
    assert NOTE_SPEED_DEFAULT not in given["values"]["notes"]
    assert given["values"]["sliding_distance"] == pytest.approx(0.05 * 49, rel=1e-12)
