"""In headless Chromium: a writer signs in, uploads a sketch on the run page's form (its
session's token, the browser's own Origin and multipart body), and sees it on the page,
loaded under the pages' Content-Security-Policy."""

from __future__ import annotations

from pathlib import Path

import httpx

from tests.api.conftest import READER, WRITER, Server, auth
from tests.api.test_sketches import image
from tests.web.test_browser import pytestmark, signed_in  # noqa: F401 (the marks)


def test_a_writer_uploads_a_sketch_on_the_run_page(server: Server, tmp_path: Path) -> None:
    api = f"{server.url}/api/v1"
    made = httpx.post(
        f"{api}/runs", json={"stand": "smts2", "operator": "Ivanova"}, headers=auth(WRITER)
    )
    run_id = made.json()["id"]
    sketch = tmp_path / "specimens.png"
    sketch.write_bytes(image("PNG", (120, 80)))
    with signed_in(server.url, WRITER, tmp_path / "chromium-profile") as (page, refused):
        page.goto(f"{server.url}/runs/{run_id}")
        form = page.locator(f"form[action^='/runs/{run_id}/sketches/4']")
        form.locator("input[name=image]").set_input_files(str(sketch))
        with page.expect_response(lambda r: "/sketches/4?version=1" in r.url) as shown:
            form.locator("button[type=submit]").click()
        assert shown.value.status == 200
        assert shown.value.body() == sketch.read_bytes()
        assert page.url.endswith(f"/runs/{run_id}?lang=en#sketches")
        assert page.locator("img.sketch").count() == 1
        assert refused == []
    listed = httpx.get(f"{api}/runs/{run_id}/sketches", headers=auth(READER)).json()
    assert [(s["item"], s["version"], s["by"]) for s in listed["sketches"]] == [(4, 1, "lab PC")]
