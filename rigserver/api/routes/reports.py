"""``/runs/{id}/report.html|pdf``, ``results.csv`` and ``export.zip``: the run's report and
its data for download. The language comes from ``?lang=`` or ``Accept-Language``."""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from typing import Annotated

from fastapi import APIRouter, Depends, Query, Request
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import FileResponse, HTMLResponse, Response
from starlette.background import BackgroundTask

from rigserver.api.cases.found import load_run
from rigserver.api.cases.reports import run_report_answer
from rigserver.api.deps import Language, ReadAccess, Services, ServicesDep
from rigserver.api.problems import ApiProblem
from rigserver.api.run_results import StoredReadings, results_payload
from rigserver.reports.export import (
    DIALECTS,
    CsvDialect,
    Dialect,
    export_members,
    export_zip,
    results_csv,
)
from rigserver.reports.i18n import Lang, Messages
from rigserver.reports.x3p import PROFILE_GROUP, NoProfile, profile_group, profile_x3p
from schemas.runs import Run

router = APIRouter(prefix="/runs/{run_id}", tags=["reports"], dependencies=[ReadAccess])

_RENDERED = (
    "Rendered once per version of the run (its readings, state, results and the students' "
    "words and sketches), language and "
    "deployment, then kept: the answer carries an ETag, and If-None-Match with it is "
    "answered 304. 503 with Retry-After while the server renders as many reports as it "
    "may, or this key's share of them."
)


@router.get(
    "/report.html",
    summary="The run's report as a web page (the manual's tables, plots, conclusions)",
    description=_RENDERED,
    response_class=HTMLResponse,
)
async def report_html(
    run_id: str, request: Request, services: ServicesDep, lang: Language
) -> Response:
    _, answer = await run_report_answer(request, services, run_id, lang, "html")
    return answer


@router.get(
    "/report.pdf",
    summary="The run's report as an A4 PDF, from the same template",
    description=_RENDERED,
    response_class=Response,
    responses={200: {"content": {"application/pdf": {}}}},
)
async def report_pdf(
    run_id: str, request: Request, services: ServicesDep, lang: Language
) -> Response:
    _, answer = await run_report_answer(request, services, run_id, lang, "pdf")
    return answer


LabelsQuery = Annotated[
    Lang | None,
    Query(description="language of the labels; without it, Russian for excel-ru, else en"),
]
DialectQuery = Annotated[
    Dialect,
    Query(
        description="csv (comma, decimal point) or excel-ru (semicolon, decimal comma, "
        "UTF-8 BOM; labels in Russian unless lang says otherwise)"
    ),
]


@dataclass(frozen=True, slots=True)
class _Tables:
    """How a download writes its tables: the labels' words and the CSV dialect."""

    t: Messages
    dialect: CsvDialect


def _tables(lang: LabelsQuery = None, dialect: DialectQuery = "csv") -> _Tables:
    """The labels in ``lang``, else in Russian for ``excel-ru``, else in English (a download
    is not negotiated: the same link gives the same file)."""
    chosen = lang if lang is not None else ("ru" if dialect == "excel-ru" else "en")
    return _Tables(Messages(chosen), DIALECTS[dialect])


TablesDep = Annotated[_Tables, Depends(_tables)]


def _results_csv(services: Services, run_id: str, tables: _Tables) -> tuple[Run, str]:
    run = load_run(services, run_id)
    text = results_csv(
        results_payload(services, run),
        stand=services.stand_of(run),
        t=tables.t,
        dialect=tables.dialect,
    )
    return run, text


@router.get(
    "/results.csv",
    summary="The single results as CSV: one row per quantity with its label, its value in "
    "the display unit and the unit (per-row tables and plot series: export.zip, results)",
    response_class=Response,
    responses={200: {"content": {"text/csv": {}}}},
)
async def get_results_csv(run_id: str, services: ServicesDep, tables: TablesDep) -> Response:
    run, text = await run_in_threadpool(_results_csv, services, run_id, tables)
    return Response(
        text,
        media_type="text/csv; charset=utf-8",
        headers={"Content-Disposition": f'attachment; filename="{run.id}-results.csv"'},
    )


def _export(services: Services, run_id: str, tables: _Tables) -> tuple[Run, str]:
    run = load_run(services, run_id)
    handle, path = tempfile.mkstemp(prefix="rig-export-", suffix=".zip")
    try:
        with os.fdopen(handle, "wb") as target:
            members = export_members(
                run=run,
                stand=services.stand_of(run),
                readings=StoredReadings(services, run),
                payload=results_payload(services, run),
                t=tables.t,
                dialect=tables.dialect,
            )
            export_zip(target, run.id, members)
    except BaseException:
        os.unlink(path)
        raise
    return run, path


@router.get(
    "/export.zip",
    summary="Everything of the run in one zip: a CSV per channel group, the results "
    "(CSV and JSON) and the run's metadata",
    response_class=FileResponse,
    responses={200: {"content": {"application/zip": {}}}},
)
async def get_export(run_id: str, services: ServicesDep, tables: TablesDep) -> FileResponse:
    run, path = await run_in_threadpool(_export, services, run_id, tables)
    return FileResponse(
        path,
        media_type="application/zip",
        filename=f"{run.id}.zip",
        background=BackgroundTask(os.unlink, path),
    )


def _profile_x3p(services: Services, run_id: str, group: str) -> tuple[Run, bytes]:
    run = load_run(services, run_id)
    try:
        chosen = profile_group(services.stand_of(run).groups, group)
        return run, profile_x3p(run, chosen, StoredReadings(services, run))
    except NoProfile as exc:
        raise ApiProblem(404, "No profile", f"run {run.id}: {exc}") from None


@router.get(
    "/profile.x3p",
    summary="The traced profile as an X3P file (ISO 25178-72), for other surface software",
    response_class=Response,
    responses={200: {"content": {"application/x-x3p": {}}}},
)
async def get_profile_x3p(
    run_id: str,
    services: ServicesDep,
    group: Annotated[
        str, Query(description="the channel group of the profile (x, y)", max_length=40)
    ] = PROFILE_GROUP,
) -> Response:
    run, data = await run_in_threadpool(_profile_x3p, services, run_id, group)
    return Response(
        data,
        media_type="application/x-x3p",
        headers={"Content-Disposition": f'attachment; filename="{run.id}-{group}.x3p"'},
    )
