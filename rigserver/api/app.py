"""``create_app``: the FastAPI application, handed its settings, store, stands and keys."""

from __future__ import annotations

import asyncio
import contextlib
import re
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from functools import partial

from fastapi import FastAPI
from fastapi.telemetry import TelemetryConfig
from starlette.middleware.cors import CORSMiddleware
from starlette.requests import cookie_parser
from starlette.types import Scope

from rigserver.api import problems
from rigserver.api.auth import ApiKey, Keyring
from rigserver.api.body_limit import BodyLimit
from rigserver.api.deps import Services, caller_in
from rigserver.api.gate import Gate
from rigserver.api.ingest_lane import IngestLane
from rigserver.api.openapi import add_components
from rigserver.api.page_policy import PagePolicy
from rigserver.api.problems import ApiProblem
from rigserver.api.rate_limit import RateLimit
from rigserver.api.routes import (
    api_docs,
    corrections,
    eln,
    entry,
    live,
    models,
    pages,
    readings,
    reports,
    results,
    runs,
    stand_kinds,
)
from rigserver.api.routes import notes as notes_routes
from rigserver.api.routes import series as series_routes
from rigserver.api.routes import sketches as sketches_routes
from rigserver.api.routes.pages import LOGIN_BODY_BYTES
from rigserver.api.sessions import COOKIE
from rigserver.api.settings import Settings
from rigserver.storage.base import RunStore
from rigserver.storage.notes import NotesStore, SqliteNotes
from rigserver.storage.series import SeriesStore, SqliteSeries
from rigserver.storage.sketches import SketchStore, SqliteSketches
from schemas.readings import ReadingBatch
from schemas.sketches import SKETCH_MAX_BYTES
from schemas.stands import Stand, StandKind

API_PREFIX = "/api/v1"
#: The routers of the API, under :data:`API_PREFIX`; the ingest route first: routes are
#: matched in order.
API_ROUTERS = (
    readings.router,
    corrections.router,
    stand_kinds.router,
    runs.router,
    notes_routes.router,
    sketches_routes.router,
    results.router,
    models.router,
    reports.router,
    eln.router,
    live.router,
    series_routes.router,
)
#: The report renderer is loaded (:meth:`RenderPool.warm_up`) once no batch has been posted
#: for this long, s: loading it takes a core for 2-3 s, and binary batches posted meanwhile
#: were stored at three quarters of the rate (docs/speed.md, "Ingest, the seventh set").
WARM_UP_WHEN_QUIET_S = 2.0


#: FastAPI's native OpenTelemetry, off: no traces, metrics or logs of requests.
NO_TELEMETRY: TelemetryConfig = {"tracing": False, "metrics": False, "logs": False}

#: The route that takes a whole run's archive (rigserver.api.routes.eln).
IMPORT_PATH = f"{API_PREFIX}/runs/import"
#: The bodies of routes without a key, bytes: the login and logout forms.
FORM_BODY_BYTES = {"/login": LOGIN_BODY_BYTES, "/logout": LOGIN_BODY_BYTES}
#: The largest body of any other request without a key (a calculator's input, when reads
#: are public), bytes.
ANONYMOUS_BODY_BYTES = 64 << 10
#: The run page's form of a sketch (rigserver.api.routes.pages.run_sketch), and the most it
#: sends from a live session: the largest sketch and its form's parts, bytes.
SKETCH_FORM = re.compile(r"/runs/[^/]+/sketches/\d+")
SKETCH_FORM_BYTES = SKETCH_MAX_BYTES + (64 << 10)


def body_limit(services: Services, scope: Scope) -> int:
    """The largest body the request may send: its route's own (the login form, a live
    session's sketch form), else without a key :data:`ANONYMOUS_BODY_BYTES` (a key this
    server does not know is none: :mod:`rigserver.api.gate` answers it 401), with one
    ``max_body_bytes`` (an archive's import: ``import_max_bytes``)."""
    path = scope["path"]
    own = FORM_BODY_BYTES.get(path)
    if own is not None:
        return own
    try:
        caller = caller_in(scope, services)
    except ApiProblem:
        caller = None
    if caller is None:
        return _session_form(services, scope) or ANONYMOUS_BODY_BYTES
    if path == IMPORT_PATH:
        return services.settings.import_max_bytes
    return services.settings.max_body_bytes


