"""Read sessions of the web pages: a key with the ``read`` scope, given once on the login
page, becomes a cookie, since a browser's EventSource cannot send an Authorization header.

A session grants reads (its cookie is never taken for a write through the API: no form of
another site can post readings with it) and lasts :data:`SESSION_SECONDS`. The one write a
session makes is the student's words on a run, through the run page's own form (checked
to come from this site, and by the key's write scope: :func:`Sessions.key`). Sessions live in the
server's memory: a restart asks for the key again. The cookie holds a random token, never
the key.
"""

from __future__ import annotations

import secrets
import threading
import time
from collections import OrderedDict
from collections.abc import Callable

from rigserver.api.auth import READ, ApiKey

COOKIE = "rig_session"
#: How long a session lasts, s (a lab day).
SESSION_SECONDS = 12 * 3600
#: Sessions kept at once; the oldest are dropped beyond it.
MAX_SESSIONS = 10_000


class Sessions:
    """Tokens of the read sessions, each with the key it reads as (``read`` scope only)."""

    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self._clock = clock
        self._lock = threading.Lock()
        #: token -> (the key read as: scope ``read`` only, the key given, expiry)
        self._open: OrderedDict[str, tuple[ApiKey, ApiKey, float]] = OrderedDict()

    def open(self, key: ApiKey) -> str:
        """A new session reading as ``key``; ``ValueError`` if the key may not read."""
        if not key.allows(READ):
            raise ValueError(f"this key lacks the scope '{READ}'")
        reader = key.model_copy(update={"scopes": frozenset({READ})})
        token = secrets.token_urlsafe(32)
        with self._lock:
            self._open[token] = (reader, key, self._clock() + SESSION_SECONDS)
            while len(self._open) > MAX_SESSIONS:
                self._open.popitem(last=False)
        return token

    def find(self, token: str) -> ApiKey | None:
        """The key of a live session, with the scope ``read`` only (None for an unknown or
        expired token)."""
        found = self._live(token)
        return None if found is None else found[0]

    def key(self, token: str) -> ApiKey | None:
        """The key a live session was opened with, all its scopes: for the page forms of
        this site only (None for an unknown or expired token)."""
        found = self._live(token)
        return None if found is None else found[1]

    def _live(self, token: str) -> tuple[ApiKey, ApiKey, float] | None:
        with self._lock:
            found = self._open.get(token)
            if found is None:
                return None
            if found[2] < self._clock():
                del self._open[token]
                return None
            return found

    def close(self, token: str) -> None:
        with self._lock:
            self._open.pop(token, None)
