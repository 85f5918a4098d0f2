"""What the routes are handed: the store, the stands, the keys, and the caller's key.

The dependencies are ``async def`` although they never wait: FastAPI runs a plain ``def``
dependency in its thread pool, a thread hop per request.
"""

from __future__ import annotations

import threading
from collections import OrderedDict, defaultdict
from dataclasses import dataclass, field
from typing import Annotated

from fastapi import Depends, Request

from rigserver.api.auth import READ, ApiKey, Keyring, write_scope
from rigserver.api.ingest_queue import IngestQueue
from rigserver.api.problems import ApiProblem
from rigserver.api.results_cache import ResultsCache
from rigserver.api.sessions import COOKIE, Sessions
from rigserver.api.settings import Settings
from rigserver.storage.base import RunStore
from schemas.runs import Run
from schemas.stands import Stand, StandKind

#: Runs whose stand the service remembers (the stand of a run never changes).
RUN_STANDS = 4096
#: Runs whose last computed results the service keeps (rigserver.api.results_cache).
RESULTS_KEPT = 128


@dataclass
class Services:
    settings: Settings
    store: RunStore
    stands: dict[StandKind, Stand]
    keyring: Keyring
    sessions: Sessions = field(default_factory=Sessions)
    run_locks: defaultdict[str, threading.Lock] = field(
        default_factory=lambda: defaultdict(threading.Lock)
    )
    #: set when the server is asked to stop: long requests (live streams) end by themselves
    stopping: threading.Event = field(default_factory=threading.Event)
    #: run id -> its stand as its configuration sets it, the most recently posted-to last
    run_stands: OrderedDict[str, Stand] = field(default_factory=OrderedDict)
    ingest: IngestQueue = field(init=False)
    results: ResultsCache = field(init=False)

    def __post_init__(self) -> None:
        self.results = ResultsCache(
            workers=self.settings.results_workers,
            runs=RESULTS_KEPT,
            retry_after=self.settings.retry_after,
        )
        self.ingest = IngestQueue(
            self.store,
            self.run_locks.__getitem__,
            max_batches=self.settings.ingest_queue,
            max_bytes=self.settings.ingest_queue_bytes,
            retry_after=self.settings.retry_after,
        )

    def stand_of(self, run: Run) -> Stand:
        """The run's stand as its configuration snapshot sets it (the gauges' unit)."""
        return self.stands[run.stand].for_run(run.configuration)

    def remember_stand(self, run_id: str, stand: Stand) -> None:
        self.run_stands[run_id] = stand
        if len(self.run_stands) > RUN_STANDS:
            self.run_stands.popitem(last=False)


def services_of(request: Request) -> Services:
    services: Services = request.app.state.services
    return services


async def get_services(request: Request) -> Services:
    return services_of(request)


ServicesDep = Annotated[Services, Depends(get_services)]


#: Methods that only read: the only ones a session cookie is taken for.
_READING = frozenset({"GET", "HEAD"})


def caller_of(request: Request, services: Services) -> ApiKey | None:
    """The key the request presents (None without one); 401 for a key not configured.

    Without an Authorization header, a read may present a session cookie
    (:mod:`rigserver.api.sessions`); it reads as its key, with the scope ``read`` only."""
    header = request.headers.get("authorization", "")
    scheme, _, token = header.partition(" ")
    if scheme.lower() != "bearer" or not token:
        session = request.cookies.get(COOKIE)
        if session and request.method in _READING:
            return services.sessions.find(session)
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


async def get_caller(request: Request, services: ServicesDep) -> ApiKey | None:
    return caller_of(request, services)


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


async def require_read(services: ServicesDep, caller: CallerDep) -> None:
    if not services.settings.public_reads:
        require_scope(caller, READ)


ReadAccess = Depends(require_read)


def require_write(caller: ApiKey | None, stand: StandKind) -> None:
    require_scope(caller, write_scope(stand.value))
