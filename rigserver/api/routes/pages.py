"""The web pages: ``/`` (the runs, filtered) and ``/runs/{id}`` (a run, live), and their
static files under ``/static``. Reads follow the API's rule: a key, or ``--public-reads``;
a browser without either is sent to ``/login``, where a key with the scope ``read``
becomes a session cookie (:mod:`rigserver.api.sessions`)."""

from __future__ import annotations

from datetime import UTC, date, datetime, time, timedelta
from importlib import resources
from typing import Annotated, TypeVar
from urllib.parse import parse_qs, urlencode

from fastapi import APIRouter, Depends, FastAPI, Query, Request, Response
from fastapi.concurrency import run_in_threadpool
from fastapi.exceptions import RequestValidationError
from fastapi.responses import HTMLResponse, RedirectResponse
from fastapi.staticfiles import StaticFiles
from pydantic import ValidationError

from rigserver.api.auth import READ, write_scope
from rigserver.api.cases.found import load_run
from rigserver.api.cases.notes import write_notes
from rigserver.api.cases.series import series_view
from rigserver.api.cases.sketches import upload_sketch
from rigserver.api.deps import Language, Services, ServicesDep
from rigserver.api.page_forms import (
    FORM_TOKEN,
    LoginFirst,
    form_token,
    form_writer,
    read_form,
    require_page_read,
    same_origin,
    signed_in,
    writable_stands,
    writer_of,
)
from rigserver.api.problems import ApiProblem
from rigserver.api.run_results import results_payload
from rigserver.api.sessions import COOKIE, SESSION_SECONDS
from rigserver.api.sketch_form import read_sketch_form
from rigserver.api.sketch_images import checked
from rigserver.reports.i18n import Lang, language_headers
from rigserver.reports.series_report import render_series_body
from rigserver.web.entry import ReceivedRow, received
from rigserver.web.pages import login_page, results_html, run_page, runs_page
from rigserver.web.series_pages import series_list_page, series_page
from schemas.channels import Violation
from schemas.runs import Run, RunQuery, RunState
from schemas.stands import Stand, StandKind
from schemas.student_notes import StudentNotesWrite
from schemas.wire import Text

router = APIRouter(include_in_schema=False, dependencies=[Depends(require_page_read)])
login_router = APIRouter(include_in_schema=False)
#: Forms of this site only.
SameOrigin = Depends(same_origin)
#: The largest login (or logout) form read, bytes: a longer body is refused 413 before it is
#: read (:func:`rigserver.api.app.body_limit`).
LOGIN_BODY_BYTES = 4096

PAGE_SIZE = 50

#: The pages' icon, served at ``/favicon.ico`` too.
FAVICON = resources.files("rigserver.web") / "static" / "favicon.svg"

Filter = Annotated[Text, Query(max_length=100)]
Choice = TypeVar("Choice", StandKind, RunState)


def install(app: FastAPI) -> None:
    """Add the pages, the login and their static files to the app."""

    async def to_login(request: Request, exc: Exception) -> Response:
        assert isinstance(exc, LoginFirst)
        return RedirectResponse("/login?" + urlencode({"next": exc.next_page}), status_code=303)

    app.add_exception_handler(LoginFirst, to_login)
    app.include_router(router)
    app.include_router(login_router)
    app.mount("/static", StaticFiles(packages=[("rigserver.web", "static")]), name="static")

    @app.get("/favicon.ico", include_in_schema=False)
    def favicon() -> Response:
        """The pages' icon, where browsers look for it first (an SVG: rig's own drawing)."""
        return Response(
            FAVICON.read_bytes(),
            media_type="image/svg+xml",
            headers={"Cache-Control": "public, max-age=86400"},
        )


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
    if end and day == date.max:
        return None  # the end of the last day there is: no bound
    return datetime.combine(day + timedelta(days=1 if end else 0), time(), tzinfo=UTC)


