"""Every error leaves as application/problem+json that a lab user can act on.

:class:`ApiProblem` is raised by the routes; storage and model errors are translated here,
so no third-party exception reaches a client and no request ends in a bare 500.
"""

from __future__ import annotations

import logging
import math
import re
from collections.abc import Iterable, Mapping
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.routing import Match

from rigserver.api.media import media_type
from rigserver.api.openapi import amend, component_schemas, schemas_of
from rigserver.core.errors import ModelInputError
from rigserver.storage.errors import (
    KeyReused,
    MemberExists,
    MemberNotFound,
    OtherStand,
    RunDamaged,
    RunExists,
    RunNotFound,
    RunNotOpen,
    SequenceConflict,
    SeriesFull,
    SeriesNotFound,
    StorageError,
    StorageFull,
)
from schemas.channels import MAX_VIOLATIONS, Violation
from schemas.problems import PROBLEM_MEDIA_TYPE, Problem

log = logging.getLogger("rigserver")


class ApiProblem(Exception):
    """An error answer: status, a short title, a detail, and the offending fields."""

    def __init__(
        self,
        status: int,
        title: str,
        detail: str,
        errors: list[Violation] | None = None,
        headers: dict[str, str] | None = None,
    ) -> None:
        super().__init__(detail)
        self.problem = Problem(title=title, status=status, detail=detail, errors=errors or [])
        self.headers = headers


def problem_response(problem: Problem, headers: dict[str, str] | None = None) -> JSONResponse:
    return JSONResponse(
        renderable(problem.model_dump(mode="json", exclude_none=True)),
        status_code=problem.status,
        media_type=PROBLEM_MEDIA_TYPE,
        headers=headers,
    )


_SURROGATE = re.compile("[\ud800-\udfff]")


def renderable(value: Any) -> Any:
    """``value`` with what JSON in UTF-8 cannot hold replaced: a lone surrogate by U+FFFD,
    a NaN or infinity by its name as text. An error's echo of a hostile input always
    renders."""
    if isinstance(value, str):
        return _SURROGATE.sub("\ufffd", value)
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    if isinstance(value, Mapping):
        return {renderable(str(k)): renderable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [renderable(v) for v in value]
    return value


def _echo(value: object) -> float | str | None:
    """The refused input as an error shows it: a short number or text, else nothing."""
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        return None
    if isinstance(value, int) and not -(2**53) <= value <= 2**53:
        return None  # no exact double, and str() of a long one fails
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)
    return value if len(str(value)) <= 80 else None


def violations(errors: Iterable[Mapping[str, Any]], prefix: str = "") -> list[Violation]:
    """Pydantic's errors as violations, each naming its field (``prefix`` + the loc path)."""
    found = []
    for err in errors:
        loc = [str(p) for p in err.get("loc", ()) if p != "body"]
        msg = err.get("msg")
        if err.get("type") == "json_invalid":  # loc: the character, or a strict_json path
            loc = [p for p in loc if not p.isdigit()]
            msg = f"invalid JSON: {err.get('ctx', {}).get('error', msg)}"
        field = prefix + ".".join(loc) if loc else prefix.rstrip(".") or "body"
        found.append(
            Violation(field=field, value=_echo(err.get("input")), message=f"{field}: {msg}")
        )
        if len(found) == MAX_VIOLATIONS:
            break
    return found


def _not_json(request: Request, exc: RequestValidationError) -> Problem | None:
    """A JSON body refused whole because the request did not say it was JSON: the
    ``Content-Type`` header named, not "Input should be a valid dictionary"."""
    if not any(tuple(e.get("loc", ())) == ("body",) for e in exc.errors()):
        return None
    media = media_type(request.headers.get("content-type"))
    if media == "application/json" or media.endswith("+json"):
        return None
    got = f"Content-Type: {media[:80]}" if media else "no Content-Type header"
    detail = f"the body is read as JSON with the header Content-Type: application/json; got {got}"
    return Problem(
        title="Unsupported media type",
        status=415,
        detail=detail,
        errors=[Violation(field="Content-Type", message=detail)],
    )


def _from_validation(exc: RequestValidationError) -> Problem:
    errors = violations(exc.errors())
    detail = "; ".join(e.message for e in errors[:3]) or "the request is not valid"
    return Problem(title="Invalid request", status=422, detail=detail, errors=errors)


