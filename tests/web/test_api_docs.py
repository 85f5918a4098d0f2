"""In headless Chromium with the network cut: ``/docs`` (Swagger UI) and ``/redoc`` (ReDoc)
render every operation of the OpenAPI document from the service's own assets, no request
leaves the loopback, and the pages run under the Content-Security-Policy they are sent with
(scripts from the server only: no inline script, no eval).

A real ``rigserver serve`` subprocess (the ``server`` fixture)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

import httpx
import pytest

from rigserver.api.page_policy import DOCS
from tests.api.conftest import Server
from tests.web import test_browser
from tests.web.test_browser import chromium

pytestmark = test_browser.pytestmark  # slow; needs Debian's chromium

#: Records the page's CSP violations (an init script runs outside the page's policy).
RECORD_VIOLATIONS = """
window.cspViolations = [];
document.addEventListener("securitypolicyviolation", (e) => {
  window.cspViolations.push(e.violatedDirective + " " + e.blockedURI);
});
"""
#: ReDoc's footer logo, from its CDN: blocked by the page's policy before any request.
REDOC_LOGO = "img-src https://cdn.redoc.ly/redoc/logo-mini.svg"


def summaries(server: Server) -> list[str]:
    """Every operation's summary, as the OpenAPI document gives them."""
    spec = httpx.get(f"{server.url}/openapi.json", timeout=10).json()
    return sorted(op["summary"] for ops in spec["paths"].values() for op in ops.values())


@pytest.fixture
def offline_page(server: Server, tmp_path: Path) -> Iterator[tuple[Any, list[str]]]:
    """A Chromium page that reaches only the server, and the requests it tried elsewhere."""
    from playwright.sync_api import Route, sync_playwright

    elsewhere: list[str] = []

    def loopback_only(route: Route) -> None:
        if urlsplit(route.request.url).hostname == "127.0.0.1":
            route.continue_()
        else:
            elsewhere.append(route.request.url)
            route.abort("internetdisconnected")

    with sync_playwright() as playwright:
        context = chromium(playwright, tmp_path / "chromium-profile")
        try:
            context.route("**/*", loopback_only)
            context.add_init_script(RECORD_VIOLATIONS)
            yield context.new_page(), elsewhere
        finally:
            context.close()


@pytest.mark.parametrize(
    ("path", "operation", "allowed"),
    [
        ("/docs", ".opblock-summary-description", set()),  # Swagger UI: a summary per block
        ("/redoc", "[data-section-id*='operation/'] h2", {REDOC_LOGO}),  # ReDoc: a heading
    ],
)
def test_the_docs_page_renders_every_operation_offline(
    server: Server,
    offline_page: tuple[Any, list[str]],
    path: str,
    operation: str,
    allowed: set[str],
) -> None:
    page, elsewhere = offline_page
    response = page.goto(f"{server.url}{path}")
    assert response.headers["content-security-policy"] == DOCS
    page.wait_for_selector(operation)
    shown = page.locator(operation).all_text_contents()
    assert sorted(h.strip() for h in shown) == summaries(server)
    assert set(page.evaluate("window.cspViolations")) <= allowed
    assert elsewhere == []