@router.get("/", response_class=HTMLResponse)
def runs(
    request: Request,
    services: ServicesDep,
    lang: Language,
    stand: Filter = "",
    operator: Filter = "",
    state: Filter = "",
    since: Filter = "",
    until: Filter = "",
    offset: Annotated[int, Query(ge=0)] = 0,
) -> HTMLResponse:
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
    html = runs_page(
        page=page,
        filters=filters,
        offset=offset,
        limit=PAGE_SIZE,
        lang=lang,
        signed_in=signed_in(request, services),
        writable=writable_stands(writer_of(request, services)),
    )
    return HTMLResponse(html, headers=language_headers(lang))


@router.get("/runs/{run_id}", response_class=HTMLResponse)
def run(run_id: str, request: Request, services: ServicesDep, lang: Language) -> HTMLResponse:
    found = load_run(services, run_id)
    writer = writer_of(request, services)
    may_write = writer is not None and writer.allows(write_scope(found.stand.value))
    stand = services.stand_of(found)
    token = form_token(request, services) if may_write else ""
    html = run_page(
        run=found,
        stand=stand,
        payload=results_payload(services, found),
        lang=lang,
        signed_in=signed_in(request, services),
        notes=services.notes.get(found.id),
        sketches=services.sketches.history(found.id),
        may_write=may_write,
        form_token=token,
        received=received_rows(services, found, stand) if token else None,
    )
    return HTMLResponse(html, headers=language_headers(lang))


@router.get("/runs/{run_id}/results", response_class=HTMLResponse)
def run_results(
    run_id: str, request: Request, services: ServicesDep, lang: Language
) -> HTMLResponse:
    """The results part of a run's page (refreshed by the page while the run is open)."""
    found = load_run(services, run_id)
    html = results_html(run=found, payload=results_payload(services, found), lang=lang)
    return HTMLResponse(html, headers=language_headers(lang))


@router.get("/series", response_class=HTMLResponse)
def series_list(request: Request, services: ServicesDep, lang: Language) -> HTMLResponse:
    html = series_list_page(
        series=services.series.list(), lang=lang, signed_in=signed_in(request, services)
    )
    return HTMLResponse(html, headers=language_headers(lang))


@router.get("/series/{series_id}", response_class=HTMLResponse)
def series(series_id: str, request: Request, services: ServicesDep, lang: Language) -> HTMLResponse:
    detail, context = series_view(services, series_id, lang)
    html = series_page(
        detail=detail,
        context=context,
        body=render_series_body(context),
        lang=lang,
        signed_in=signed_in(request, services),
    )
    return HTMLResponse(html, headers=language_headers(lang))


@login_router.post("/runs/{run_id}/notes", dependencies=[SameOrigin])
async def run_notes(
    run_id: str, request: Request, services: ServicesDep, lang: Lang | None = None
) -> Response:
    """The run page's form of the student's words (``group``, ``students`` one per line,
    ``conclusions``), posted by a session whose key may write the run's stand: stored, and
    back to the page. Without a session: the login page; 422 for words the API refuses."""
    body = await request.body()  # at most ANONYMOUS_BODY_BYTES (rigserver.api.app.body_limit)
    form = read_form(body, (*_NOTES_FIELDS, FORM_TOKEN))
    writer = form_writer(request, services, form.pop(FORM_TOKEN, ""), f"/runs/{run_id}")
    words = _notes_form(form)
    await run_in_threadpool(write_notes, services, run_id, words, writer)
    return _back_to(run_id, "notes", lang)


@login_router.post("/runs/{run_id}/sketches/{item}", dependencies=[SameOrigin])
async def run_sketch(
    run_id: str, item: int, request: Request, services: ServicesDep, lang: Lang | None = None
) -> Response:
    """The run page's form of a sketch (``multipart/form-data``: ``form_token``, ``image``),
    posted by a session whose key may write the run's stand: checked as the API checks an
    upload (:mod:`rigserver.api.sketch_images`), stored as the item's next version, and back
    to the page. Without a session: the login page."""
    body = await request.body()  # at most SKETCH_FORM_BYTES (rigserver.api.app.body_limit)
    form = read_sketch_form(body, request.headers.get("content-type"))
    writer = form_writer(request, services, form.token, f"/runs/{run_id}")
    image = await run_in_threadpool(checked, form.data, form.media_type)
    await run_in_threadpool(upload_sketch, services, run_id, item, image, writer)
    return _back_to(run_id, "sketches", lang)


