"""The runs list and a run's page, rendered on the server (in process, in-memory store)."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from rigserver.api.auth import ApiKey
from rigserver.api.routes import pages
from rigserver.api.sessions import COOKIE, SESSION_SECONDS, Sessions
from rigserver.reports.formatting import shown
from rigserver.web.pages import live_axes
from schemas.labels import PROFILOMETER, SMTS2
from schemas.stands import StandKind, default_stands
from tests.api.conftest import KEYS, MTOS_ONLY, READER, WRITER, auth, in_process
from tests.reports.simulated import post, simulated


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[TestClient, dict[str, str]]]:
    """Public reads; a finished profilometer run, then a finished and an open SMTs-2 run."""
    with in_process(Path(tmp_path_factory.mktemp("data")), public_reads=True) as client:
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
    # in the manual's unit (µm) and the digits declared for Ra (three)
    assert f"R<sub>a</sub> = {shown(PROFILOMETER['ra'], ra, 'm')} µm" in answer.text
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
    assert config["results_url"] == f"/runs/{run_id}/results?lang=en"
    assert (config["state"], config["x"], config["y"]) == ("open", "time", "friction_moment")
    for link in (
        f"/api/v1/runs/{run_id}/report.pdf?lang=en",
        f"/api/v1/runs/{run_id}/report.html?lang=en",
        f"/api/v1/runs/{run_id}/readings?group=friction&amp;format=csv",
        f"/api/v1/runs/{run_id}/results.csv?lang=en",
        f"/api/v1/runs/{run_id}/export.zip?lang=en",
        f"/api/v1/runs/{run_id}/readings?format=hdf5",
    ):
        assert f'href="{link}"' in html
    script = client.get("/static/live.js")
    assert script.status_code == 200 and "EventSource" in script.text


def test_a_finished_run_shows_its_results_as_the_report_groups_them(
    site: tuple[TestClient, dict[str, str]],
) -> None:
    client, ids = site
    html = client.get(f"/runs/{ids['wear']}", params={"lang": "ru"}).text
    assert "Пока испытание идёт" not in html  # no "while the run is open" on a finished run
    parts = re.findall(r"<h3>([^<]+)</h3>", html)
    assert parts[:3] == ["Результаты измерений", "Теория", "Сравнение теории и опыта"]
    paths = re.findall(r'data-path="([^"]+)"', html)
    declared = [p for p in SMTS2 if p in paths]
    assert paths == declared  # the declared order, not the alphabet
    assert "theoretical.k_nu" not in re.sub(r'data-path="[^"]+"', "", html)
    assert "коэффициент трения, установившийся участок (2.8)" in html
    assert "нагрузка: 300 Н" in html  # the test plan with labels, not load_N: 300
    fragment = client.get(f"/runs/{ids['wear']}/results", params={"lang": "en"}).text
    assert "friction coefficient, steady part (2.8)" in fragment
    open_page = client.get(f"/runs/{ids['open']}").text
    assert 'id="results-note"' in open_page


def test_an_unknown_run_page_is_a_404(site: tuple[TestClient, dict[str, str]]) -> None:
    client, _ = site
    answer = client.get("/runs/20261122T114026Z-00000000")
    assert answer.status_code == 404
    assert answer.headers["content-type"].startswith("application/problem+json")


def _private_site(tmp_path: Path) -> TestClient:
    client = in_process(tmp_path)
    client.follow_redirects = False
    return client


def test_pages_send_a_browser_without_a_key_to_the_login(tmp_path: Path) -> None:
    with _private_site(tmp_path) as client:
        answer = client.get("/runs/20261122T114026Z-00000000?lang=ru")
        assert answer.status_code == 303
        assert answer.headers["location"] == (
            "/login?next=%2Fruns%2F20261122T114026Z-00000000%3Flang%3Dru"
        )
        assert client.get("/static/style.css").status_code == 200  # no data in it
        assert client.get("/", headers=auth(MTOS_ONLY)).status_code == 403  # a key, no read


def test_a_read_key_given_once_becomes_a_session_for_reads_only(tmp_path: Path) -> None:
    with _private_site(tmp_path) as client:
        form = client.get("/login?next=/runs/x")
        assert form.status_code == 200 and 'name="key"' in form.text
        answer = client.post("/login", data={"key": READER, "next": "/?lang=ru"})
        assert answer.status_code == 303 and answer.headers["location"] == "/?lang=ru"
        cookie = answer.headers["set-cookie"]
        assert "HttpOnly" in cookie and "SameSite=strict" in cookie and READER not in cookie
        page = client.get("/")
        assert page.status_code == 200 and 'action="/logout"' in page.text
        assert client.get("/api/v1/runs").status_code == 200  # the live page's API reads
        opened = client.post("/api/v1/runs", json={"stand": "smts2", "operator": "X"})
        assert opened.status_code == 401  # never a write by cookie
        client.post("/logout")
        assert client.get("/").status_code == 303


#: The manual's plots of each stand's record (x, y): lab 2 M_tr(t); lab 3 the middle
#: manometer p3 (z = 0, table 3.1) over the limb angle; lab 4 Δl over N (tables 4.1-4.3);
#: lab 1 the profile y(x); a tribometer μ(t).
LIVE_CHARTS = {
    StandKind.SMTS2: ("time", "friction_moment"),
    StandKind.SLIDE_BEARING: ("limb_angle", "p3"),
    StandKind.MTOS: ("load", "indicator"),
    StandKind.PROFILOMETER: ("x", "y"),
    StandKind.PIN_ON_DISC: ("time", "friction_coefficient"),
    StandKind.RECIPROCATING: ("time", "friction_coefficient"),
}


@pytest.mark.parametrize("kind", list(StandKind))
def test_a_live_chart_draws_the_manual_s_plot_of_the_record(kind: StandKind) -> None:
    record = next(g for g in default_stands()[kind].groups if g.aligned)
    assert live_axes(record) == LIVE_CHARTS[kind]


def test_a_cookie_of_no_live_session_shows_no_log_out(
    site: tuple[TestClient, dict[str, str]],
) -> None:
    """Public reads: a page is served to anyone, and a cookie left from an expired session
    (or from before a restart) is no session to log out of."""
    client, _ = site
    client.cookies.set(COOKIE, "left-from-before-a-restart")
    try:
        page = client.get("/")
        assert page.status_code == 200 and 'action="/logout"' not in page.text
        client.cookies.delete(COOKIE)
        answer = client.post("/login", data={"key": READER, "next": "/"}, follow_redirects=False)
        assert answer.status_code == 303
        assert 'action="/logout"' in client.get("/").text  # a live session: the button
    finally:
        client.cookies.clear()


@pytest.mark.parametrize(
    ("key", "target", "status", "location"),
    [
        (MTOS_ONLY, "/", 401, None),  # a key that may not read
        ("not-a-key-of-this-server", "/", 401, None),
        (READER, "//elsewhere.example/", 303, "/"),  # no redirect off the site
        (READER, "https://elsewhere.example/", 303, "/"),
    ],
)
def test_the_login_refuses_keys_that_cannot_read_and_stays_on_the_site(
    tmp_path: Path, key: str, target: str, status: int, location: str | None
) -> None:
    with _private_site(tmp_path) as client:
        answer = client.post("/login", data={"key": key, "next": target})
        assert answer.status_code == status
        if location is None:
            assert "set-cookie" not in answer.headers
            assert key not in answer.text
        else:
            assert answer.headers["location"] == location


def test_sessions_end_after_a_lab_day() -> None:
    now = [0.0]
    sessions = Sessions(clock=lambda: now[0])
    token = sessions.open(ApiKey.model_validate(KEYS[1]))
    reader = sessions.find(token)
    assert reader is not None and reader.scopes == {"read"}  # the writer key reads only
    now[0] = SESSION_SECONDS + 1
    assert sessions.find(token) is None
    with pytest.raises(ValueError, match="read"):
        sessions.open(ApiKey.model_validate(KEYS[2]))
