"""What a browser may do with the service's answers: ``Content-Security-Policy`` and
``X-Content-Type-Options: nosniff`` on every response, no page framed by another site.

The policies, one place to adjust them:

- the web pages (runs, a run, login) run their own static files only: ``live.js`` and
  ``style.css`` (the run's settings are a JSON data block, never executed);
- the HTML reports are self-contained downloads: their inline styles and SVG plots, no
  script at all;
- the API documentation (``/docs``, ``/redoc``) runs scripts and styles of this server
  (and, while FastAPI's pages load them from CDNs, of :data:`DOCS_ELSEWHERE`); an inline
  script of the page (Swagger UI's start-up) runs only with its hash, taken from the page
  the server itself renders (no client's input reaches it);
- anything else (JSON, CSV, files): nothing, should a browser open it as a page.
"""

from __future__ import annotations

import base64
import hashlib
import re
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
#: Where the documentation pages load from besides this server: FastAPI's pages load
#: Swagger UI and ReDoc from CDNs; once they are served by this server, these go.
DOCS_ELSEWHERE = {
    "script-src": "https://cdn.jsdelivr.net",
    "style-src": "https://cdn.jsdelivr.net https://fonts.googleapis.com",
    "font-src": "https://fonts.gstatic.com",
    "img-src": "https://fastapi.tiangolo.com https://cdn.redoc.ly",
}
DOCS = (
    "default-src 'none'; script-src 'self'{hashes} {script-src}; "
    "style-src 'self' 'unsafe-inline' {style-src}; img-src 'self' data: {img-src}; "
    "font-src 'self' {font-src}; connect-src 'self'; worker-src 'self' blob:; "
    f"form-action 'self'; {_NOT_FRAMED}"
)
OTHER = f"default-src 'none'; form-action 'none'; {_NOT_FRAMED}"

_INLINE_SCRIPT = re.compile(rb"<script>(.*?)</script>", re.DOTALL)


def docs_policy(page: bytes) -> str:
    """:data:`DOCS` with the hash of every inline script of ``page``."""
    hashes = "".join(
        f" 'sha256-{base64.b64encode(hashlib.sha256(script).digest()).decode()}'"
        for script in _INLINE_SCRIPT.findall(page)
    )
    return DOCS.format(hashes=hashes, **DOCS_ELSEWHERE)


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
            await self._documentation(scope, receive, send)
            return
        html = _REPORTS if scope["path"].startswith(self.api) else _PAGES

        async def with_policy(message: Message) -> None:
            if message["type"] == "http.response.start":
                message["headers"] = _with(message["headers"], html)
            await send(message)

        await self.app(scope, receive, with_policy)

    async def _documentation(self, scope: Scope, receive: Receive, send: Send) -> None:
        """The documentation's answer held until its body is whole, to hash its scripts."""
        start: Message = {}
        body = bytearray()

        async def held(message: Message) -> None:
            nonlocal start
            if message["type"] != "http.response.body":
                start = message
                return
            body.extend(message.get("body", b""))
            if message.get("more_body", False):
                return
            start["headers"] = _with(start["headers"], docs_policy(bytes(body)).encode())
            await send(start)
            await send({"type": "http.response.body", "body": bytes(body)})

        await self.app(scope, receive, held)


_PAGES, _REPORTS, _OTHER = (policy.encode() for policy in (PAGES, REPORTS, OTHER))
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
