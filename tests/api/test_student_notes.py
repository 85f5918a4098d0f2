"""The student's own words on a run (issue 27 item 9): written by a key with the run's stand's
write scope, or the run page's session of such a key; printed by the report as written, in
both languages, under the headings of the lab's report list after the computed results; a new
version renders the report anew."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from fastapi.testclient import TestClient
from markupsafe import escape

from schemas.stands import StandKind
from schemas.student_notes import CONCLUSIONS_LIMIT, STUDENTS_LIMIT
from tests.api.conftest import KEYS, MTOS_ONLY, READER, WRITER, Server, auth, in_process
from tests.api.test_service import open_run
from tests.reports.simulated import post, simulated

API = "/api/v1"
WORDS = {
    "group": "MT-31 <b>",
    "students": ["А. Иванова", "B. O'Neil & Sons"],
    "conclusions": 'The wear grows with the load: f < 0.5 & "mild" <script>x</script>\n'
    "second line\n\nA second paragraph.",
}


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    with in_process(tmp_path, report_processes=False) as c:
        yield c


def _put(client: TestClient, run_id: str, body: Any, key: str | None) -> httpx.Response:
    headers = {"Content-Type": "application/json", **(auth(key) if key else {})}
    text = body if isinstance(body, str) else json.dumps(body)
    return client.put(f"{API}/runs/{run_id}/notes", content=text, headers=headers)


def test_the_order_is_key_then_body_then_scope(client: TestClient) -> None:
    run_id = open_run(client)  # an SMTs-2 run
    bad = {"conclusions": "x\u0000y"}
    assert _put(client, run_id, bad, None).status_code == 401
    assert _put(client, run_id, WORDS, "not-a-key-000000000000").status_code == 401
    assert _put(client, run_id, bad, READER).status_code == 422  # parsed before the scope
    refused = _put(client, run_id, WORDS, READER)
    assert refused.status_code == 403 and "write:smts2" in refused.json()["detail"]
    other = _put(client, run_id, WORDS, MTOS_ONLY)  # a writer of another stand
    assert other.status_code == 403 and "write:smts2" in other.json()["detail"]
    assert client.get(f"{API}/runs/{run_id}/notes", headers=auth(READER)).json()["version"] == 0
    written = _put(client, run_id, WORDS, WRITER)
    assert written.status_code == 200, written.text
    got = client.get(f"{API}/runs/{run_id}/notes", headers=auth(READER)).json()
    assert got == written.json()
    assert {k: got[k] for k in WORDS} == {**WORDS, "group": "MT-31 <b>"}
    assert (got["version"], got["by"]) == (1, "lab PC")
    assert _put(client, "20261122T114026Z-00000000", WORDS, WRITER).status_code == 404


@pytest.mark.parametrize(
    ("body", "field", "words"),
    [
        ({"conclusions": "a\u0000b"}, "conclusions", "NUL"),
        ('{"group": "\\ud800"}', "group", "lone surrogate"),
        ({"conclusions": "x" * (CONCLUSIONS_LIMIT + 1)}, "conclusions", str(CONCLUSIONS_LIMIT)),
        ({"students": ["A"] * (STUDENTS_LIMIT + 1)}, "students", str(STUDENTS_LIMIT)),
        ({"students": ["  "]}, "students.0", "at least 1"),
        ({"group": 31}, "group", "string"),
        ({"grade": "5"}, "grade", "Extra inputs"),
        ('{"group": "a", "group": "b"}', "group", "twice"),
    ],
)
def test_words_the_service_cannot_keep_are_refused_naming_field_and_limit(
    client: TestClient, body: Any, field: str, words: str
) -> None:
    run_id = open_run(client)
    answer = _put(client, run_id, body, WRITER)
    assert answer.status_code == 422, answer.text
    problem = answer.json()
    assert problem["errors"][0]["field"] == field
    assert words in problem["detail"]
    assert client.get(f"{API}/runs/{run_id}/notes", headers=auth(READER)).json()["version"] == 0


def _section(html: str, title: str) -> str:
    """The text of the report's section ``title`` (to the next section)."""
    return html.split(f"<h2>{title}</h2>", 1)[1].split("</section>", 1)[0]


@pytest.mark.parametrize(
    ("lang", "computed", "students", "group"),
    [
        ("en", "Computed results", "Conclusions from the analysis of the results", "Group"),
        ("ru", "Вычисленные результаты", "Выводы по анализу результатов работы", "Группа"),
    ],
)
def test_the_report_prints_the_words_as_written_and_renders_again_after_an_edit(
    client: TestClient, lang: str, computed: str, students: str, group: str
) -> None:
    run_id = post(client, simulated(StandKind.PROFILOMETER).sim, WRITER, finish=False)
    url = f"{API}/runs/{run_id}/report.html?lang={lang}"
    before = client.get(url, headers=auth(READER))
    assert before.status_code == 200
    verdicts = _section(before.text, computed)  # the computed results, before any words
    assert "space ruled" in _section(before.text, students)  # room to write on paper

    assert _put(client, run_id, WORDS, WRITER).status_code == 200
    after = client.get(url, headers={**auth(READER), "If-None-Match": before.headers["etag"]})
    assert after.status_code == 200  # a new version, not 304
    assert after.headers["etag"] != before.headers["etag"]
    html = after.text
    assert f"<tr><th>{group}</th><td>{escape(WORDS['group'])}</td></tr>" in html
    assert escape(", ".join(WORDS["students"])) in html
    section = _section(html, students)
    first, second = WORDS["conclusions"].split("\n\n")
    lines = [escape(line) for line in first.split("\n")]
    assert f"<p>{'<br>'.join(lines)}</p>" in section
    assert f"<p>{escape(second)}</p>" in section
    assert "space ruled" not in section
    assert "<script>" not in html
    # the computed results stay, unchanged, in their own section before the students' words
    assert _section(html, computed) == verdicts
    assert html.index(f"<h2>{computed}</h2>") < html.index(f"<h2>{students}</h2>")

    edited = {**WORDS, "conclusions": "Edited."}
    assert _put(client, run_id, edited, WRITER).status_code == 200
    again = client.get(url, headers=auth(READER)).text
    assert "<p>Edited.</p>" in again and escape(second) not in again


