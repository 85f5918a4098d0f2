"""What the routes are handed: the store, the stands, the keys, and the caller's key."""

from __future__ import annotations

import threading
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Annotated

from fastapi import Depends, Request

from rigserver.api.auth import READ, ApiKey, Keyring, write_scope
from rigserver.api.problems import ApiProblem
from rigserver.api.settings import Settings
from rigserver.storage.base import RunStore
from schemas.stands import Stand, StandKind


@dataclass
class Services:
    settings: Settings
    store: RunStore
    stands: dict[StandKind, Stand]
    keyring: Keyring
    run_locks: defaultdict[str, threading.Lock] = field(
        default_factory=lambda: defaultdict(threading.Lock)
    )


def get_services(request: Request) -> Services:
    services: Services = request.app.state.services
    return services


ServicesDep = Annotated[Services, Depends(get_services)]


def get_caller(request: Request, services: ServicesDep) -> ApiKey | None:
    header = request.headers.get("authorization", "")
    scheme, _, token = header.partition(" ")
    if scheme.lower() != "bearer" or not token:
        return None
    key = services.keyring.find(token.strip())
    if key is None:
        raise ApiProblem(
            401,
            "Unknown API key",
            "the key in the Authorization header is not configured on this server",
            headers={"WWW-Authenticate": "Bearer"},
        )
    return key


CallerDep = Annotated[ApiKey | None, Depends(get_caller)]


def require_scope(caller: ApiKey | None, scope: str) -> None:
    """401 without a key, 403 when the key lacks ``scope`` (the message names it)."""
    if caller is None:
        raise ApiProblem(
            401,
            "API key required",
            f"send 'Authorization: Bearer <key>' with a key that has the scope '{scope}'",
            headers={"WWW-Authenticate": "Bearer"},
        )
    if not caller.allows(scope):
        raise ApiProblem(403, "Scope missing", f"this key lacks the scope '{scope}'")


def require_read(services: ServicesDep, caller: CallerDep) -> None:
    if not services.settings.public_reads:
        require_scope(caller, READ)


ReadAccess = Depends(require_read)


def require_write(caller: ApiKey | None, stand: StandKind) -> None:
    require_scope(caller, write_scope(stand.value))
