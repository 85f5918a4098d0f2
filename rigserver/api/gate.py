"""Authenticate first: under the API's prefix, a request that needs a key and presents
none, or presents one this server does not know, is answered 401 before anything else is
said or read (its body, its parameters, whether the run it names exists).

Which routes need a key is read off the routes themselves: a route with
:data:`~rigserver.api.deps.WriteAccess` always, one with
:data:`~rigserver.api.deps.ReadAccess` unless reads are public, a route with neither never.
A path that is no route needs a key as a read does, so a made-up run id and a real one
are answered alike. The route then parses the request and checks the key's scope (403).
"""

from __future__ import annotations

import re
from collections import defaultdict
from collections.abc import Sequence

from fastapi.routing import APIRoute
from starlette.routing import BaseRoute
from starlette.types import ASGIApp, Receive, Scope, Send

from rigserver.api.deps import Services, caller_in, key_required, require_key, require_read
from rigserver.api.problems import ApiProblem, problem_response


class Gate:
    """ASGI middleware: 401 for a request under ``prefix`` without the key it needs."""

    def __init__(
        self, app: ASGIApp, services: Services, prefix: str, routes: Sequence[BaseRoute]
    ) -> None:
        self.app = app
        self.services = services
        self.prefix = prefix
        self.free = free_routes(routes, prefix, public_reads=services.settings.public_reads)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http" and scope["path"].startswith(self.prefix):
            try:
                caller = caller_in(scope, self.services)
                if caller is None and not self._free(scope["method"], scope["path"]):
                    raise key_required()
            except ApiProblem as refused:
                response = problem_response(refused.problem, refused.headers)
                await response(scope, receive, send)
                return
        await self.app(scope, receive, send)

    def _free(self, method: str, path: str) -> bool:
        pattern = self.free.get(method)
        return pattern is not None and pattern.match(path) is not None


def free_routes(
    routes: Sequence[BaseRoute], prefix: str, *, public_reads: bool
) -> dict[str, re.Pattern[str]]:
    """Per method, one pattern of the paths that need no key, of the ``routes`` of the
    API's routers (their paths under ``prefix``)."""
    paths: defaultdict[str, list[str]] = defaultdict(list)
    for route in routes:
        if not isinstance(route, APIRoute):
            continue
        calls = {dependency.call for dependency in route.dependant.dependencies}
        if require_key in calls or (require_read in calls and not public_reads):
            continue
        # one alternation per method: the groups of the path parameters made anonymous
        path = re.sub(r"\(\?P<\w+>", "(?:", route.path_regex.pattern)
        path = "^" + re.escape(prefix) + path.removeprefix("^")
        for method in route.methods or ():
            paths[method].append(path)
    return {method: re.compile("|".join(found)) for method, found in paths.items()}
