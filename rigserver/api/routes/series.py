"""``/series``: named sets of runs (repeats, or a comparison by a factor) and their statistics,
the series report and the per-run table as CSV."""

from __future__ import annotations

from dataclasses import replace
from typing import Annotated, Any

from fastapi import APIRouter, Query, Request, status
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import HTMLResponse, Response

from rigserver.analysis.series import Member, series_statistics
from rigserver.api.cases.runs import load_run
from rigserver.api.deps import (
    CallerDep,
    ReadAccess,
    Services,
    ServicesDep,
    WriteAccess,
    require_scope,
)
from rigserver.api.problems import ApiProblem
from rigserver.api.report_answers import (
    caller_key,
    file_answer,
    kept,
    rendered,
    sketch_images,
    targets,
)
from rigserver.api.report_files import ReportFile
from rigserver.api.report_jobs import SeriesReportJob
from rigserver.api.run_results import StoredReadings, results_payload
from rigserver.api.strict_json import StrictJsonRoute
from rigserver.reports.i18n import Lang, language_headers, negotiate
from rigserver.reports.lab_work import WorkRun
from rigserver.reports.series_report import series_context, series_csv
from rigserver.storage.errors import RunNotFound, SeriesNotFound, StorageError
from schemas.runs import RunState
from schemas.series import (
    LAB_PARTS,
    SERIES_RUNS_LIMIT,
    Series,
    SeriesCreate,
    SeriesDetail,
    SeriesMemberAdd,
    SeriesPurpose,
    is_series_id,
)

router = APIRouter(prefix="/series", tags=["series"], route_class=StrictJsonRoute)

#: The scope that creates series and changes their runs (``write:*`` has it too).
WRITE_SERIES = "write:series"

LangQuery = Annotated[
    Lang | None,
    Query(description="report language; without it, the best of Accept-Language (else en)"),
]


def load_series(services: Services, series_id: str) -> Series:
    if not is_series_id(series_id):
        raise SeriesNotFound(
            f"{series_id[:40]!r} is not a series id (they look like s-0123456789ab)"
        )
    return services.series.get(series_id)


def series_detail(services: Services, series_id: str) -> SeriesDetail:
    """The series, each member run with its results (computed on what an open run holds),
    and the statistics."""
    return _detail(services, series_id)[0]


def _detail(services: Services, series_id: str) -> tuple[SeriesDetail, list[Member]]:
    series = load_series(services, series_id)
    members: list[Member] = []
    missing: list[str] = []
    for member in series.members:
        try:
            run = services.store.get_run(member.run_id)
        except StorageError as exc:
            missing.append(f"{member.run_id}: {exc}")
            continue
        values = None
        if run.state is not RunState.ABORTED:
            values = results_payload(services, run)["values"]
        members.append(Member(run=run, level=member.level, values=values))
    return series_statistics(series, members, missing), members


@router.post(
    "",
    status_code=status.HTTP_201_CREATED,
    summary="Open a series: repeats of one test, or a comparison by a named factor",
    description=f"Needs a key with the scope `{WRITE_SERIES}` (or `write:*`).",
    dependencies=[WriteAccess],
)
def create_series(body: SeriesCreate, services: ServicesDep, caller: CallerDep) -> Series:
    require_scope(caller, WRITE_SERIES)
    return services.series.create(body)


@router.get("", summary="Every series, newest first", dependencies=[ReadAccess])
def list_series(services: ServicesDep) -> list[Series]:
    return services.series.list()


@router.get(
    "/{series_id}",
    summary="A series: its runs, their levels and the statistics of every headline result",
    description="Per result: n, mean, standard deviation, standard error, the 95 % interval "
    "of the mean (Student's t), the repeatability standard deviation and Grubbs' outlier "
    "test (flagged, never removed); for a comparison also per level, and Welch's t-test "
    "(two levels) or one-way ANOVA. Open runs count with what they hold so far.",
    dependencies=[ReadAccess],
)
async def get_series(series_id: str, services: ServicesDep) -> SeriesDetail:
    return await run_in_threadpool(series_detail, services, series_id)


