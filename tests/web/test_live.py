"""The live readings (server-sent events): every row once, in order, resumable by
``Last-Event-ID``; the end of the run closes the stream (in process, in-memory store)."""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fastapi.testclient import TestClient

from rigserver.api.routes import live
from schemas.stands import StandKind
from tests.api.conftest import READER, WRITER, auth, in_process
from tests.reports.simulated import post, simulated

API = "/api/v1"


@dataclass
class Event:
    name: str
    id: str | None
    data: dict[str, Any]


def events(client: TestClient, url: str, **headers: str) -> list[Event]:
    """The events of one connection, until the server closes it."""
    found: list[Event] = []
    fields: dict[str, str] = {}
    with client.stream("GET", url, headers={**auth(READER), **headers}) as answer:
        assert answer.status_code == 200, answer.read()
        assert answer.headers["content-type"].startswith("text/event-stream")
        for line in answer.iter_lines():
            if not line:
                if "event" in fields:
                    data = json.loads(fields["data"])
                    found.append(Event(fields["event"], fields.get("id"), data))
                fields = {}
            elif not line.startswith(":"):
                name, _, value = line.partition(": ")
                fields[name] = value
    return found


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    with in_process(tmp_path) as c:
        yield c


def joined(found: list[Event], channel: str) -> list[float]:
    return [v for e in found if e.name == "rows" for v in e.data["columns"][channel]]


def test_a_finished_run_streams_every_row_once_then_ends(client: TestClient) -> None:
    sim = simulated(StandKind.SMTS2).sim
    run_id = post(client, sim, WRITER)
    found = events(client, f"{API}/runs/{run_id}/live")
    total = sim.rows("friction")  # 9185 rows: two events of at most MAX_ROWS
    rows = [e for e in found if e.name == "rows"]
    assert [(e.data["start"], e.data["stop"], e.id) for e in rows] == [
        (0, live.MAX_ROWS, str(live.MAX_ROWS)),
        (live.MAX_ROWS, total, str(total)),
    ]
    assert np.array_equal(
        joined(found, "friction_moment"), sim.columns("friction")["friction_moment"]
    )
    assert found[-1] == Event("end", None, {"state": "finished", "rows": total})


def test_last_event_id_resumes_where_the_client_stopped(client: TestClient) -> None:
    sim = simulated(StandKind.SLIDE_BEARING).sim
    run_id = post(client, sim, WRITER)
    found = events(client, f"{API}/runs/{run_id}/live?from=3", **{"Last-Event-ID": "15"})
    assert [(e.data["start"], e.data["stop"]) for e in found if e.name == "rows"] == [(15, 19)]
    assert joined(found, "limb_angle") == sim.columns("rows")["limb_angle"][15:].tolist()
    resumed = events(client, f"{API}/runs/{run_id}/live?from=17")  # a new connection
    assert joined(resumed, "limb_angle") == sim.columns("rows")["limb_angle"][17:].tolist()


def test_an_open_run_streams_as_batches_arrive(
    client: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(live, "MAX_SECONDS", 0.2)  # each connection closes soon, unended
    sim = simulated(StandKind.SLIDE_BEARING).sim
    created = client.post(
        f"{API}/runs", json=sim.run_create.model_dump(mode="json"), headers=auth(WRITER)
    )
    run_id = created.json()["id"]
    url = f"{API}/runs/{run_id}/live"

    def send(seq: int) -> None:
        batch = sim.batches[seq]
        body = {"seq": seq, "group": batch.group, "columns": batch.as_json()}
        assert client.post(f"{url[:-5]}/readings", json=body, headers=auth(WRITER)).is_success

    rows_group = [i for i, b in enumerate(sim.batches) if b.group == "rows"]
    for seq in range(rows_group[2] + 1):
        send(seq)
    first = events(client, url)
    assert [e.name for e in first] == ["rows"]  # no end: the run is open
    seen = first[-1].id
    assert seen == "3"
    for seq in range(rows_group[2] + 1, len(sim.batches)):
        send(seq)
    assert client.post(f"{API}/runs/{run_id}/finish", headers=auth(WRITER)).is_success
    rest = events(client, url, **{"Last-Event-ID": seen})
    assert joined(first + rest, "p3") == sim.columns("rows")["p3"].tolist()
    assert rest[-1].name == "end"


def test_bad_requests_are_problems(client: TestClient) -> None:
    run_id = post(client, simulated(StandKind.SLIDE_BEARING).sim, WRITER)
    url = f"{API}/runs/{run_id}/live"
    bad_id = client.get(url, headers={**auth(READER), "Last-Event-ID": "abc"})
    assert bad_id.status_code == 422
    assert "number of rows already received" in bad_id.json()["detail"]
    for group in ("measurements", "friction"):
        answer = client.get(url, params={"group": group}, headers=auth(READER))
        assert answer.status_code == 422
        assert "streams the groups rows" in answer.json()["detail"]
    assert client.get(url).status_code == 401
