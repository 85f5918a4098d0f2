"""``create_app``: the FastAPI application, handed its settings, store, stands and keys."""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

from fastapi import FastAPI
from starlette.middleware.cors import CORSMiddleware

from rigserver.api import problems
from rigserver.api.auth import ApiKey, Keyring
from rigserver.api.body_limit import BodyLimit
from rigserver.api.deps import Services
from rigserver.api.gate import Gate
from rigserver.api.openapi import add_components
from rigserver.api.page_policy import PagePolicy
from rigserver.api.rate_limit import RateLimit
from rigserver.api.routes import (
    api_docs,
    eln,
    live,
    models,
    pages,
    readings,
    reports,
    results,
    runs,
)
from rigserver.api.routes import series as series_routes
from rigserver.api.routes import stands as stand_routes
from rigserver.api.settings import Settings
from rigserver.storage.base import RunStore
from rigserver.storage.series import SeriesStore, SqliteSeries
from schemas.readings import ReadingBatch
from schemas.stands import Stand, StandKind

API_PREFIX = "/api/v1"
#: The routers of the API, under :data:`API_PREFIX`; the ingest route first: routes are
#: matched in order.
API_ROUTERS = (
    readings.router,
    stand_routes.router,
    runs.router,
    results.router,
    models.router,
    reports.router,
    eln.router,
    live.router,
    series_routes.router,
)


def create_app(
    settings: Settings,
    store: RunStore,
    keys: list[ApiKey],
    stands: dict[StandKind, Stand],
    series: SeriesStore | None = None,
) -> FastAPI:
    """Build the service. Nothing is built at import time; the stores are closed on shutdown.

    Without a series store the series live in memory (tests, and stores without a disk)."""
    series_store = series if series is not None else SqliteSeries(":memory:")

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        yield
        app.state.services.results.close()
        app.state.services.reports.close()
        store.close()
        series_store.close()

    app = FastAPI(
        title="rig",
        version="0.1.0",
        summary="Data acquisition and analysis for tribology test stands",
        description="Lab PCs post readings of the SMTs-2, slide-bearing, MTOS and ABRIS-PM7 "
        "stands; the service stores each run in HDF5 and computes what the lab manual asks "
        "for. Errors are application/problem+json naming the field, the value and the limit.",
        lifespan=lifespan,
        docs_url=None,  # served by api_docs, without a CDN
        redoc_url=None,
    )
    app.state.services = Services(
        settings=settings,
        store=store,
        stands=stands,
        keyring=Keyring(keys),
        series=series_store,
    )
    problems.install(app)
    for router in API_ROUTERS:
        app.include_router(router, prefix=API_PREFIX)
    add_components(app, [ReadingBatch])  # the ingest route parses its body itself
    api_docs.install(app)
    pages.install(app)
    # the last added is the outermost: rate, then key, then size
    app.add_middleware(
        BodyLimit,
        max_bytes=settings.max_body_bytes,
        timeout=settings.body_timeout,
        larger={f"{API_PREFIX}/runs/import": settings.import_max_bytes},
    )
    services = app.state.services
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
            allow_methods=["GET", "POST"],
            allow_headers=["Authorization", "Content-Type"],
        )
    app.add_middleware(PagePolicy, api=API_PREFIX, docs=api_docs.PAGES)
    return app