def _add(services: Services, series_id: str, body: SeriesMemberAdd) -> Series:
    series = load_series(services, series_id)
    run = load_run(services, body.run_id)
    if series.purpose is SeriesPurpose.COMPARISON and body.level is None:
        raise ApiProblem(
            422,
            "Level required",
            f"series {series.id} compares by {series.factor!r}: give the run's level",
        )
    if series.purpose is SeriesPurpose.REPEATABILITY and body.level is not None:
        raise ApiProblem(
            422, "No levels in a repeatability series", "its runs are repeats of one test"
        )
    parts = LAB_PARTS.get(run.stand)
    if series.purpose is SeriesPurpose.LAB and parts and body.level not in parts:
        raise ApiProblem(
            422,
            "Part of the lab work required",
            f"series {series.id} is a lab work: give the run's level as the manual's part it "
            f"is, one of {', '.join(parts)}; got {body.level!r}",
        )
    if len(series.members) >= SERIES_RUNS_LIMIT:
        raise ApiProblem(409, "Series full", f"a series holds at most {SERIES_RUNS_LIMIT} runs")
    for member in series.members:
        try:
            other = services.store.get_run(member.run_id)
        except RunNotFound:
            continue
        if other.stand is not run.stand:
            raise ApiProblem(
                409,
                "Run of another stand",
                f"series {series.id} holds {other.stand.value} runs; "
                f"run {run.id} is a {run.stand.value} run",
            )
        break
    # the checks above saw the series before this add: the store checks both again in the
    # transaction that adds the run (SeriesFull, OtherStand: 409), for adds at once
    return services.series.add(series.id, run.id, body.level, stand=run.stand.value)


@router.post(
    "/{series_id}/runs",
    status_code=status.HTTP_201_CREATED,
    summary="Add a run to a series (a run may belong to several)",
    description=f"Needs the scope `{WRITE_SERIES}`. All runs of a series are of one stand; "
    "in a comparison each run has a level of the factor; in a lab work (purpose `lab`) "
    "the manual's part it is (SMTs-2: `wear`, `adhesive`, `oxidative`).",
    dependencies=[WriteAccess],
)
async def add_run(
    series_id: str, body: SeriesMemberAdd, services: ServicesDep, caller: CallerDep
) -> Series:
    require_scope(caller, WRITE_SERIES)
    return await run_in_threadpool(_add, services, series_id, body)


@router.delete(
    "/{series_id}/runs/{run_id}",
    summary="Take a run out of a series (the run itself stays)",
    description=f"Needs the scope `{WRITE_SERIES}`.",
    dependencies=[WriteAccess],
)
def remove_run(series_id: str, run_id: str, services: ServicesDep, caller: CallerDep) -> Series:
    require_scope(caller, WRITE_SERIES)
    series = load_series(services, series_id)
    return services.series.remove(series.id, run_id)


@router.get(
    "/{series_id}/runs.csv",
    summary="The per-run table as CSV: one row per run, one column per headline result",
    response_class=Response,
    responses={200: {"content": {"text/csv": {}}}},
    dependencies=[ReadAccess],
)
async def runs_csv(series_id: str, services: ServicesDep) -> Response:
    detail = await run_in_threadpool(series_detail, services, series_id)
    return Response(
        series_csv(detail),
        media_type="text/csv",
        headers={"Content-Disposition": f'attachment; filename="{detail.id}-runs.csv"'},
    )


def series_view(
    services: Services, series_id: str, lang: Lang
) -> tuple[SeriesDetail, dict[str, Any]]:
    """The series' statistics and what its report and page show of them."""
    detail, members = _detail(services, series_id)
    context = series_context(
        detail,
        values={m.run.id: m.values for m in members},
        readings={m.run.id: StoredReadings(services, m.run) for m in members},
        lang=lang,
    )
    return detail, context


def _prepare(services: Services, series_id: str, lang: Lang, fmt: str) -> ReportFile:
    """Where the series report of this version is: the series and its members' versions."""
    series = load_series(services, series_id)
    runs = []
    for member in series.members:
        try:
            runs.append(services.store.get_run(member.run_id))
        except StorageError:
            continue
    if not _lab_work(series):
        return services.report_files.series_report(series, runs, lang, fmt)
    notes = [services.notes.get(r.id) for r in runs]
    sketches = [s for r in runs for s in services.sketches.latest(r.id)]
    return services.report_files.series_report(series, runs, lang, fmt, notes, sketches)