def _back_to(run_id: str, part: str, lang: Lang | None) -> RedirectResponse:
    """The run's page again at ``part``, in the language asked for if one was (303)."""
    query = f"?{urlencode({'lang': lang})}" if lang else ""
    return RedirectResponse(f"/runs/{run_id}{query}#{part}", status_code=303)


def _notes_form(form: dict[str, str]) -> StudentNotesWrite:
    """The words of the form; 422 naming the field refused."""
    fields: dict[str, str | list[str]] = dict(form)
    students = form.get("students", "")
    fields["students"] = [name for name in students.splitlines() if name.strip()]
    try:
        return StudentNotesWrite.model_validate(fields)
    except ValidationError as exc:
        raise RequestValidationError(exc.errors()) from None


#: The fields of the run page's form of the student's words.
_NOTES_FIELDS = ("group", "students", "conclusions", "analysis", "mismatch", "observations")


@login_router.get("/login", response_class=HTMLResponse)
def login_form(
    lang: Language,
    next: Annotated[Text, Query(max_length=2000)] = "/",
) -> HTMLResponse:
    return HTMLResponse(login_page(next_page=_local(next), refused=False, lang=lang))


@login_router.post("/login", dependencies=[SameOrigin])
async def login(request: Request, services: ServicesDep, lang: Language) -> Response:
    """The login form posted (``key``, ``next``): a session and back to ``next``, or the form
    again (401) if the key is unknown or may not read."""
    body = await request.body()  # at most LOGIN_BODY_BYTES (rigserver.api.app.body_limit)
    form = parse_qs(body.decode("utf-8", "replace"), max_num_fields=4)
    key, next_page = form.get("key", [""])[0].strip(), _local(form.get("next", ["/"])[0])
    found = services.keyring.find(key) if key else None
    if found is None or not found.allows(READ):
        page = login_page(next_page=next_page, refused=True, lang=lang)
        return HTMLResponse(page, status_code=401)
    response = RedirectResponse(next_page, status_code=303)
    response.set_cookie(
        COOKIE,
        services.sessions.open(found),
        max_age=SESSION_SECONDS,
        path="/",
        secure=request.url.scheme == "https",
        httponly=True,
        samesite="strict",
    )
    return response


@login_router.post("/logout", dependencies=[SameOrigin])
def logout(request: Request, services: ServicesDep) -> Response:
    token = request.cookies.get(COOKIE)
    if token:
        services.sessions.close(token)
    response = RedirectResponse("/login", status_code=303)
    response.delete_cookie(COOKIE, path="/")
    return response


#: Rows of a group shown as received on the run page (the last ones).
RECEIVED_ROWS = 100


def received_rows(services: Services, run: Run, stand: Stand) -> dict[str, list[ReceivedRow]]:
    """The last rows the server holds of each group of the run as corrected, the values as
    typed kept and the struck rows marked (:func:`rigserver.web.entry.received`); of a
    group of single values, one row of the latest of each."""
    corrections = services.store.corrections(run.id) if run.corrections else []
    found: dict[str, list[ReceivedRow]] = {}
    for group in stand.groups:
        total = run.rows.get(group.name, 0)
        if not total:
            continue
        start = max(0, total - RECEIVED_ROWS) if group.aligned else 0
        data = services.store.read(run.id, group.name, None, start, total)
        found[group.name] = received(group, data, start, corrections)
    return found


def _local(target: str) -> str:
    """``target`` if it is a path of this site, else ``/`` (no redirect elsewhere)."""
    if target.startswith("/") and not target.startswith("//") and "\\" not in target:
        return target
    return "/"
