"""The run page's form of a sketch (issue 38 item 5): shown to a writer of the run's stand,
taken from the session of such a key with the session's form token and from this site only,
checked as the API checks an upload; the page shows the latest version and links the
earlier ones."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from schemas.sketches import SKETCH_MAX_BYTES
from tests.api.conftest import READER, WRITER, auth, in_process
from tests.api.test_service import open_run
from tests.api.test_sketches import API, image
from tests.api.test_student_notes import form_token
from tests.web.test_entry_forms import login

ITEM = 4  # the SMTs-2 lab's sketch of the specimens


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    with in_process(tmp_path) as c:
        yield c


def files(
    data: bytes, name: str = "specimens.png", media: str = "image/png"
) -> dict[str, tuple[str, bytes, str]]:
    return {"image": (name, data, media)}


def test_the_page_takes_a_sketch_from_a_writers_session_with_its_form_token(
    client: TestClient,
) -> None:
    run_id = open_run(client)
    page, action = f"/runs/{run_id}", f"/runs/{run_id}/sketches/{ITEM}"
    assert (
        f'action="{action}?lang=en" enctype="multipart/form-data"'
        in client.get(page, headers=auth(WRITER)).text
    )
    assert 'name="image"' not in client.get(page, headers=auth(READER)).text
    png = image("PNG")

    # no session: to the login page, nothing stored
    answer = client.post(action, files=files(png), follow_redirects=False)
    assert answer.status_code == 303 and answer.headers["location"].startswith("/login?")
    login(client, READER)  # a session that may read only
    assert 'name="image"' not in client.get(page).text
    assert client.post(action, files=files(png)).status_code == 403

    login(client, WRITER)
    token = form_token(client.get(page).text)
    signed = {"form_token": token}
    elsewhere = client.post(
        action, data=signed, files=files(png), headers={"Origin": "https://evil.example"}
    )
    assert elsewhere.status_code == 403
    for forged in ({}, {"form_token": "x" * 43}):  # a form another site made
        answer = client.post(action, data=forged, files=files(png), follow_redirects=False)
        assert answer.status_code == 403 and answer.json()["title"] == "Form token missing"
    # a file whose name and type say JPEG, its bytes PNG: refused, naming both
    lying = client.post(action, data=signed, files=files(png, "specimens.jpg", "image/jpeg"))
    assert lying.status_code == 415
    assert "says image/jpeg, but the bytes are image/png" in lying.json()["detail"]
    big = client.post(action, data=signed, files=files(b"\x89PNG" + bytes(SKETCH_MAX_BYTES)))
    assert big.status_code == 413 and str(SKETCH_MAX_BYTES) in big.json()["detail"]
    listed = client.get(f"{API}/runs/{run_id}/sketches", headers=auth(READER)).json()
    assert listed == {"sketches": []}

    saved = client.post(f"{action}?lang=ru", data=signed, files=files(png), follow_redirects=False)
    assert saved.status_code == 303 and saved.headers["location"] == f"{page}?lang=ru#sketches"
    again = client.post(action, data=signed, files=files(image("JPEG"), "b.jpg", "image/jpeg"))
    assert again.status_code == 200  # followed back to the page
    got = client.get(f"{API}/runs/{run_id}/sketches/{ITEM}?version=1", headers=auth(READER))
    assert got.content == png
    shown = client.get(f"{page}?lang=ru").text
    assert f'src="{API}/runs/{run_id}/sketches/{ITEM}?version=2"' in shown
    assert f'href="{API}/runs/{run_id}/sketches/{ITEM}?version=1"' in shown
    assert "Эскизы студентов" in shown and "Версия 2, загрузил lab PC" in shown


def test_without_a_session_the_form_takes_no_more_than_any_anonymous_body(
    client: TestClient,
) -> None:
    run_id = open_run(client)
    answer = client.post(
        f"/runs/{run_id}/sketches/{ITEM}", files=files(b"\x89PNG" + bytes(1 << 20))
    )
    assert answer.status_code == 413  # refused before it is read: 64 KiB without a key
