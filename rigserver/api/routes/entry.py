"""The pages that write at the stand: ``/runs/new`` (open a run), the rows typed on a run's
page (``/runs/{id}/rows``), their corrections (``/runs/{id}/readings/{group}/{index}``,
``.../strike``), and its finish and abort buttons.

They are the pages' own posts, never the API (whose routes never take the session
cookie): each comes from this site's page (``Origin``) and carries the session's form
token (:func:`rigserver.api.page_forms.form_writer`), and the session's key needs the
stand's write scope as in the API. Each goes the API's way once the key is known: a run is
opened by :func:`rigserver.api.cases.runs.open_run`, a row is stored by
:func:`rigserver.api.cases.readings.store_posted` (the same checks, the same ``seq``),
a row corrected by :func:`rigserver.api.cases.corrections.correct`, a run ended by
:func:`rigserver.api.cases.runs.end_run`. A refusal is one line in the
page's language (:func:`rigserver.web.entry.refusal_line`).
"""

from __future__ import annotations

import secrets
from collections.abc import Awaitable, Callable
from typing import Annotated
from urllib.parse import urlencode

from fastapi import APIRouter, Depends, Query, Request, Response
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import HTMLResponse, JSONResponse, RedirectResponse
from pydantic import ValidationError

from rigserver.api.auth import ApiKey
from rigserver.api.cases.corrections import correct
from rigserver.api.cases.found import load_run
from rigserver.api.cases.notes import write_notes
from rigserver.api.cases.readings import stand_of_run, store_posted
from rigserver.api.cases.runs import end_run
from rigserver.api.cases.runs import open_run as open_api_run
from rigserver.api.deps import Group, Index, Language, ServicesDep, require_write
from rigserver.api.media import media_type
from rigserver.api.page_forms import (
    FORM_TOKEN,
    LoginFirst,
    form_token,
    form_writer,
    read_form,
    require_page_read,
    writable_stands,
    writer_of,
)
from rigserver.api.problems import ApiProblem, storage_problem
from rigserver.reports.i18n import Lang, Messages, language_headers
from rigserver.storage.errors import StorageError
from rigserver.web.entry import FORM_HEADER, REASON_MISSING, refusal_line
from rigserver.web.new_run import (
    INVALID,
    NO_STAND,
    REQUIRED,
    Field,
    form_fields,
    new_run_page,
    read_posted,
    with_posted,
)
from schemas.corrections import CorrectionWrite, StrikeWrite
from schemas.problems import Problem
from schemas.runs import RunCreate, RunState
from schemas.stands import Stand, StandKind
from schemas.strict_json import strict_loads
from schemas.student_notes import StudentNotesWrite
from schemas.wire import Text

router = APIRouter(include_in_schema=False)
_IDEMPOTENCY = "idempotency_key"


def _stand(value: str) -> StandKind | None:
    try:
        return StandKind(value)
    except ValueError:
        return None


@router.get("/runs/new", response_class=HTMLResponse, dependencies=[Depends(require_page_read)])
def new_run_form(
    request: Request,
    services: ServicesDep,
    lang: Language,
    stand: Annotated[Text, Query(max_length=40)] = "",
) -> HTMLResponse:
    """The form that opens a run on ``stand`` (without one: the stands to choose from)."""
    t = Messages(lang)
    writer = writer_of(request, services)
    if writer is None:
        raise LoginFirst(f"/runs/new?{urlencode({'stand': stand, 'lang': lang})}")
    writable = writable_stands(writer)
    kind = _stand(stand)
    status, refusal = 200, ""
    if kind is not None and kind not in writable:
        status, refusal = 403, refusal_line(t, _scope_missing(kind))
        kind = None
    elif not writable:
        status, refusal = 403, t.gettext(NO_STAND)
    fields = form_fields(t, services.stands[kind], lang) if kind else None
    html = new_run_page(
        stand=services.stands[kind] if kind else None,
        stands=writable,
        fields=fields,
        lang=lang,
        form_token=form_token(request, services),
        idempotency_key=secrets.token_urlsafe(16),
        refusal=refusal,
    )
    return HTMLResponse(html, status_code=status, headers=language_headers(lang))


def _scope_missing(kind: StandKind) -> Problem:
    return Problem(
        title="Scope missing", status=403, detail=f"this key lacks the scope 'write:{kind}'"
    )


