"""Request rate limit per client: a token bucket per API key (or per address without one).

Off unless ``rate_limit`` is set (requests per second, with ``rate_burst`` at once). A
request beyond it is answered 429 with ``Retry-After`` before its body is read. A bucket
is the authenticated key's (by its fingerprint, never the key itself); a request without a
key this server knows (none, a random token, a session cookie gone stale) takes from its
address's bucket, so no header makes a new client. The least recently seen are forgotten
beyond :data:`MAX_CLIENTS`.
"""

from __future__ import annotations

import math
import threading
import time
from collections import OrderedDict

from starlette.types import ASGIApp, Receive, Scope, Send

from rigserver.api.deps import Services, client_of
from rigserver.api.problems import problem_response
from schemas.problems import Problem

MAX_CLIENTS = 10_000


class RateLimit:
    """ASGI middleware: ``rate`` requests per second per client, ``burst`` at once."""

    def __init__(self, app: ASGIApp, services: Services, rate: float, burst: int) -> None:
        self.app = app
        self.services = services
        self.rate = rate
        self.burst = burst
        self._lock = threading.Lock()
        #: client -> (tokens, time of the last refill)
        self._buckets: OrderedDict[str, tuple[float, float]] = OrderedDict()

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        wait = self._take(client_of(scope, self.services))
        if wait > 0:
            problem = Problem(
                title="Too many requests",
                status=429,
                detail=f"this client may send {self.rate:g} requests per second "
                f"({self.burst} at once); retry in {math.ceil(wait)} s",
            )
            response = problem_response(problem, {"Retry-After": str(math.ceil(wait))})
            await response(scope, receive, send)
            return
        await self.app(scope, receive, send)

    def _take(self, client: str) -> float:
        """Take a token from the client's bucket: 0, or the seconds until there is one."""
        now = time.monotonic()
        with self._lock:
            tokens, then = self._buckets.pop(client, (float(self.burst), now))
            tokens = min(float(self.burst), tokens + (now - then) * self.rate)
            wait = 0.0 if tokens >= 1.0 else (1.0 - tokens) / self.rate
            self._buckets[client] = (tokens - 1.0 if wait == 0.0 else tokens, now)
            if len(self._buckets) > MAX_CLIENTS:
                self._buckets.popitem(last=False)
        return wait
