"""Every error leaves as application/problem+json that a lab user can act on.

:class:`ApiProblem` is raised by the routes; storage and model errors are translated here,
so no third-party exception reaches a client and no request ends in a bare 500.
"""

from __future__ import annotations

import logging

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException

from rigserver.core.errors import ModelInputError
from rigserver.storage.errors import (
    RunExists,
    RunNotFound,
    RunNotOpen,
    SequenceConflict,
    StorageError,
    StorageFull,
)
from schemas.channels import Violation
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
        problem.model_dump(mode="json", exclude_none=True),
        status_code=problem.status,
        media_type=PROBLEM_MEDIA_TYPE,
        headers=headers,
    )


def _from_validation(exc: RequestValidationError) -> Problem:
    errors = []
    for err in exc.errors()[:20]:
        loc = [str(p) for p in err.get("loc", ()) if p != "body"]
        field = ".".join(loc) or "body"
        value = err.get("input")
        shown = value if isinstance(value, int | float | str) and len(str(value)) <= 80 else None
        errors.append(Violation(field=field, value=shown, message=f"{field}: {err.get('msg')}"))
    detail = "; ".join(e.message for e in errors[:3]) or "the request is not valid"
    return Problem(title="Invalid request", status=422, detail=detail, errors=errors)


_STORAGE_STATUS: list[tuple[type[StorageError], int, str]] = [
    (RunNotFound, 404, "Run not found"),
    (RunExists, 409, "Run exists"),
    (RunNotOpen, 409, "Run is not open"),
    (SequenceConflict, 409, "Sequence number reused"),
    (StorageFull, 507, "Storage full"),
]


def install(app: FastAPI) -> None:
    """Register the handlers that turn every error into problem+json."""

    @app.exception_handler(ApiProblem)
    async def _api_problem(request: Request, exc: ApiProblem) -> JSONResponse:
        return problem_response(exc.problem, exc.headers)

    @app.exception_handler(RequestValidationError)
    async def _validation(request: Request, exc: RequestValidationError) -> JSONResponse:
        return problem_response(_from_validation(exc))

    @app.exception_handler(StarletteHTTPException)
    async def _http(request: Request, exc: StarletteHTTPException) -> JSONResponse:
        title = {404: "Not found", 405: "Method not allowed"}.get(exc.status_code, "Error")
        return problem_response(
            Problem(title=title, status=exc.status_code, detail=str(exc.detail)),
            dict(exc.headers) if exc.headers else None,
        )

    @app.exception_handler(ModelInputError)
    async def _model(request: Request, exc: ModelInputError) -> JSONResponse:
        return problem_response(
            Problem(title="Outside the model's domain", status=422, detail=str(exc))
        )

    @app.exception_handler(StorageError)
    async def _storage(request: Request, exc: StorageError) -> JSONResponse:
        for kind, status, title in _STORAGE_STATUS:
            if isinstance(exc, kind):
                return problem_response(Problem(title=title, status=status, detail=str(exc)))
        log.error("storage failure on %s: %s", request.url.path, exc)
        return problem_response(
            Problem(title="Storage unavailable", status=503, detail=str(exc)),
            {"Retry-After": "5"},
        )

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