@router.post("/runs/new")
async def open_run(
    request: Request,
    services: ServicesDep,
    lang: Language,
    stand: Annotated[Text, Query(max_length=40)] = "",
) -> Response:
    """The new-run form posted: the run opened as ``POST /api/v1/runs`` opens it (the
    students' names its first words), then its page; else the form again, each refusal
    beside its field (422), or one line (403)."""
    t = Messages(lang)
    kind = _stand(stand)
    if kind is None:
        raise ApiProblem(422, "Invalid form", f"stand must be a stand kind, got {stand[:40]!r}")
    declared = services.stands[kind]
    fields = form_fields(t, declared, lang)
    names = [f.name for section in fields.values() for f in section]
    body = await request.body()  # at most ANONYMOUS_BODY_BYTES (rigserver.api.app.body_limit)
    form = read_form(body, (*names, FORM_TOKEN, _IDEMPOTENCY))
    back = f"/runs/new?{urlencode({'stand': kind.value, 'lang': lang})}"
    writer = form_writer(request, services, form.pop(FORM_TOKEN, ""), back)
    idempotency = form.pop(_IDEMPOTENCY, "") or None

    def again(errors: dict[str, str], refusal: str = "", status: int = 422) -> HTMLResponse:
        html = new_run_page(
            stand=declared,
            stands=writable_stands(writer),
            fields=with_posted(fields, form, errors),
            lang=lang,
            form_token=form_token(request, services),
            idempotency_key=idempotency or secrets.token_urlsafe(16),
            refusal=refusal,
        )
        return HTMLResponse(html, status_code=status, headers=language_headers(lang))

    if not writer.allows(f"write:{kind.value}"):
        return again({}, refusal_line(t, _scope_missing(kind)), 403)
    posted = read_posted(t, declared, form)
    if posted.errors:
        return again(posted.errors)
    try:
        create = RunCreate.model_validate(posted.body)
        words = StudentNotesWrite(students=posted.students)
    except ValidationError as exc:
        return again(_by_field(t, exc, fields))
    try:
        run, _ = await run_in_threadpool(open_api_run, services, writer, create, idempotency)
        if words.students:
            await run_in_threadpool(write_notes, services, run.id, words, writer)
    except ApiProblem as exc:
        errors = {e.field: e.message for e in exc.problem.errors if e.field in names}
        return again(errors, "" if errors else refusal_line(t, exc.problem), exc.problem.status)
    return RedirectResponse(f"/runs/{run.id}?lang={lang}", status_code=303)


def _by_field(t: Messages, exc: ValidationError, fields: dict[str, list[Field]]) -> dict[str, str]:
    """Pydantic's refusals by the form's field (``specimen.pin``; ``students`` for the
    names), in the page's language where it has the words."""
    names = {f.name for section in fields.values() for f in section}
    found: dict[str, str] = {}
    for err in exc.errors():
        loc = [str(p) for p in err["loc"]]
        name = ".".join(loc[:2]) if loc[0] in ("specimen", "test_plan") else loc[0]
        if name not in names:
            name = "operator" if loc[0] == "operator" else name
        if err["type"] in ("missing", "string_too_short", "too_short"):
            found.setdefault(name, t.gettext(REQUIRED))
        else:
            found.setdefault(name, t.gettext(INVALID).format(detail=err["msg"]))
    return found


@router.post("/runs/{run_id}/rows")
async def typed_row(
    run_id: str, request: Request, services: ServicesDep, lang: Language
) -> Response:
    """A row typed on the run's page (JSON as ``POST /api/v1/runs/{id}/readings`` takes
    it, one batch with its ``seq``), sent by ``entry.js`` with the session's form token in
    the ``X-Rig-Form`` header: the receipt (201; 200 for a ``seq`` stored before), or the
    refusal in one line of the page's language (``{"message": ...}``)."""

    async def store(writer: ApiKey, stand: Stand) -> Response:
        receipt = await store_posted(request, services, run_id, stand, writer)
        status = 200 if receipt.duplicate else 201
        return JSONResponse(receipt.model_dump(mode="json"), status_code=status)

    return await _page_write(run_id, request, services, lang, store)


@router.post("/runs/{run_id}/readings/{group}/{index}")
async def corrected_row(
    run_id: str,
    group: Group,
    index: Index,
    request: Request,
    services: ServicesDep,
    lang: Language,
) -> Response:
    """A row's cells corrected on the run's page (JSON as ``PATCH
    /api/v1/runs/{id}/readings/{group}/{index}`` takes it: ``values``, ``reason``), sent by
    ``entry.js`` as a typed row is: the row as it now reads, or the refusal in one line of
    the page's language (``{"message", "channel"}``: the cell it names, if one)."""
    return await _page_write(
        run_id,
        request,
        services,
        lang,
        _edit(run_id, group, index, request, services, CorrectionWrite),
    )


