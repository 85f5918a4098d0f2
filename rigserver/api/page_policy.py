"""What a browser may do with the service's answers: ``Content-Security-Policy`` and
``X-Content-Type-Options: nosniff`` on every response, no page framed by another site.

The policies, one place to adjust them:

- the web pages (runs, a run, login) run their own static files only: ``live.js`` and
  ``style.css`` (the run's settings are a JSON data block, never executed);
- the HTML reports are self-contained downloads: their inline styles and SVG plots, no
  script at all;
- the API documentation (``/docs``, ``/redoc``) runs the scripts of this server only
  (Swagger UI and ReDoc from ``/docs-assets``, no inline script); their styles are written
  into ``<style>`` elements as they run, their icons are ``data:`` URLs, and ReDoc builds
  its search index in a ``blob:`` worker (:mod:`rigserver.api.routes.api_docs`);
- anything else (JSON, CSV, files): nothing, should a browser open it as a page.
"""

from __future__ import annotations

from collections.abc import Collection

from starlette.types import ASGIApp, Message, Receive, Scope, Send

_NOT_FRAMED = "base-uri 'none'; frame-ancestors 'none'"
PAGES = (
    "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data:; "
    f"connect-src 'self'; form-action 'self'; {_NOT_FRAMED}"
)
REPORTS = (
    "default-src 'none'; style-src 'unsafe-inline'; img-src data:; form-action 'none'; "
    f"{_NOT_FRAMED}"
)
DOCS = (
    "default-src 'none'; script-src 'self'; style-src 'self' 'unsafe-inline'; "
    "img-src 'self' data:; font-src 'self'; connect-src 'self'; worker-src 'self' blob:; "
    f"form-action 'self'; {_NOT_FRAMED}"
)
OTHER = f"default-src 'none'; form-action 'none'; {_NOT_FRAMED}"


class PagePolicy:
    """ASGI middleware: the policy of each response, chosen by its type and path (the
    module docstring); ``docs`` are the paths of the API documentation, ``api`` the
    prefix whose HTML is a report."""

    def __init__(self, app: ASGIApp, api: str, docs: Collection[str]) -> None:
        self.app = app
        self.api = api
        self.docs = frozenset(docs)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        if scope["path"] in self.docs:
            html = _DOCS
        elif scope["path"].startswith(self.api):
            html = _REPORTS
        else:
            html = _PAGES

        async def with_policy(message: Message) -> None:
            if message["type"] == "http.response.start":
                message["headers"] = _with(message["headers"], html)
            await send(message)

        await self.app(scope, receive, with_policy)


_PAGES, _REPORTS, _DOCS, _OTHER = (p.encode() for p in (PAGES, REPORTS, DOCS, OTHER))
_CSP, _NOSNIFF = b"content-security-policy", (b"x-content-type-options", b"nosniff")


def _with(headers: list[tuple[bytes, bytes]], html: bytes) -> list[tuple[bytes, bytes]]:
    """``headers`` and the policy: ``html`` for a page, :data:`OTHER` for anything else."""
    policy = _OTHER
    for name, value in headers:
        if name == b"content-type":
            if value.startswith(b"text/html"):
                policy = html
            break
    return [*headers, (_CSP, policy), _NOSNIFF]
