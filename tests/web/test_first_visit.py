"""What a new user's browser meets first (issue 39, item 11): an icon, and a way to the
login from every page."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from rigserver.api.app import create_app
from rigserver.api.auth import ApiKey
from rigserver.api.settings import Settings
from rigserver.storage import MemoryStore
from schemas.stands import configure_stands
from tests.api.conftest import KEYS


@pytest.fixture(params=[False, True], ids=["keys", "public-reads"])
def client(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[TestClient]:
    settings = Settings(data_dir=tmp_path, public_reads=request.param)
    app = create_app(
        settings, MemoryStore(), [ApiKey.model_validate(k) for k in KEYS], configure_stands()
    )
    with TestClient(app) as c:
        yield c


def test_the_icon_is_served_without_a_key(client: TestClient) -> None:
    r = client.get("/favicon.ico")
    assert r.status_code == 200
    assert r.headers["content-type"].startswith("image/svg+xml")
    assert r.content.startswith(b"<svg") and b"<script" not in r.content
    assert '<link rel="icon" href="/favicon.ico"' in client.get("/login").text


@pytest.mark.parametrize("lang", ["en", "ru"])
def test_every_page_links_to_the_login_until_signed_in(client: TestClient, lang: str) -> None:
    login = client.get(f"/login?lang={lang}")
    assert 'id="login"' not in login.text  # the login page does not link to itself
    for path in ("/", "/series"):
        page = client.get(f"{path}?lang={lang}")  # public reads: the page; else the login
        assert page.status_code == 200
        if "<form" not in page.text or 'action="/login' not in page.text:
            assert f'<a href="/login?lang={lang}" id="login">' in page.text