@router.post("/runs/{run_id}/readings/{group}/{index}/strike")
async def struck_row(
    run_id: str,
    group: Group,
    index: Index,
    request: Request,
    services: ServicesDep,
    lang: Language,
) -> Response:
    """A row struck out on the run's page (``{"reason"}``, as ``DELETE
    /api/v1/runs/{id}/readings/{group}/{index}`` takes it): as :func:`corrected_row`."""
    return await _page_write(
        run_id, request, services, lang, _edit(run_id, group, index, request, services, StrikeWrite)
    )


def _edit(
    run_id: str,
    group: str,
    index: int,
    request: Request,
    services: ServicesDep,
    kind: type[CorrectionWrite | StrikeWrite],
) -> Callable[[ApiKey, Stand], Awaitable[Response]]:
    """The correction of the request's body, made as the API makes it."""

    async def act(writer: ApiKey, stand: Stand) -> Response:
        body = await request.body()  # at most ANONYMOUS_BODY_BYTES (rigserver.api.app.body_limit)
        try:
            edit = kind.model_validate(strict_loads(body))
        except ValidationError as exc:
            raise _invalid(exc) from None
        except ValueError as exc:  # not JSON
            raise ApiProblem(422, "Invalid correction", f"the body is not JSON: {exc}") from None
        row = await run_in_threadpool(correct, services, run_id, group, index, edit, writer)
        return JSONResponse(row.model_dump(mode="json"))

    return act


def _invalid(exc: ValidationError) -> ApiProblem:
    """The first thing a correction's body lacks, as the API would name it."""
    err = exc.errors()[0]
    field = ".".join(str(p) for p in err["loc"])
    if field == "reason":
        return ApiProblem(422, REASON_MISSING, f"reason: {err['msg']}")
    return ApiProblem(422, "Invalid correction", f"{field}: {err['msg']}")


async def _page_write(
    run_id: str,
    request: Request,
    services: ServicesDep,
    lang: Lang,
    act: Callable[[ApiKey, Stand], Awaitable[Response]],
) -> Response:
    """A write of the run's page by ``entry.js`` (JSON, the session's form token in the
    ``X-Rig-Form`` header), ``act`` for a key that may write the run's stand; a refusal
    as one line of the page's language (``{"status", "message", "channel"}``)."""
    t = Messages(lang)
    stand: Stand | None = None
    try:
        writer = form_writer(
            request, services, request.headers.get(FORM_HEADER, ""), f"/runs/{run_id}"
        )
        stand = await stand_of_run(services, run_id)
        require_write(writer, stand.kind)
        media = media_type(request.headers.get("content-type"))
        if media != "application/json":
            raise ApiProblem(415, "Unsupported media type", "send application/json")
        return await act(writer, stand)
    except LoginFirst:
        problem = Problem(title="Key needed", status=401, detail="no session")
        return _refused(t, problem)
    except ApiProblem as exc:
        return _refused(t, exc.problem, stand)
    except StorageError as exc:
        return _refused(t, storage_problem(exc))


def _refused(t: Messages, problem: Problem, stand: Stand | None = None) -> JSONResponse:
    headers = {"Retry-After": "5"} if problem.status in (429, 503) else None
    field = problem.errors[0].field if problem.errors else ""
    return JSONResponse(
        {
            "status": problem.status,
            "message": refusal_line(t, problem, stand),
            "channel": field.removeprefix("values.") if field.startswith("values.") else "",
        },
        status_code=problem.status,
        headers=headers,
    )


async def _end(
    run_id: str, request: Request, services: ServicesDep, lang: Lang, state: RunState
) -> Response:
    body = await request.body()
    form = read_form(body, (FORM_TOKEN,))
    writer = form_writer(request, services, form.get(FORM_TOKEN, ""), f"/runs/{run_id}")
    run = await run_in_threadpool(load_run, services, run_id)
    if run.state is RunState.OPEN:  # a second press (another tab) finds it ended: its page
        await run_in_threadpool(end_run, run_id, services, writer, state)
    return RedirectResponse(f"/runs/{run_id}?lang={lang}", status_code=303)


@router.post("/runs/{run_id}/finish")
async def finish(run_id: str, request: Request, services: ServicesDep, lang: Language) -> Response:
    """The run page's "Finish the run": results computed, the run closed; back to its page."""
    return await _end(run_id, request, services, lang, RunState.FINISHED)


@router.post("/runs/{run_id}/abort")
async def abort(run_id: str, request: Request, services: ServicesDep, lang: Language) -> Response:
    """The run page's "Abort the run": closed without results; back to its page."""
    return await _end(run_id, request, services, lang, RunState.ABORTED)
