"""What the routes are handed: the store, the stands, the keys, and the caller's key.

The dependencies are ``async def`` although they never wait: FastAPI runs a plain ``def``
dependency in its thread pool, a thread hop per request.
"""

from __future__ import annotations

import hashlib
import threading
from collections import OrderedDict, defaultdict
from dataclasses import dataclass, field
from typing import Annotated, cast

from fastapi import Depends, Path, Query, Request
from starlette.requests import cookie_parser
from starlette.types import Scope

from rigserver.api.auth import READ, ApiKey, Keyring, write_scope
from rigserver.api.import_slots import ImportSlots
from rigserver.api.ingest_queue import IngestQueue
from rigserver.api.problems import ApiProblem
from rigserver.api.report_files import ReportFiles
from rigserver.api.report_pool import RenderPool
from rigserver.api.results_cache import ResultsCache
from rigserver.api.series_export import SeriesExports
from rigserver.api.sessions import COOKIE, Sessions
from rigserver.api.settings import Settings
from rigserver.reports.i18n import Lang, negotiate
from rigserver.storage.base import RunStore
from rigserver.storage.notes import NotesStore, SqliteNotes
from rigserver.storage.series import SeriesStore
from rigserver.storage.sketches import SketchStore, SqliteSketches
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
    series: SeriesStore
    #: the student's own words on runs (rigserver.storage.notes)
    notes: NotesStore = field(default_factory=lambda: SqliteNotes(":memory:"))
    #: the students' sketches on runs (rigserver.storage.sketches)
    sketches: SketchStore = field(default_factory=lambda: SqliteSketches(":memory:"))
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
    reports: RenderPool = field(init=False)
    imports: ImportSlots = field(init=False)
    report_files: ReportFiles = field(init=False)
    #: the series exports whose reports render in the background
    exports: SeriesExports = field(init=False)

    def __post_init__(self) -> None:
        self.reports = RenderPool(
            workers=self.settings.report_workers,
            queue=self.settings.report_queue,
            share=self.settings.report_key_share,
            retry_after=self.settings.retry_after,
            processes=self.settings.report_processes,
        )
        self.imports = ImportSlots(
            queue=self.settings.import_queue,
            share=self.settings.import_key_share,
            retry_after=self.settings.retry_after,
        )
        stands = "".join(self.stands[kind].model_dump_json() for kind in sorted(self.stands))
        self.report_files = ReportFiles(
            self.settings.data_dir / "reports", hashlib.sha256(stands.encode()).hexdigest()
        )
        self.exports = SeriesExports(self.stopping, self.settings.retry_after)
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
            share=self.settings.ingest_key_share,
            retry_after=self.settings.retry_after,
        )

    def stop(self) -> None:
        """The server is asked to stop: long requests end (live streams are woken)."""
        self.stopping.set()
        self.store.wake_waiters()

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
#: Where a request's caller is kept once found: its ASGI scope (so the rate limit, the
#: gate and the route find the key once per request).
_CALLER = "rig.caller"
#: A key presented that is not configured.
_UNKNOWN = object()


def _present(scope: Scope, services: Services) -> ApiKey | object | None:
    """The key (or session) the request presents, :data:`_UNKNOWN`, or None."""
    authorization = cookie = b""
    for name, value in scope["headers"]:
        if name == b"authorization":
            authorization = value
        elif name == b"cookie":
            cookie = value
    scheme, _, token = authorization.decode("latin-1").partition(" ")
    if scheme.lower() != "bearer" or not token:
        if cookie and scope["method"] in _READING:
            session = cookie_parser(cookie.decode("latin-1")).get(COOKIE)
            return services.sessions.find(session) if session else None
        return None
    found = services.keyring.find(token.strip())
    return _UNKNOWN if found is None else found


def caller_in(scope: Scope, services: Services) -> ApiKey | None:
    """The key the request presents (None without one); 401 for a key not configured.

    Without an Authorization header, a read may present a session cookie
    (:mod:`rigserver.api.sessions`); it reads as its key, with the scope ``read`` only.
    Found once per request and kept in its scope."""
    found = scope.get(_CALLER, _CALLER)
    if found is _CALLER:
        found = scope[_CALLER] = _present(scope, services)
    if found is _UNKNOWN:
        raise ApiProblem(
            401,
            "Unknown API key",
            "the key in the Authorization header is not configured on this server",
            headers={"WWW-Authenticate": "Bearer"},
        )
    return cast(ApiKey | None, found)


def caller_of(request: Request, services: Services) -> ApiKey | None:
    """:func:`caller_in` of a request."""
    return caller_in(request.scope, services)


def client_of(scope: Scope, services: Services) -> str:
    """Whose share of the service a request takes (the rate limit's tokens, the report
    renders, the imports): its key's fingerprint, else its address (a key not configured
    too: it is refused 401 further in)."""
    try:
        caller = caller_in(scope, services)
    except ApiProblem:
        caller = None
    if caller is not None:
        return caller.fingerprint
    client = scope.get("client")
    return f"address {client[0]}" if client else "address unknown"


async def get_caller(request: Request, services: ServicesDep) -> ApiKey | None:
    return caller_of(request, services)


CallerDep = Annotated[ApiKey | None, Depends(get_caller)]


def key_required(scope: str | None = None) -> ApiProblem:
    """The 401 of a request without a key (naming the scope it needs, if known)."""
    scoped = (
        f" with a key that has the scope '{scope}'"
        if scope
        else f" with a key of this server (the scope '{READ}' to read, 'write:<stand>' to write)"
    )
    return ApiProblem(
        401,
        "API key required",
        f"send 'Authorization: Bearer <key>'{scoped}",
        headers={"WWW-Authenticate": "Bearer"},
    )


def require_scope(caller: ApiKey | None, scope: str) -> ApiKey:
    """The caller's key; 401 without one, 403 when it lacks ``scope`` (named)."""
    if caller is None:
        raise key_required(scope)
    if not caller.allows(scope):
        raise ApiProblem(403, "Scope missing", f"this key lacks the scope '{scope}'")
    return caller


async def require_read(services: ServicesDep, caller: CallerDep) -> None:
    if not services.settings.public_reads:
        require_scope(caller, READ)


async def require_key(caller: CallerDep) -> None:
    """401 without a key: a write's first check (its scope needs the stand, found later)."""
    if caller is None:
        raise key_required()


#: A read route: a key with the scope ``read``, unless reads are public.
ReadAccess = Depends(require_read)
#: A write route: a key always (:mod:`rigserver.api.gate` answers before the route).
WriteAccess = Depends(require_key)


def require_write(caller: ApiKey | None, stand: StandKind) -> ApiKey:
    return require_scope(caller, write_scope(stand.value))


#: A row of a run's readings named in a path: its channel group and its index as stored.
Group = Annotated[str, Path(max_length=40, description="the channel group, e.g. 'rows'")]
Index = Annotated[
    int, Path(ge=0, le=2**62, description="the row's index in its group as stored, from 0")
]


def chosen_language(
    request: Request,
    lang: Annotated[
        Lang | None,
        Query(description="report language; without it, the best of Accept-Language (else en)"),
    ] = None,
) -> Lang:
    """``lang``, else the best of the request's ``Accept-Language`` (else English)."""
    return negotiate(lang, request.headers.get("accept-language"))


#: The language of a report or a page: ``?lang=``, else the best of ``Accept-Language``
#: (else English).
Language = Annotated[Lang, Depends(chosen_language)]
