"""Reports answered as files: rendered once per version on the render pool, then served with
their ``ETag`` (``If-None-Match`` answered 304)."""

from __future__ import annotations

import asyncio
import base64
from collections.abc import Callable, Mapping
from concurrent.futures import Future
from dataclasses import dataclass
from functools import partial

from fastapi import Request, Response
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import FileResponse

from rigserver.api.cases.found import load_run
from rigserver.api.deps import Services, client_of
from rigserver.api.problems import ApiProblem
from rigserver.api.report_files import ReportFile
from rigserver.api.report_jobs import Job, RunReportJob
from rigserver.api.run_results import StoredReadings, results_payload
from rigserver.reports.i18n import LANGS, Lang, language_headers
from rigserver.storage.errors import RunDamaged
from schemas.runs import Run, RunState
from schemas.sketches import Sketch
from schemas.student_notes import StudentNotes


def targets(target: ReportFile) -> dict[str, ReportFile]:
    """What one render writes: the page, and the PDF when it is asked for (made from the
    page, which then costs nothing more)."""
    return {
        fmt: target.sibling(fmt) for fmt in (("html", "pdf") if target.fmt == "pdf" else ("html",))
    }


@dataclass(frozen=True, slots=True)
class StudentsPart:
    """What the students put on a run, as its report prints it: their words, and the
    versions of their sketches (the latest of each item)."""

    notes: StudentNotes
    sketches: tuple[Sketch, ...] = ()


def run_target(
    services: Services, run: Run, lang: Lang, fmt: str
) -> tuple[ReportFile, StudentsPart]:
    """Where the run's report in ``lang`` and ``fmt`` is kept, named by the run and the
    students' words and sketches on it as they are now, and those (for its job)."""
    theirs = StudentsPart(services.notes.get(run.id), tuple(services.sketches.latest(run.id)))
    target = services.report_files.run_report(run, lang, fmt, theirs.notes, theirs.sketches)
    return target, theirs


def sketch_images(services: Services, run: Run, sketches: tuple[Sketch, ...]) -> dict[int, str]:
    """The images of these versions of the run's sketches, item -> a ``data:`` URI."""
    images: dict[int, str] = {}
    for sketch in sketches:
        found = services.sketches.image(run.id, sketch.item, sketch.version)
        if found is not None:
            encoded = base64.b64encode(found[1]).decode("ascii")
            images[sketch.item] = f"data:{sketch.media_type};base64,{encoded}"
    return images


def run_job(
    services: Services,
    run: Run,
    values: Mapping[str, object],
    target: ReportFile,
    theirs: StudentsPart,
) -> tuple[RunReportJob, bool]:
    """The job of ``target``, the report of ``run`` with what the students put on it, and
    whether it renders in this process (an open run, whose readings only the store has)."""
    in_process = run.state is RunState.OPEN
    job = RunReportJob(
        run,
        services.stand_of(run),
        dict(values),
        target.lang,
        {fmt: t.path for fmt, t in targets(target).items()},
        run_file=None if in_process else services.store.run_file(run.id),
        readings=StoredReadings(services, run) if in_process else None,
        notes=theirs.notes,
        sketches=sketch_images(services, run, theirs.sketches),
    )
    return job, in_process


def kept(
    services: Services, target: ReportFile, job: Callable[[], tuple[Job, bool]], key: str
) -> dict[str, bytes]:
    """The report of ``target`` as page and PDF bytes, rendered on the pool first if this
    version has none (blocks the calling thread: for an export that packs reports)."""
    if not target.path.exists():
        made, in_process = job()
        services.reports.render(target.render, key, made, in_process=in_process).result()
        for t in targets(target).values():
            t.prune()
    return {fmt: t.path.read_bytes() for fmt, t in targets(target).items()}


def file_answer(request: Request, target: ReportFile, headers: Mapping[str, str]) -> Response:
    """The report's file, or 304 when the client holds this version."""
    common = {"ETag": target.etag, "Cache-Control": "no-cache", **headers}
    if target.matches(request.headers.get("if-none-match")):
        return Response(status_code=304, headers=common)
    return FileResponse(target.path, media_type=target.media_type, headers=common)


async def rendered(future: Future[None], target: ReportFile) -> None:
    """Wait for a render; a damaged run file is a 409, any other failure a 500 that says
    so (logged once by the pool)."""
    try:
        await asyncio.wrap_future(future)
    except RunDamaged:
        raise  # 409, as every route of a damaged run answers
    except Exception as exc:
        raise ApiProblem(
            500, "Report not rendered", f"rendering the report failed: {type(exc).__name__}"
        ) from None
    for t in targets(target).values():
        t.prune()


def render_finished(services: Services, run_id: str, values: Mapping[str, object]) -> None:
    """Start rendering a finished run's reports in the background (both languages, page and
    PDF), where the pool has room; the first download renders what was not."""
    run = services.store.get_run(run_id)
    for lang in LANGS:
        target, theirs = run_target(services, run, lang, "pdf")
        if target.path.exists():
            continue
        job, in_process = run_job(services, run, values, target, theirs)
        future = services.reports.render_later(target.render, job, in_process=in_process)
        if future is not None:
            future.add_done_callback(partial(_prune_after, target))


def _prune_after(target: ReportFile, done: Future[None]) -> None:
    if not done.cancelled() and done.exception() is None:
        for t in targets(target).values():
            t.prune()


def _run_target(
    services: Services, run_id: str, lang: Lang, fmt: str
) -> tuple[Run, ReportFile, StudentsPart]:
    run = load_run(services, run_id)
    return run, *run_target(services, run, lang, fmt)


def _run_job(
    services: Services, run: Run, target: ReportFile, theirs: StudentsPart
) -> tuple[RunReportJob, bool]:
    return run_job(services, run, results_payload(services, run)["values"], target, theirs)


async def run_report_answer(
    request: Request, services: Services, run_id: str, lang: Lang, fmt: str
) -> tuple[Run, Response]:
    """The run's report in ``fmt``: its file, rendered first if this version has none."""
    run, target, theirs = await run_in_threadpool(_run_target, services, run_id, lang, fmt)
    job = partial(_run_job, services, run, target, theirs)
    return run, await report_answer(request, services, target, run.id, job)


async def report_answer(
    request: Request,
    services: Services,
    target: ReportFile,
    name: str,
    job: Callable[[], tuple[Job, bool]],
) -> Response:
    """The report ``target`` (of the run or series ``name``): its file, rendered on the pool
    first (``job``) if this version has none; a PDF is a download."""
    headers = language_headers(target.lang)
    if target.fmt == "pdf":
        headers["Content-Disposition"] = f'attachment; filename="{name}-report-{target.lang}.pdf"'
    if not target.path.exists() and not target.matches(request.headers.get("if-none-match")):
        made, in_process = await run_in_threadpool(job)
        future = services.reports.render(
            target.render, client_of(request.scope, services), made, in_process=in_process
        )
        await rendered(future, target)
    return file_answer(request, target, headers)


def run_report_kept(services: Services, run: Run, lang: Lang) -> bool:
    """Whether the run's report of this version in ``lang`` is rendered and kept."""
    return run_target(services, run, lang, "pdf")[0].path.exists()


def run_report_bytes(services: Services, run: Run, lang: Lang, key: str) -> dict[str, bytes]:
    """The run's report in ``lang``, ``html`` and ``pdf``: kept, or rendered on the pool."""
    target, theirs = run_target(services, run, lang, "pdf")
    return kept(services, target, lambda: _run_job(services, run, target, theirs), key)
