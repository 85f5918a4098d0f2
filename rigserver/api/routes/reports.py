"""``/runs/{id}/report.html|pdf``, ``results.csv`` and ``export.zip``: the run's report and
its data for download. The language comes from ``?lang=`` or ``Accept-Language``."""

from __future__ import annotations

import os
import tempfile
from datetime import UTC, datetime
from typing import Annotated

from fastapi import APIRouter, Query, Request
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import FileResponse, HTMLResponse, Response
from starlette.background import BackgroundTask

from rigserver.api.deps import ReadAccess, Services, ServicesDep
from rigserver.api.routes.runs import load_run
from rigserver.api.run_results import StoredReadings, results_payload
from rigserver.reports.export import export_zip, results_csv
from rigserver.reports.i18n import Lang, negotiate
from rigserver.reports.pdf import html_to_pdf
from rigserver.reports.run_report import build_report, render_report
from schemas.runs import Run

router = APIRouter(prefix="/runs/{run_id}", tags=["reports"], dependencies=[ReadAccess])

LangQuery = Annotated[
    Lang | None,
    Query(description="report language; without it, the best of Accept-Language (else en)"),
]


def _report_html(services: Services, run_id: str, lang: Lang) -> tuple[Run, str]:
    run = load_run(services, run_id)
    report = build_report(
        run=run,
        stand=services.stand_of(run),
        values=results_payload(services, run)["values"],
        readings=StoredReadings(services, run),
        lang=lang,
        made=datetime.now(UTC),
    )
    return run, render_report(report)


def _language(request: Request, lang: Lang | None) -> Lang:
    return negotiate(lang, request.headers.get("accept-language"))


def _vary(lang: Lang) -> dict[str, str]:
    return {"Content-Language": lang, "Vary": "Accept-Language"}


@router.get(
    "/report.html",
    summary="The run's report as a web page (the manual's tables, plots, conclusions)",
    response_class=HTMLResponse,
)
async def report_html(
    run_id: str, request: Request, services: ServicesDep, lang: LangQuery = None
) -> HTMLResponse:
    chosen = _language(request, lang)
    _, html = await run_in_threadpool(_report_html, services, run_id, chosen)
    return HTMLResponse(html, headers=_vary(chosen))


@router.get(
    "/report.pdf",
    summary="The run's report as an A4 PDF, from the same template",
    response_class=Response,
    responses={200: {"content": {"application/pdf": {}}}},
)
async def report_pdf(
    run_id: str, request: Request, services: ServicesDep, lang: LangQuery = None
) -> Response:
    chosen = _language(request, lang)
    run, html = await run_in_threadpool(_report_html, services, run_id, chosen)
    pdf = await run_in_threadpool(html_to_pdf, html)
    headers = {
        **_vary(chosen),
        "Content-Disposition": f'attachment; filename="{run.id}-report-{chosen}.pdf"',
    }
    return Response(pdf, media_type="application/pdf", headers=headers)


def _results_csv(services: Services, run_id: str) -> tuple[Run, str]:
    run = load_run(services, run_id)
    return run, results_csv(results_payload(services, run))


@router.get(
    "/results.csv",
    summary="The results as CSV: one row per quantity with its value and unit",
    response_class=Response,
    responses={200: {"content": {"text/csv": {}}}},
)
async def get_results_csv(run_id: str, services: ServicesDep) -> Response:
    run, text = await run_in_threadpool(_results_csv, services, run_id)
    return Response(
        text,
        media_type="text/csv",
        headers={"Content-Disposition": f'attachment; filename="{run.id}-results.csv"'},
    )


def _export(services: Services, run_id: str) -> tuple[Run, str]:
    run = load_run(services, run_id)
    handle, path = tempfile.mkstemp(prefix="rig-export-", suffix=".zip")
    try:
        with os.fdopen(handle, "wb") as target:
            export_zip(
                target,
                run=run,
                stand=services.stand_of(run),
                readings=StoredReadings(services, run),
                payload=results_payload(services, run),
            )
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
async def get_export(run_id: str, services: ServicesDep) -> FileResponse:
    run, path = await run_in_threadpool(_export, services, run_id)
    return FileResponse(
        path,
        media_type="application/zip",
        filename=f"{run.id}.zip",
        background=BackgroundTask(os.unlink, path),
    )