def _lab_work(series: Series) -> bool:
    """Whether the series' report is a lab work's (its runs at the manual's parts)."""
    return series.purpose is SeriesPurpose.LAB


def _job(services: Services, series_id: str, target: ReportFile) -> tuple[SeriesReportJob, bool]:
    """The series report's job; rendered in this process if a member is open (its readings
    are only in the store)."""
    detail, members = _detail(services, series_id)
    files = {fmt: t.path for fmt, t in targets(target).items()}
    open_runs = {m.run.id: m.run for m in members if m.run.state is RunState.OPEN}
    job = SeriesReportJob(
        detail,
        values={m.run.id: m.values for m in members},
        lang=target.lang,
        targets=files,
        run_files={
            m.run.id: services.store.run_file(m.run.id)
            for m in members
            if m.run.id not in open_runs
        },
        readings={run_id: StoredReadings(services, run) for run_id, run in open_runs.items()},
    )
    if _lab_work(detail) and members and members[0].run.stand in LAB_PARTS:
        work = tuple(
            WorkRun(
                m.run,
                m.level or "",
                m.values,
                services.notes.get(m.run.id),
                sketch_images(services, m.run, tuple(services.sketches.latest(m.run.id))),
            )
            for m in members
        )
        job = replace(job, work=work, stand=services.stand_of(members[0].run))
    return job, bool(open_runs)


def report_kept(services: Services, series_id: str, lang: Lang) -> bool:
    """Whether the series report of this version in ``lang`` is rendered and kept."""
    return _prepare(services, series_id, lang, "pdf").path.exists()


def report_bytes(services: Services, series_id: str, lang: Lang, key: str) -> dict[str, bytes]:
    """The series report in ``lang``, ``html`` and ``pdf``: kept, or rendered on the pool."""
    target = _prepare(services, series_id, lang, "pdf")
    return kept(services, target, lambda: _job(services, series_id, target), key)


async def _report(
    request: Request, services: Services, series_id: str, lang: Lang, fmt: str
) -> Response:
    target = await run_in_threadpool(_prepare, services, series_id, lang, fmt)
    headers = language_headers(lang)
    if fmt == "pdf":
        headers["Content-Disposition"] = f'attachment; filename="{series_id}-report-{lang}.pdf"'
    if not target.path.exists() and not target.matches(request.headers.get("if-none-match")):
        job, in_process = await run_in_threadpool(_job, services, series_id, target)
        future = services.reports.render(
            target.render, caller_key(request, services), job, in_process=in_process
        )
        await rendered(future, target)
    return file_answer(request, target, headers)


_RENDERED = (
    "Rendered once per version of the series (its runs, their levels and each run's "
    "version), language and deployment, then kept: the answer carries an ETag "
    "(If-None-Match answered 304). 503 with Retry-After while the server renders as many "
    "reports as it may, or this key's share of them."
)


@router.get(
    "/{series_id}/report.html",
    summary="The series report: the per-run table, the statistics and the overlay plots",
    description=_RENDERED,
    response_class=HTMLResponse,
    dependencies=[ReadAccess],
)
async def report_html(
    series_id: str, request: Request, services: ServicesDep, lang: LangQuery = None
) -> Response:
    chosen = negotiate(lang, request.headers.get("accept-language"))
    return await _report(request, services, series_id, chosen, "html")


@router.get(
    "/{series_id}/report.pdf",
    summary="The series report as an A4 PDF",
    description=_RENDERED,
    response_class=Response,
    responses={200: {"content": {"application/pdf": {}}}},
    dependencies=[ReadAccess],
)
async def report_pdf(
    series_id: str, request: Request, services: ServicesDep, lang: LangQuery = None
) -> Response:
    chosen = negotiate(lang, request.headers.get("accept-language"))
    return await _report(request, services, series_id, chosen, "pdf")
