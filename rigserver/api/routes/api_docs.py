"""``/docs`` (Swagger UI) and ``/redoc`` (ReDoc), served with their assets by the service
itself: a lab network without internet gets the pages too (FastAPI's own load them from a
CDN).

The assets are those the ``fastapi-offline`` package ships (Swagger UI 5 and ReDoc 2, kept
current by its maintainer; why this package in ``docs/api-docs.md``), under
``/docs-assets``. The pages hold no inline script: Swagger UI is started by
``/docs-assets/swagger-init.js``, which reads the document's address from the page. The
pages' Content-Security-Policy (:data:`rigserver.api.page_policy.DOCS`) holds them to this
server: ReDoc's footer asks a CDN for a logo, which the policy blocks (ReDoc then hides it).
"""

from __future__ import annotations

import io
from functools import lru_cache
from html import escape
from typing import Any

import numpy as np
from fastapi import APIRouter, FastAPI, Request, Response
from fastapi.concurrency import run_in_threadpool
from fastapi.openapi.docs import get_redoc_html
from fastapi.responses import HTMLResponse
from fastapi.staticfiles import StaticFiles

from rigserver.api.examples import (
    ELN_EXAMPLE,
    NPZ_EXAMPLE,
    SKETCH_EXAMPLES,
    example_archive,
    example_sketch,
)
from rigserver.reports.eln import ELN_MEDIA_TYPE
from schemas.readings import NPZ_MEDIA_TYPE, ReadingBatch

ASSETS = "/docs-assets"

SWAGGER_UI = "/docs"
REDOC = "/redoc"
#: The two pages, for the page policy (rigserver.api.page_policy).
PAGES = (SWAGGER_UI, REDOC)

router = APIRouter(include_in_schema=False)

_SWAGGER_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{title}</title>
<link rel="stylesheet" href="{assets}/swagger-ui.css">
<link rel="icon" href="{assets}/favicon.png">
</head>
<body>
<div id="swagger-ui" data-openapi-url="{openapi_url}"></div>
<script src="{assets}/swagger-ui-bundle.js"></script>
<script src="{assets}/swagger-init.js"></script>
</body>
</html>
"""


def _paths(request: Request) -> tuple[str, str]:
    """The assets' and the document's addresses, behind a proxy's root path too."""
    root = str(request.scope.get("root_path", "")).rstrip("/")
    openapi_url = request.app.openapi_url or "/openapi.json"
    return root + ASSETS, root + openapi_url


@router.get(SWAGGER_UI)
async def swagger_ui(request: Request) -> HTMLResponse:
    assets, openapi_url = _paths(request)
    page = _SWAGGER_PAGE.format(
        title=escape(f"{request.app.title} - API"),
        assets=escape(assets),
        openapi_url=escape(openapi_url),
    )
    return HTMLResponse(page)


@router.get(REDOC)
async def redoc(request: Request) -> HTMLResponse:
    assets, openapi_url = _paths(request)
    return get_redoc_html(
        openapi_url=openapi_url,
        title=f"{request.app.title} - API",
        redoc_js_url=f"{assets}/redoc.standalone.js",
        redoc_favicon_url=f"{assets}/favicon.png",
        with_google_fonts=False,
    )


@lru_cache(maxsize=1)
def example_npz() -> bytes:
    """:class:`ReadingBatch`'s example as the binary form: ``numpy.savez``, one array per
    channel."""
    columns = ReadingBatch.model_json_schema()["examples"][0]["columns"]
    arrays: dict[str, Any] = {name: np.asarray(v, dtype=np.float64) for name, v in columns.items()}
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return buffer.getvalue()


@router.get(ELN_EXAMPLE)
async def run_eln_example() -> Response:
    return Response(await run_in_threadpool(example_archive), media_type=ELN_MEDIA_TYPE)


@router.get("/docs/examples/sketch.{suffix}")
async def sketch_example(suffix: str) -> Response:
    for media_type, url in SKETCH_EXAMPLES.items():
        if url.endswith(f".{suffix}"):
            return Response(example_sketch(media_type), media_type=media_type)
    return Response(status_code=404)


@router.get(NPZ_EXAMPLE)
async def readings_npz_example() -> Response:
    return Response(example_npz(), media_type=NPZ_MEDIA_TYPE)


def install(app: FastAPI) -> None:
    """Add the two pages, the binary example and the assets to the app."""
    app.include_router(router)
    app.mount(
        ASSETS,
        StaticFiles(packages=[("fastapi_offline", "static"), ("rigserver.api", "static")]),
        name="docs-assets",
    )
