"""JSON bodies read strictly (:mod:`schemas.strict_json`): a key given twice, a number
too long to convert or nesting deeper than the limit is refused with 422 naming where.

:class:`StrictJsonRoute` is the route class of the routers that take JSON bodies through
FastAPI (``/runs``, ``/models``); the ingest route parses its own (``routes.readings``)
with :func:`~schemas.strict_json.strict_loads` as the judge of what its fast parser refuses.
"""

from __future__ import annotations

from collections.abc import Callable, Coroutine
from typing import Any

from fastapi import Request, Response
from fastapi.routing import APIRoute

from schemas.strict_json import strict_loads


class _StrictJsonRequest(Request):
    async def json(self) -> Any:
        if not hasattr(self, "_json"):
            self._json = strict_loads(await self.body())
        return self._json


class StrictJsonRoute(APIRoute):
    """A route whose JSON body is read by :func:`strict_loads`."""

    def get_route_handler(self) -> Callable[[Request], Coroutine[Any, Any, Response]]:
        handler = super().get_route_handler()

        async def strict(request: Request) -> Response:
            return await handler(_StrictJsonRequest(request.scope, request.receive))

        return strict
