"""Read sessions of the web pages: a key with the ``read`` scope, given once on the login
page, becomes a cookie, since a browser's EventSource cannot send an Authorization header.

A session grants reads (its cookie is never taken for a write through the API: no form of
another site can post readings with it) and lasts :data:`SESSION_SECONDS`. A session writes only
through the pages' own forms (the student's words, a new run, the rows typed at the stand,
finish and abort), each checked to come from this site (its ``Origin``) and to carry the
session's own form token (:func:`Sessions.form_token`), and by the key's write scope
(:func:`Sessions.key`). Sessions live in the
server's memory: a restart asks for the key again. The cookie holds a random token, never
the key.
"""

from __future__ import annotations

import hmac
import secrets
import threading
import time
from collections import OrderedDict
from collections.abc import Callable
from typing import NamedTuple

from rigserver.api.auth import READ, ApiKey

COOKIE = "rig_session"
#: How long a session lasts, s (a lab day).
SESSION_SECONDS = 12 * 3600
#: Sessions kept at once; the oldest are dropped beyond it.
MAX_SESSIONS = 10_000


class _Session(NamedTuple):
    reader: ApiKey  # the key read as: scope ``read`` only
    key: ApiKey  # the key given
    expiry: float
    form_token: str  # what the session's forms carry against cross-site requests


class Sessions:
    """Tokens of the read sessions, each with the key it reads as (``read`` scope only)."""

    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self._clock = clock
        self._lock = threading.Lock()
        self._open: OrderedDict[str, _Session] = OrderedDict()

    def open(self, key: ApiKey) -> str:
        """A new session reading as ``key``; ``ValueError`` if the key may not read."""
        if not key.allows(READ):
            raise ValueError(f"this key lacks the scope '{READ}'")
        reader = key.model_copy(update={"scopes": frozenset({READ})})
        token = secrets.token_urlsafe(32)
        with self._lock:
            self._open[token] = _Session(
                reader, key, self._clock() + SESSION_SECONDS, secrets.token_urlsafe(32)
            )
            while len(self._open) > MAX_SESSIONS:
                self._open.popitem(last=False)
        return token

    def find(self, token: str) -> ApiKey | None:
        """The key of a live session, with the scope ``read`` only (None for an unknown or
        expired token)."""
        found = self._live(token)
        return None if found is None else found.reader

    def key(self, token: str) -> ApiKey | None:
        """The key a live session was opened with, all its scopes: for the page forms of
        this site only (None for an unknown or expired token)."""
        found = self._live(token)
        return None if found is None else found.key

    def form_token(self, token: str) -> str | None:
        """The token the session's forms carry (a hidden field, or the ``X-Rig-Form``
        header of the page's own requests): another site's page cannot read it (None for an
        unknown or expired session)."""
        found = self._live(token)
        return None if found is None else found.form_token

    def form_token_holds(self, token: str, given: str) -> bool:
        """Whether ``given`` is the form token of the live session ``token`` (compared in
        constant time)."""
        expected = self.form_token(token)
        return expected is not None and hmac.compare_digest(
            expected.encode(), given.encode("utf-8", "replace")
        )

    def _live(self, token: str) -> _Session | None:
        with self._lock:
            found = self._open.get(token)
            if found is None:
                return None
            if found.expiry < self._clock():
                del self._open[token]
                return None
            return found

    def close(self, token: str) -> None:
        with self._lock:
            self._open.pop(token, None)
