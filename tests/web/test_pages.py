"""The runs list and a run's page, rendered on the server (in process, in-memory store)."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from rigserver.api.app import create_app
from rigserver.api.auth import ApiKey
from rigserver.api.routes import pages
from rigserver.api.settings import Settings
from rigserver.reports.formatting import fmt
from rigserver.storage import MemoryStore
from schemas.stands import StandKind, configure_stands
from tests.api.conftest import KEYS, WRITER
from tests.reports.simulated import post, simulated


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[TestClient, dict[str, str]]]:
    """Public reads; a finished profilometer run, then a finished and an open SMTs-2 run."""
    settings = Settings(data_dir=Path(tmp_path_factory.mktemp("data")), public_reads=True)
    app = create_app(
        settings, MemoryStore(), [ApiKey.model_validate(k) for k in KEYS], configure_stands()
    )
    with TestClient(app, raise_server_exceptions=False) as client:
        ids = {"profile": post(client, simulated(StandKind.PROFILOMETER).sim, WRITER)}
        ids["wear"] = post(client, simulated(StandKind.SMTS2).sim, WRITER)
        ids["open"] = post(client, simulated(StandKind.SMTS2).sim, WRITER, finish=False)
        yield client, ids


def run_links(html: str) -> list[str]:
    return re.findall(r'href="/runs/([^"?]+)\?', html)


def test_runs_newest_first_with_their_key_results(
    site: tuple[TestClient, dict[str, str]],
) -> None:
    client, ids = site
    answer = client.get("/")
    assert answer.status_code == 200
    assert answer.headers["content-type"].startswith("text/html")
    assert run_links(answer.text) == [ids["open"], ids["wear"], ids["profile"]]
    ra = simulated(StandKind.PROFILOMETER).result.key_results["ra"]
    assert f"R<sub>a</sub> = {fmt(ra)} m" in answer.text  # the stand's unit, 4 figures
    assert "1–3 of 3" in answer.text


@pytest.mark.parametrize(
    ("query", "expected"),
    [
        ({"stand": "profilometer"}, ["profile"]),
        ({"stand": "smts2", "state": "finished"}, ["wear"]),
        ({"state": "open"}, ["open"]),
        ({"operator": "nobody"}, []),
        ({"operator": "rigsim", "stand": ""}, ["open", "wear", "profile"]),  # empty = any
        ({"since": f"{datetime.now(UTC):%Y-%m-%d}"}, ["open", "wear", "profile"]),
        ({"until": "2000-01-01"}, []),
    ],
)
def test_runs_filtered(
    site: tuple[TestClient, dict[str, str]], query: dict[str, str], expected: list[str]
) -> None:
    client, ids = site
    answer = client.get("/", params=query)
    assert answer.status_code == 200
    assert run_links(answer.text) == [ids[name] for name in expected]


def test_a_bad_filter_is_a_problem(site: tuple[TestClient, dict[str, str]]) -> None:
    client, _ = site
    answer = client.get("/", params={"since": "22.11.2026"})
    assert answer.status_code == 422
    assert "since must be a date like 2026-11-22" in answer.json()["detail"]
    assert client.get("/", params={"state": "done"}).status_code == 422


def test_pages_of_runs(
    site: tuple[TestClient, dict[str, str]], monkeypatch: pytest.MonkeyPatch
) -> None:
    client, ids = site
    monkeypatch.setattr(pages, "PAGE_SIZE", 2)
    first = client.get("/").text
    assert run_links(first) == [ids["open"], ids["wear"]]
    older = re.search(r'href="([^"]+)">older', first)
    assert older is not None
    second = client.get(older.group(1).replace("&amp;", "&")).text
    assert run_links(second) == [ids["profile"]]
    assert "3–3 of 3" in second and "newer" in second


def test_the_runs_list_in_russian(site: tuple[TestClient, dict[str, str]]) -> None:
    client, _ = site
    assert "Испытания" in client.get("/", params={"lang": "ru"}).text
    assert "Испытания" in client.get("/", headers={"Accept-Language": "ru"}).text


def test_a_run_page_has_the_live_view_and_the_downloads(
    site: tuple[TestClient, dict[str, str]],
) -> None:
    client, ids = site
    run_id = ids["open"]
    html = client.get(f"/runs/{run_id}").text
    config = json.loads(re.search(r'id="run-config">(.*?)</script>', html, re.S).group(1))  # type: ignore[union-attr]
    assert config["live_url"] == f"/api/v1/runs/{run_id}/live?group=friction"
    assert config["results_url"] == f"/api/v1/runs/{run_id}/results"
    assert (config["state"], config["x"], config["y"]) == ("open", "time", "friction_moment")
    for link in (
        f"/api/v1/runs/{run_id}/report.pdf?lang=en",
        f"/api/v1/runs/{run_id}/report.html?lang=en",
        f"/api/v1/runs/{run_id}/readings?group=friction&amp;format=csv",
        f"/api/v1/runs/{run_id}/results.csv",
        f"/api/v1/runs/{run_id}/export.zip",
        f"/api/v1/runs/{run_id}/readings?format=hdf5",
    ):
        assert f'href="{link}"' in html
    script = client.get("/static/live.js")
    assert script.status_code == 200 and "EventSource" in script.text


def test_an_unknown_run_page_is_a_404(site: tuple[TestClient, dict[str, str]]) -> None:
    client, _ = site
    answer = client.get("/runs/20261122T114026Z-00000000")
    assert answer.status_code == 404
    assert answer.headers["content-type"].startswith("application/problem+json")


def test_pages_need_a_key_unless_reads_are_public(tmp_path: Path) -> None:
    app = create_app(
        Settings(data_dir=tmp_path),
        MemoryStore(),
        [ApiKey.model_validate(k) for k in KEYS],
        configure_stands(),
    )
    with TestClient(app) as client:
        assert client.get("/").status_code == 401
        assert client.get("/static/style.css").status_code == 200  # no data in it
