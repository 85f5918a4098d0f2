"""The web pages: ``/`` (the runs, filtered) and ``/runs/{id}`` (a run, live), and their
static files under ``/static``. Reads follow the API's rule: a key, or ``--public-reads``."""

from __future__ import annotations

from datetime import UTC, date, datetime, time, timedelta
from typing import Annotated, TypeVar

from fastapi import APIRouter, FastAPI, Query, Request
from fastapi.responses import HTMLResponse
from fastapi.staticfiles import StaticFiles

from rigserver.api.deps import ReadAccess, ServicesDep
from rigserver.api.problems import ApiProblem
from rigserver.api.routes.runs import load_run
from rigserver.reports.i18n import Lang, negotiate
from rigserver.web.pages import run_page, runs_page
from schemas.channels import Violation
from schemas.runs import RunQuery, RunState
from schemas.stands import StandKind

router = APIRouter(include_in_schema=False, dependencies=[ReadAccess])

PAGE_SIZE = 50

Text = Annotated[str, Query(max_length=100)]
Choice = TypeVar("Choice", StandKind, RunState)


def install(app: FastAPI) -> None:
    """Add the pages and their static files to the app."""
    app.include_router(router)
    app.mount("/static", StaticFiles(packages=[("rigserver.web", "static")]), name="static")


def _choice(kind: type[Choice], field: str, value: str) -> Choice | None:
    if not value:
        return None
    try:
        return kind(value)
    except ValueError:
        known = ", ".join(k.value for k in kind)
        raise ApiProblem(
            422,
            "Invalid filter",
            f"{field} must be one of {known}, got {value[:40]!r}",
            [Violation(field=field, value=value[:40], limit=f"one of {known}", message="")],
        ) from None


def _day(field: str, value: str, *, end: bool = False) -> datetime | None:
    """The start of the day (``end``: of the next day) of an ISO date, UTC."""
    if not value:
        return None
    try:
        day = date.fromisoformat(value)
    except ValueError:
        raise ApiProblem(
            422, "Invalid filter", f"{field} must be a date like 2026-11-22, got {value[:40]!r}"
        ) from None
    return datetime.combine(day + timedelta(days=1 if end else 0), time(), tzinfo=UTC)


@router.get("/", response_class=HTMLResponse)
def runs(
    request: Request,
    services: ServicesDep,
    stand: Text = "",
    operator: Text = "",
    state: Text = "",
    since: Text = "",
    until: Text = "",
    offset: Annotated[int, Query(ge=0)] = 0,
    lang: Lang | None = None,
) -> HTMLResponse:
    chosen = negotiate(lang, request.headers.get("accept-language"))
    query = RunQuery(
        stand=_choice(StandKind, "stand", stand),
        operator=operator or None,
        state=_choice(RunState, "state", state),
        since=_day("since", since),
        until=_day("until", until, end=True),
        limit=PAGE_SIZE,
        offset=offset,
    )
    page = services.store.list_runs(query)
    filters = {"stand": stand, "operator": operator, "state": state, "since": since, "until": until}
    html = runs_page(page=page, filters=filters, offset=offset, limit=PAGE_SIZE, lang=chosen)
    return HTMLResponse(html, headers={"Content-Language": chosen, "Vary": "Accept-Language"})


@router.get("/runs/{run_id}", response_class=HTMLResponse)
def run(
    run_id: str, request: Request, services: ServicesDep, lang: Lang | None = None
) -> HTMLResponse:
    chosen = negotiate(lang, request.headers.get("accept-language"))
    found = load_run(services, run_id)
    html = run_page(run=found, stand=services.stand_of(found), lang=chosen)
    return HTMLResponse(html, headers={"Content-Language": chosen, "Vary": "Accept-Language"})