_STORAGE_STATUS: list[tuple[type[StorageError], int, str]] = [
    (RunNotFound, 404, "Run not found"),
    (RunDamaged, 409, "Run damaged"),
    (RunExists, 409, "Run exists"),
    (KeyReused, 409, "Idempotency-Key reused"),
    (RunNotOpen, 409, "Run is not open"),
    (SequenceConflict, 409, "Sequence number reused"),
    (StorageFull, 507, "Storage full"),
    (SeriesNotFound, 404, "Series not found"),
    (MemberExists, 409, "Run in the series already"),
    (MemberNotFound, 404, "Run not in the series"),
    (SeriesFull, 409, "Series full"),
    (OtherStand, 409, "Run of another stand"),
]


def storage_problem(exc: StorageError) -> Problem:
    """The answer to a storage error: its status (503 for a failure of the storage)."""
    for kind, status, title in _STORAGE_STATUS:
        if isinstance(exc, kind):
            return Problem(title=title, status=status, detail=str(exc))
    return Problem(title="Storage unavailable", status=503, detail=str(exc))


def _document(app: FastAPI) -> None:
    """Describe the errors in the OpenAPI document as they are sent: every operation's
    ``default`` response, and its 422, is application/problem+json (FastAPI documents its
    own validation error, which :func:`install` replaces)."""
    amend(app, _problems_documented)


def _problems_documented(document: dict[str, Any]) -> None:
    problem = {"$ref": "#/components/schemas/Problem"}
    error = {
        "description": "an error: its title, the detail, the offending fields",
        "content": {PROBLEM_MEDIA_TYPE: {"schema": problem}},
    }
    for operations in document.get("paths", {}).values():
        for operation in operations.values():
            responses = operation.setdefault("responses", {})
            responses["default"] = error
            if "422" in responses:
                responses["422"] = {**error, "description": "the request is not valid"}
    schemas = schemas_of(document)
    for name in ("HTTPValidationError", "ValidationError"):
        schemas.pop(name, None)
    schemas.update(_PROBLEM_SCHEMAS)


_PROBLEM_SCHEMAS: dict[str, Any] = component_schemas(Problem)


def _allowed_methods(request: Request) -> list[str]:
    """The methods some route of the request's path takes; a path that a route names
    literally (``/runs/import``) is that route's alone, not also a value of another's
    parameter (``/runs/{run_id}``)."""
    methods = ("GET", "HEAD", "POST", "PUT", "PATCH", "DELETE")
    literal = request.app.openapi().get("paths", {}).get(request.url.path)
    if literal:  # as documented; a GET answers HEAD too
        named = {m.upper() for m in literal} | ({"HEAD"} if "get" in literal else set())
        return [method for method in methods if method in named]
    routes = request.app.router.routes
    return [
        method
        for method in methods
        if any(
            route.matches({**request.scope, "method": method})[0] is Match.FULL for route in routes
        )
    ]


def install(app: FastAPI) -> None:
    """Register the handlers that turn every error into problem+json, and document them."""
    _document(app)

    @app.exception_handler(ApiProblem)
    async def _api_problem(request: Request, exc: ApiProblem) -> JSONResponse:
        return problem_response(exc.problem, exc.headers)

    @app.exception_handler(RequestValidationError)
    async def _validation(request: Request, exc: RequestValidationError) -> JSONResponse:
        return problem_response(_not_json(request, exc) or _from_validation(exc))

    @app.exception_handler(StarletteHTTPException)
    async def _http(request: Request, exc: StarletteHTTPException) -> JSONResponse:
        title = {404: "Not found", 405: "Method not allowed"}.get(exc.status_code, "Error")
        headers = dict(exc.headers) if exc.headers else {}
        detail = str(exc.detail)
        if exc.status_code == 405:  # Starlette names the methods of one route of the path
            allowed = _allowed_methods(request)
            headers["Allow"] = ", ".join(allowed)
            detail = f"{request.method} is not allowed here; use {' or '.join(allowed)}"
        return problem_response(
            Problem(title=title, status=exc.status_code, detail=detail), headers or None
        )

    @app.exception_handler(ModelInputError)
    async def _model(request: Request, exc: ModelInputError) -> JSONResponse:
        return problem_response(
            Problem(title="Outside the model's domain", status=422, detail=str(exc))
        )

    @app.exception_handler(StorageError)
    async def _storage(request: Request, exc: StorageError) -> JSONResponse:
        problem = storage_problem(exc)
        if problem.status != 503:
            return problem_response(problem)
        log.error("storage failure on %s: %s", request.url.path, exc)
        return problem_response(problem, {"Retry-After": "5"})

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception) -> JSONResponse:
        log.exception("unexpected error on %s", request.url.path)
        return problem_response(
            Problem(
                title="Internal error",
                status=500,
                detail="the server failed on this request; the error is in its log",
            )
        )
