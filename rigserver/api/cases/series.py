"""Series: loaded (a 404 that says why), with each member's results and the statistics,
and their report answered as the run's is (:mod:`.reports`)."""

from __future__ import annotations

from dataclasses import replace
from functools import partial
from typing import Any

from fastapi import Request
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import Response

from rigserver.analysis.series import Member, series_statistics
from rigserver.api.cases.reports import kept, report_answer, sketch_images, targets
from rigserver.api.deps import (
    Services,
)
from rigserver.api.report_files import ReportFile
from rigserver.api.report_jobs import SeriesReportJob
from rigserver.api.run_results import StoredReadings, results_payload
from rigserver.reports.i18n import Lang
from rigserver.reports.lab_work import WorkRun
from rigserver.reports.series_report import series_context
from rigserver.storage.errors import SeriesNotFound, StorageError
from schemas.runs import RunState
from schemas.series import (
    LAB_PARTS,
    Series,
    SeriesDetail,
    SeriesPurpose,
    is_series_id,
)


def load_series(services: Services, series_id: str) -> Series:
    if not is_series_id(series_id):
        raise SeriesNotFound(
            f"{series_id[:40]!r} is not a series id (they look like s-0123456789ab)"
        )
    return services.series.get(series_id)


def series_detail(services: Services, series_id: str) -> SeriesDetail:
    """The series, each member run with its results (computed on what an open run holds),
    and the statistics."""
    return detail_and_members(services, series_id)[0]


def detail_and_members(services: Services, series_id: str) -> tuple[SeriesDetail, list[Member]]:
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


def series_view(
    services: Services, series_id: str, lang: Lang
) -> tuple[SeriesDetail, dict[str, Any]]:
    """The series' statistics and what its report and page show of them."""
    detail, members = detail_and_members(services, series_id)
    context = series_context(
        detail,
        values={m.run.id: m.values for m in members},
        readings={m.run.id: StoredReadings(services, m.run) for m in members},
        lang=lang,
    )
    return detail, context


def _series_target(services: Services, series_id: str, lang: Lang, fmt: str) -> ReportFile:
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


def _series_job(
    services: Services, series_id: str, target: ReportFile
) -> tuple[SeriesReportJob, bool]:
    """The series report's job; rendered in this process if a member is open (its readings
    are only in the store)."""
    detail, members = detail_and_members(services, series_id)
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


def series_report_kept(services: Services, series_id: str, lang: Lang) -> bool:
    """Whether the series report of this version in ``lang`` is rendered and kept."""
    return _series_target(services, series_id, lang, "pdf").path.exists()


def series_report_bytes(
    services: Services, series_id: str, lang: Lang, key: str
) -> dict[str, bytes]:
    """The series report in ``lang``, ``html`` and ``pdf``: kept, or rendered on the pool."""
    target = _series_target(services, series_id, lang, "pdf")
    return kept(services, target, lambda: _series_job(services, series_id, target), key)


async def series_report_answer(
    request: Request, services: Services, series_id: str, lang: Lang, fmt: str
) -> Response:
    """The series report in ``fmt``: its file, rendered first if this version has none."""
    target = await run_in_threadpool(_series_target, services, series_id, lang, fmt)
    job = partial(_series_job, services, series_id, target)
    return await report_answer(request, services, target, series_id, job)
