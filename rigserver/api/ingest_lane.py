"""The ingest route without the router: ``POST {prefix}/runs/{run_id}/readings`` handed
straight to its endpoint.

Lab PCs post a reading at a time, thousands a second across a lab. For such a post, the
router's own layers (the exception middleware, the exit stack, matching the path against
the API's routes, wrapping the endpoint's request and response) cost about a fifth of the
service's work (docs/speed.md). This middleware, the innermost of the service's own (the
key, the rate and the body's size are checked before it), knows the one path by its shape
and calls the route's endpoint itself. An exception becomes its answer through the app's
own handlers, as Starlette's exception middleware would do it; one without a handler goes
on, as there, to the server-error middleware (500).

Everything else, the same path with another method among it, goes on to the router, where
the route stays registered: the OpenAPI document, a 405 and a trailing slash's answer are
as before.
"""

from __future__ import annotations

import inspect
from collections.abc import Awaitable, Callable, Mapping
from typing import Any

from fastapi.concurrency import run_in_threadpool
from starlette.requests import Request
from starlette.responses import Response
from starlette.types import ASGIApp, Receive, Scope, Send

Endpoint = Callable[[Request], Awaitable[Response]]
#: an app's exception handlers, by exception class (or status code: not used here)
Handlers = Mapping[Any, Callable[[Request, Exception], Any]]


class IngestLane:
    """ASGI middleware: ``POST`` to ``path`` (one ``{run_id}`` in it) to ``endpoint``.

    Parameters
    ----------
    app : ASGI app
        Where every other request goes.
    path : str
        The route's full path, e.g. ``/api/v1/runs/{run_id}/readings``.
    endpoint : callable
        The route's endpoint: takes the :class:`Request` (``path_params`` has ``run_id``),
        returns the :class:`Response`.
    handlers : mapping
        The app's exception handlers (``FastAPI.exception_handlers``), read when an
        exception is raised, so handlers added later count.
    """

    def __init__(self, app: ASGIApp, path: str, endpoint: Endpoint, handlers: Handlers) -> None:
        head, found, tail = path.partition("{run_id}")
        if not found or "{" in head + tail:
            raise ValueError(f"the ingest path {path!r} needs exactly one {{run_id}}")
        self.app = app
        self.head = head
        self.tail = tail
        self.endpoint = endpoint
        self.handlers = handlers

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        run_id = self._run_id(scope)
        if run_id is None:
            await self.app(scope, receive, send)
            return
        scope["path_params"] = {"run_id": run_id}
        request = Request(scope, receive, send)
        try:
            response = await self.endpoint(request)
        except Exception as exc:
            handler = self._handler(exc)
            if handler is None:
                raise
            if inspect.iscoroutinefunction(handler):
                response = await handler(request, exc)
            else:
                response = await run_in_threadpool(handler, request, exc)
        await response(scope, receive, send)

    def _run_id(self, scope: Scope) -> str | None:
        """The run id of a post to the ingest path, else None."""
        if scope["type"] != "http" or scope["method"] != "POST":
            return None
        path: str = scope["path"]
        if not (path.startswith(self.head) and path.endswith(self.tail)):
            return None
        run_id = path[len(self.head) : len(path) - len(self.tail)]
        return run_id if run_id and "/" not in run_id else None

    def _handler(self, exc: Exception) -> Callable[[Request, Exception], Any] | None:
        """The app's handler of ``exc``'s nearest class, but the server error's
        (``Exception``: the server-error middleware's, outside)."""
        for kind in type(exc).__mro__:
            if kind is Exception:
                return None
            handler = self.handlers.get(kind)
            if handler is not None:
                return handler
        return None
