"""In headless Chromium (Debian's, driven by Playwright): the login with a read key, the
runs page, a run watched while rigsim posts it (the live chart grows to every row), the PDF
report downloaded.

A real ``rigserver serve`` subprocess (reads need a key); rigsim's lab-PC client posts the
SMTs-2 run from a thread at about 200 times the stand's pace (some 8 s).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import httpx
import pytest

from rigsim.client import LabClient, RunOutcome
from rigsim.simulators import smts2
from tests.api.conftest import READER, WRITER, Server, auth

CHROMIUM = Path("/usr/bin/chromium")
ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(
        not CHROMIUM.exists(),
        reason="the browser test drives Debian's chromium at /usr/bin/chromium: "
        "apt-get install chromium",
    ),
]


def chromium(playwright: Any, profile: Path, **options: Any) -> Any:
    """A headless Chromium context (Debian's, a fresh profile at ``profile``), 1280 x 900."""
    return playwright.chromium.launch_persistent_context(
        str(profile),
        executable_path=str(CHROMIUM),
        headless=True,
        args=ARGS,
        viewport={"width": 1280, "height": 900},
        **options,
    )


@contextmanager
def signed_in(
    url: str, key: str, profile: Path, login: str = "/", **options: Any
) -> Iterator[tuple[Any, list[str]]]:
    """A page of a headless Chromium (:func:`chromium`) signed in with ``key`` on the login
    page at ``login``, and what the pages' Content-Security-Policy blocked (Chromium logs it)."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        context = chromium(playwright, profile, **options)
        try:
            page = context.new_page()
            refused: list[str] = []
            page.on(
                "console",
                lambda m: refused.append(m.text) if "Content Security Policy" in m.text else None,
            )
            page.goto(f"{url}{login}")
            page.fill("input[name=key]", key)
            page.click("form.login button[type=submit]")
            yield page, refused
        finally:
            context.close()


def points(page: Any) -> int:
    return int(page.get_attribute("#live-chart", "data-points"))


def until(condition: Callable[[], bool], seconds: float = 30.0) -> None:
    """Wait for ``condition``, polled from here: a predicate evaluated in the page is an
    eval, which the pages' Content-Security-Policy forbids."""
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.05)


def test_watch_a_run_live_and_download_its_report(server: Server, tmp_path: Path) -> None:
    sim = smts2.simulate(seed=3)
    total = sim.rows("friction")
    outcome: dict[str, RunOutcome | BaseException] = {}

    def lab_pc() -> None:
        try:
            with LabClient(server.url, WRITER) as client:
                outcome["run"] = client.run(sim, speed=sim.duration / 8.0)
        except BaseException as exc:  # reported by the test below
            outcome["run"] = exc

    poster = threading.Thread(target=lab_pc, daemon=True)
    runs = f"{server.url}/api/v1/runs"
    profile = tmp_path / "chromium-profile"
    with signed_in(server.url, READER, profile, accept_downloads=True) as (page, refused):
        # The stand starts posting once the browser is up and signed in: a slow start of
        # the browser (a loaded machine) cannot let the whole run arrive before the page.
        poster.start()
        deadline = time.monotonic() + 20
        while not httpx.get(runs, headers=auth(READER), timeout=5).json()["runs"]:
            assert time.monotonic() < deadline, "the run was not opened"
            time.sleep(0.05)
        page.reload()
        page.click("table.runs a[href^='/runs/']")
        page.wait_for_selector("#live-chart")
        until(lambda: points(page) > 0)
        first = points(page)
        assert first < total, "the run should still be posting"
        until(lambda: points(page) > first)  # the chart grows as batches arrive
        until(lambda: page.get_attribute("#live-status", "data-state") == "ended", 60)
        until(lambda: points(page) == total)
        assert page.text_content("#live-rows") == str(total)
        assert refused == []
        page.screenshot(path=str(tmp_path / "run.png"), full_page=True)
        with page.expect_download() as download:
            page.click("#report-pdf")
        saved = tmp_path / download.value.suggested_filename
        download.value.save_as(saved)
        assert saved.name.endswith("-report-en.pdf")
        assert saved.read_bytes().startswith(b"%PDF-")
    poster.join(timeout=60)
    assert not poster.is_alive()
    result = outcome["run"]
    assert isinstance(result, RunOutcome), result
    assert result.run.rows["friction"] == total
