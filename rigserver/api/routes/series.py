"""``/series``: named sets of runs (repeats, or a comparison by a factor) and their statistics,
the series report and the per-run table as CSV."""

from __future__ import annotations

from fastapi import APIRouter, Request, status
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import HTMLResponse, Response

from rigserver.api.cases.found import load_run
from rigserver.api.cases.series import (
    load_series,
    series_detail,
    series_report_answer,
)
from rigserver.api.deps import (
    CallerDep,
    Language,
    ReadAccess,
    Services,
    ServicesDep,
    WriteAccess,
    require_scope,
)
from rigserver.api.problems import ApiProblem
from rigserver.api.strict_json import StrictJsonRoute
from rigserver.reports.series_report import series_csv
from rigserver.storage.errors import RunNotFound
from schemas.series import (
    LAB_PARTS,
    SERIES_RUNS_LIMIT,
    Series,
    SeriesCreate,
    SeriesDetail,
    SeriesMemberAdd,
    SeriesPurpose,
)

router = APIRouter(prefix="/series", tags=["series"], route_class=StrictJsonRoute)

#: The scope that creates series and changes their runs (``write:*`` has it too).
WRITE_SERIES = "write:series"


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
    series_id: str, request: Request, services: ServicesDep, lang: Language
) -> Response:
    return await series_report_answer(request, services, series_id, lang, "html")


@router.get(
    "/{series_id}/report.pdf",
    summary="The series report as an A4 PDF",
    description=_RENDERED,
    response_class=Response,
    responses={200: {"content": {"application/pdf": {}}}},
    dependencies=[ReadAccess],
)
async def report_pdf(
    series_id: str, request: Request, services: ServicesDep, lang: Language
) -> Response:
    return await series_report_answer(request, services, series_id, lang, "pdf")