def _session_form(services: Services, scope: Scope) -> int | None:
    """The body of a sketch's form posted by a live session (None for any other request)."""
    if scope["method"] != "POST" or not SKETCH_FORM.fullmatch(scope["path"]):
        return None
    cookie = next((v for k, v in scope["headers"] if k == b"cookie"), b"")
    token = cookie_parser(cookie.decode("latin-1")).get(COOKIE)
    return SKETCH_FORM_BYTES if token and services.sessions.key(token) else None


async def _warm_up_when_quiet(services: Services) -> None:
    """Load the report renderer once ingest has been quiet for :data:`WARM_UP_WHEN_QUIET_S`
    (a render asked for before starts it itself)."""
    while not services.ingest.quiet_for(WARM_UP_WHEN_QUIET_S):
        await asyncio.sleep(WARM_UP_WHEN_QUIET_S / 4)
    services.reports.warm_up()


def create_app(
    settings: Settings,
    store: RunStore,
    keys: list[ApiKey],
    stands: dict[StandKind, Stand],
    series: SeriesStore | None = None,
    notes: NotesStore | None = None,
    sketches: SketchStore | None = None,
) -> FastAPI:
    """Build the service. Nothing is built at import time; the stores are closed on shutdown.

    Without a series store (a notes store, a sketch store) the series (the student's words,
    their sketches) live in memory (tests, and stores without a disk)."""
    series_store = series if series is not None else SqliteSeries(":memory:")
    notes_store = notes if notes is not None else SqliteNotes(":memory:")
    sketch_store = sketches if sketches is not None else SqliteSketches(":memory:")

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        warming = None
        if settings.reports_on_finish:  # the first run to end renders its reports at once
            warming = asyncio.create_task(_warm_up_when_quiet(app.state.services))
        yield
        if warming is not None:
            warming.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await warming
        app.state.services.results.close()
        app.state.services.reports.close()
        store.close()
        series_store.close()
        notes_store.close()
        sketch_store.close()

    app = FastAPI(
        title="rig",
        version="0.1.0",
        summary="Data acquisition and analysis for tribology test stands",
        description="Lab PCs post readings of the SMTs-2, slide-bearing, MTOS and ABRIS-PM7 "
        "stands and of the pin-on-disc and reciprocating tribometers; the service stores each "
        "run in HDF5 and computes what the lab manual (and ASTM G99, G133, ISO 20808 for the "
        "tribometers) asks for. Errors are application/problem+json naming the field, the "
        "value and the limit.",
        lifespan=lifespan,
        docs_url=None,  # served by api_docs, without a CDN
        redoc_url=None,
        # rig sets up no OpenTelemetry; FastAPI's own would ask for its providers on every
        # request (its cost: docs/speed.md, "Findings the code rests on")
        telemetry=NO_TELEMETRY,
    )
    app.state.services = Services(
        settings=settings,
        store=store,
        stands=stands,
        keyring=Keyring(keys),
        series=series_store,
        notes=notes_store,
        sketches=sketch_store,
    )
    problems.install(app)
    for router in API_ROUTERS:
        app.include_router(router, prefix=API_PREFIX)
    add_components(app, [ReadingBatch])  # the ingest route parses its body itself
    api_docs.install(app)
    app.include_router(entry.router)  # before the pages: /runs/new is no run's id
    pages.install(app)
    # the last added is the outermost: rate, then key, then size, then the ingest route
    services = app.state.services
    app.add_middleware(
        IngestLane,
        path=API_PREFIX + readings.router.prefix,
        endpoint=readings.post_readings,
        handlers=app.exception_handlers,
    )
    app.add_middleware(
        BodyLimit,
        max_bytes=settings.max_body_bytes,
        timeout=settings.body_timeout,
        limit_of=partial(body_limit, services),
    )
    api_routes = [route for router in API_ROUTERS for route in router.routes]
    app.add_middleware(Gate, services=services, prefix=API_PREFIX, routes=api_routes)
    if settings.rate_limit:
        app.add_middleware(
            RateLimit, services=services, rate=settings.rate_limit, burst=settings.rate_burst
        )
    if settings.cors_origins:
        app.add_middleware(
            CORSMiddleware,
            allow_origins=list(settings.cors_origins),
            allow_methods=["GET", "POST", "PATCH", "DELETE"],
            allow_headers=["Authorization", "Content-Type"],
        )
    app.add_middleware(PagePolicy, api=API_PREFIX, docs=api_docs.PAGES)
    return app
