"""Refuse request bodies over a size limit with 413, before reading them into memory, and
bodies that take longer than a time limit to arrive with 408.

The size limit is the request's own (``limit_of``): a request with an API key may send
``max_bytes``; one without a key (the login form, a calculator of public reads) only what
its route takes, so no unauthenticated client can make the service hold megabytes. A
``Content-Length`` over the limit is answered before any byte of the body is read; a
chunked body is cut at the limit.

The time limit runs from the first read of the body to its last byte, whatever the pace
in between: a client trickling a byte now and then holds what its request holds (an
ingest slot, a worker) for ``timeout`` seconds at most. Once the body is in, the wait for
the client's disconnect (a streamed answer's) is not timed.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any

from starlette.types import ASGIApp, Message, Receive, Scope, Send

from rigserver.api.problems import problem_response
from schemas.problems import Problem


class BodyLimit:
    """ASGI middleware: 413 when Content-Length or the streamed body exceeds the request's
    limit (``limit_of(scope)``, else ``max_bytes``); 408 when the body has not arrived
    ``timeout`` seconds after it was first asked for."""

    def __init__(
        self,
        app: ASGIApp,
        max_bytes: int,
        timeout: float,
        limit_of: Callable[[Scope], int] | None = None,
    ) -> None:
        self.app = app
        self.max_bytes = max_bytes
        self.timeout = timeout
        self.limit_of = limit_of
        self.watch = _Watch(timeout)

    def _too_large(self, limit: int) -> Problem:
        return Problem(
            title="Request body too large",
            status=413,
            detail=f"the body exceeds {limit} bytes; send smaller batches"
            if limit == self.max_bytes
            else f"the body exceeds {limit} bytes, the largest this server takes here",
        )

    def _too_slow(self, seen: int) -> Problem:
        return Problem(
            title="Request body too slow",
            status=408,
            detail=f"{seen} bytes of the body arrived in {self.timeout:g} s, the time a body "
            "may take; send it at once",
        )

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        limit = self.max_bytes if self.limit_of is None else self.limit_of(scope)
        for name, value in scope.get("headers", []):
            if name == b"content-length" and value.isdigit() and _over(value, limit):
                response = problem_response(self._too_large(limit), {"Connection": "close"})
                await response(scope, receive, send)
                return
        seen = 0
        body = _Body()

        async def counted() -> Message:
            nonlocal seen
            if body.done:  # the body is in: what follows is a wait for the disconnect
                return await receive()
            if not body.deadline:
                self.watch.add(body)
            message = await body.read(receive)
            if message["type"] == "http.request":
                seen += len(message.get("body", b""))
                if seen > limit:
                    raise _BodyTooLarge
                if not message.get("more_body", False):
                    self.watch.done(body)
            return message

        try:
            await self.app(scope, counted, send)
        except _BodyTooLarge:
            response = problem_response(self._too_large(limit), {"Connection": "close"})
            await response(scope, receive, send)
        except _BodyTooSlow:
            response = problem_response(self._too_slow(seen), {"Connection": "close"})
            await response(scope, receive, send)
        finally:
            self.watch.done(body)


def _over(length: bytes, limit: int) -> bool:
    """Whether a Content-Length of ASCII digits exceeds ``limit`` (no int of 5 000 digits)."""
    return len(length.lstrip(b"0")) > len(str(limit)) or int(length) > limit


class _Body:
    """One body being read: its deadline (0 until its first read), the task waiting for
    it, whether its time ran out."""

    __slots__ = ("deadline", "done", "expired", "waiting")

    def __init__(self) -> None:
        self.deadline = 0.0
        self.done = self.expired = False
        self.waiting: asyncio.Task[Any] | None = None

    async def read(self, receive: Receive) -> Message:
        """The next message; :class:`_BodyTooSlow` once the body's time has run out."""
        if self.expired:
            raise _BodyTooSlow
        self.waiting = asyncio.current_task()
        try:
            return await receive()
        except asyncio.CancelledError:
            if self.expired and self.waiting is not None and self.waiting.uncancel() == 0:
                raise _BodyTooSlow from None
            raise
        finally:
            self.waiting = None

    def expire(self) -> None:
        self.expired = True
        if self.waiting is not None:
            self.waiting.cancel()


class _Watch:
    """The bodies being read. One task, running while there are any, wakes every
    ``period`` s and expires the overdue (``asyncio.timeout`` around each read cost about
    18 µs per post, this about 4 µs)."""

    def __init__(self, timeout: float) -> None:
        self.timeout = timeout
        self.period = min(1.0, timeout / 4)
        self._reading: dict[int, _Body] = {}
        self._sweeper: asyncio.Task[None] | None = None

    def add(self, body: _Body) -> None:
        loop = asyncio.get_running_loop()
        body.deadline = loop.time() + self.timeout
        self._reading[id(body)] = body
        if self._sweeper is None or self._sweeper.get_loop() is not loop:
            self._sweeper = loop.create_task(self._sweep())

    def done(self, body: _Body) -> None:
        body.done = True
        self._reading.pop(id(body), None)

    async def _sweep(self) -> None:
        loop = asyncio.get_running_loop()
        try:
            while self._reading:
                await asyncio.sleep(self.period)
                now = loop.time()
                for key, body in list(self._reading.items()):
                    if body.deadline <= now:
                        del self._reading[key]
                        body.expire()
        finally:
            self._sweeper = None


# Not Exceptions: FastAPI answers any Exception raised while it reads a route's body with
# a 400 ("There was an error parsing the body"), and Starlette's handlers catch Exceptions;
# these pass both, to the middleware that answers them.


class _BodyTooLarge(BaseException):
    pass


class _BodyTooSlow(BaseException):
    pass