def test_each_section_of_the_students_part_prints_its_own_words(client: TestClient) -> None:
    # lab 3's list: conclusions (item 8) and the reasons for a mismatch (item 8), the
    # bearing's sketch (item 4) a frame on paper; the run page writes both fields
    run_id = post(client, simulated(StandKind.SLIDE_BEARING).sim, WRITER, finish=False)
    words = {"conclusions": "Agreement within 30 %.", "mismatch": "End leakage & heating."}
    assert _put(client, run_id, words, WRITER).status_code == 200
    for lang, heading in (
        ("en", "Reasons for the mismatch of theory and experiment"),
        ("ru", "Причины несовпадения теории и опыта"),
    ):
        html = client.get(f"{API}/runs/{run_id}/report.html?lang={lang}", headers=auth(READER))
        assert f"<p>{escape(words['mismatch'])}</p>" in _section(html.text, heading)
    page = client.get(f"/runs/{run_id}", headers=auth(WRITER)).text
    assert 'name="mismatch"' in page and 'name="analysis"' not in page  # lab 4's, not lab 3's
    assert escape(words["mismatch"]) in page


def _login(client: TestClient, key: str) -> None:
    answer = client.post("/login", data={"key": key, "next": "/"}, follow_redirects=False)
    assert answer.status_code == 303


FORM = {"group": "MT-32", "students": "А. Иванова\r\n\r\nB. Petrov\r\n", "conclusions": "Ours."}


def form_token(page: str) -> str:
    """The session's form token a page carries in its forms."""
    found = re.search(r'name="form_token" value="([^"]+)"', page)
    assert found, "no form token on the page"
    return found[1]


def test_the_run_page_shows_the_form_to_writers_and_takes_it_from_their_session(
    client: TestClient,
) -> None:
    run_id = open_run(client)
    page = f"/runs/{run_id}"
    assert 'name="conclusions"' in client.get(page, headers=auth(WRITER)).text
    assert 'name="conclusions"' not in client.get(page, headers=auth(READER)).text

    # no session: to the login page, nothing stored
    answer = client.post(f"{page}/notes", data=FORM, follow_redirects=False)
    assert answer.status_code == 303 and answer.headers["location"].startswith("/login?")
    _login(client, READER)  # a session that may read only
    assert 'name="conclusions"' not in client.get(page).text
    assert client.post(f"{page}/notes", data=FORM, follow_redirects=False).status_code == 403

    _login(client, WRITER)  # a session of a key that writes every stand
    form = client.get(page).text
    assert 'name="conclusions"' in form and f'action="/runs/{run_id}/notes?lang=en"' in form
    token = form_token(form)
    elsewhere = client.post(
        f"{page}/notes",
        data={**FORM, "form_token": token},
        headers={"Origin": "https://evil.example"},
        follow_redirects=False,
    )
    assert elsewhere.status_code == 403
    # without the session's form token (a form another site made): refused, nothing stored
    for forged in ({}, {"form_token": "x" * 43}):
        refused = client.post(f"{page}/notes", data={**FORM, **forged}, follow_redirects=False)
        assert refused.status_code == 403 and refused.json()["title"] == "Form token missing"
    signed = {**FORM, "form_token": token}
    bad = client.post(f"{page}/notes", data={**signed, "group": "x" * 101}, follow_redirects=False)
    assert bad.status_code == 422 and bad.json()["errors"][0]["field"] == "group"
    assert client.get(f"{API}/runs/{run_id}/notes", headers=auth(READER)).json()["version"] == 0

    saved = client.post(f"{page}/notes?lang=ru", data=signed, follow_redirects=False)
    assert saved.status_code == 303 and saved.headers["location"] == f"{page}?lang=ru#notes"
    got = client.get(f"{API}/runs/{run_id}/notes", headers=auth(READER)).json()
    assert (got["group"], got["students"], got["conclusions"]) == (
        "MT-32",
        ["А. Иванова", "B. Petrov"],
        "Ours.",
    )
    assert got["by"] == "lab PC"
    shown = client.get(f"{page}?lang=ru").text
    assert "Слова студентов" in shown and "А. Иванова, B. Petrov" in shown
    assert "Записал lab PC" in shown
    # the session still reads only through the API: its cookie writes nothing there
    assert _put(client, run_id, WORDS, None).status_code == 401


def test_the_words_outlive_a_restart_of_the_embedded_server(tmp_path: Path) -> None:
    keys_file = tmp_path / "keys.json"
    keys_file.write_text(json.dumps(KEYS))
    server = Server(tmp_path / "data", keys_file)
    server.start()
    try:
        with httpx.Client(base_url=server.url, headers=auth(WRITER), timeout=30) as http:
            made = http.post(f"{API}/runs", json={"stand": "smts2", "operator": "Ivanova"})
            run_id = made.json()["id"]
            written = http.put(f"{API}/runs/{run_id}/notes", json=WORDS)
            assert written.status_code == 200, written.text
        server.stop()
        server.start()
        with httpx.Client(base_url=server.url, headers=auth(READER), timeout=30) as http:
            assert http.get(f"{API}/runs/{run_id}/notes").json() == written.json()
    finally:
        server.stop()
    assert (tmp_path / "data" / "notes.sqlite").exists()
