"""The series page in headless Chromium: the runs, the statistics and the overlay plot in
Russian, refreshed while a member run is open, and still once it has finished."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from rigsim.simulators import simulate
from rigsim.simulators.smts2 import Smts2Settings
from schemas.stands import StandKind
from tests.api.conftest import WRITER, Server, auth, served
from tests.reports.simulated import post, series_of
from tests.web.test_browser import ARGS, CHROMIUM, until

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(not CHROMIUM.exists(), reason="needs Debian's chromium"),
]


@pytest.fixture
def public_server(tmp_path: Path) -> Iterator[Server]:
    with served(tmp_path, public_reads=True) as srv:
        yield srv


def test_series_page_refreshes_while_a_run_is_open(public_server: Server, tmp_path: Path) -> None:
    from playwright.sync_api import sync_playwright

    with httpx.Client(base_url=public_server.url, timeout=60) as http:
        sims = [
            simulate(StandKind.SMTS2, Smts2Settings(revolutions=2000.0), seed=60 + i)
            for i in range(3)
        ]
        finished = [post(http, sim, WRITER) for sim in sims[:2]]
        open_run = post(http, sims[2], WRITER, finish=False)
        series_id = series_of(
            http, WRITER, [*finished, open_run], name="Повторные испытания", purpose="repeatability"
        )

        with sync_playwright() as playwright:
            browser = playwright.chromium.launch(
                executable_path=str(CHROMIUM), headless=True, args=ARGS
            )
            try:
                page = browser.new_page(viewport={"width": 1280, "height": 900})
                page.goto(f"{public_server.url}/series/{series_id}?lang=ru")
                body = page.locator("#series-body")
                assert body.get_attribute("data-refresh") == "5"  # a member run is open
                statistics = page.locator("#series-statistics")
                assert "Результат" in statistics.inner_text()
                assert page.locator("#series-runs tbody tr, #series-runs tr").count() >= 3
                overlay = page.locator("#series-body figure img").first  # an SVG as an image
                until(lambda: overlay.evaluate("i => i.complete && i.naturalWidth > 0"))
                page.screenshot(path=str(tmp_path / "series-ru.png"), full_page=True)

                answer = http.post(f"/api/v1/runs/{open_run}/finish", headers=auth(WRITER))
                assert answer.status_code == 200, answer.text
                # The next refresh (every 5 s) shows the run finished and stops refreshing.
                until(lambda: body.get_attribute("data-refresh") == "0", seconds=20)
                assert body.get_attribute("data-updated")
                assert "идёт" not in page.locator("#series-runs").inner_text()
            finally:
                browser.close()
