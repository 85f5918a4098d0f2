"""API keys with scopes: ``read``, ``write:<stand kind>`` (or ``write:*``).

Keys come from the lab's keys file (a JSON list of ``{"key": ..., "scopes": [...]}``) and
are compared in constant time. A key never appears in a log line or an error message.
"""

from __future__ import annotations

import hashlib
import hmac
from collections.abc import Iterable
from functools import cached_property
from pathlib import Path

from pydantic import BaseModel, Field, TypeAdapter

from schemas.strict_json import strict_loads

READ = "read"


def write_scope(stand: str) -> str:
    return f"write:{stand}"


class ApiKey(BaseModel):
    key: str = Field(min_length=16, repr=False)
    scopes: frozenset[str]
    name: str = ""

    @cached_property
    def fingerprint(self) -> str:
        """A name of the key that does not reveal it (a hash): what the rate limit, the
        ingest queue's shares and the Idempotency-Keys are kept by."""
        return hashlib.sha256(b"rig api key\0" + self.key.encode()).hexdigest()[:24]

    def allows(self, scope: str) -> bool:
        if scope in self.scopes:
            return True
        return scope.startswith("write:") and "write:*" in self.scopes


_KEYS = TypeAdapter(list[ApiKey])


def load_keys(path: Path) -> list[ApiKey]:
    """Read a keys file; a bad file fails loudly at start, naming the problem (not the keys)."""
    return _KEYS.validate_python(strict_loads(path.read_bytes()))


class Keyring:
    """The configured keys; finds the one a request presents, in constant time per key."""

    def __init__(self, keys: Iterable[ApiKey]) -> None:
        self._keys = [(k.key.encode(), k) for k in keys]

    def find(self, presented: str) -> ApiKey | None:
        token = presented.encode()
        found = None
        for secret, key in self._keys:
            if hmac.compare_digest(secret, token):
                found = key
        return found
