"""Runs and series as ``.eln`` archives (a zipped RO-Crate 1.1, :mod:`rigserver.reports.eln`):
``GET /runs/{id}/export.eln``, ``GET /series/{id}/export.eln`` and ``POST /runs/import``,
which recreates a run exported by a rig server under a new id (naming the original)."""

from __future__ import annotations

import itertools
import math
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator, Mapping
from contextlib import ExitStack
from datetime import UTC, datetime
from functools import partial
from pathlib import Path
from typing import IO, Any

import numpy as np
from fastapi import APIRouter, Request, Response, status
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import FileResponse, JSONResponse
from pydantic import ValidationError
from starlette.background import BackgroundTask

from rigserver.analysis import Readings, analyse
from rigserver.api import sketch_images
from rigserver.api.auth import ApiKey
from rigserver.api.cases.found import load_run
from rigserver.api.cases.notes import author
from rigserver.api.cases.reports import run_report_bytes, run_report_kept
from rigserver.api.cases.runs import snapshot
from rigserver.api.cases.series import (
    detail_and_members,
    load_series,
    series_report_bytes,
    series_report_kept,
)
from rigserver.api.cases.sketches import sketch_item
from rigserver.api.deps import (
    ReadAccess,
    Services,
    ServicesDep,
    WriteAccess,
    caller_of,
    client_of,
    require_write,
    services_of,
)
from rigserver.api.examples import ELN_EXAMPLE, file_body
from rigserver.api.media import media_type
from rigserver.api.problems import ApiProblem, violations
from rigserver.api.report_jobs import FileReadings
from rigserver.api.run_results import StoredReadings, results_payload
from rigserver.api.series_export import Progress, Render
from rigserver.reports.eln import (
    ELN_MEDIA_TYPE,
    Publisher,
    RunPart,
    SeriesPart,
    licence_of,
    sketch_member,
    write_run_archive,
    write_series_archive,
)
from rigserver.reports.eln_read import (
    ROOM_STEP,
    ArchivedRun,
    ArchiveRefused,
    ImportLimits,
    NoRoom,
    RunArchive,
    json_member,
    room,
)
from rigserver.reports.i18n import LANGS, Lang
from rigserver.reports.series_report import series_csv
from rigserver.storage.archived import IMPORT_ROWS, file_batches, file_corrections, summary
from rigserver.storage.errors import RunNotFound, StorageError
from schemas.channels import check_cell, check_columns
from schemas.corrections import Correction
from schemas.runs import ImportedFrom, Run, RunCreate, RunState, new_run_id
from schemas.stands import MEASUREMENTS, Stand
from schemas.student_notes import StudentNotesWrite

router = APIRouter(tags=["eln"])


#: Tries for a free id when an imported run's id is taken (ids carry 32 random bits).
ID_TRIES = 3


def _publisher(request: Request) -> Publisher:
    return Publisher(str(request.base_url))


#: Whose share of the report pool an export's renders take
_EXPORT = "(.eln export)"


def _reports(render: Callable[[Lang], dict[str, bytes]]) -> dict[str, bytes]:
    """The report in both languages, as a web page and as a PDF (the kept files, rendered
    on the report pool when missing: rigserver.api.report_pool)."""
    found: dict[str, bytes] = {}
    for lang in LANGS:
        files = render(lang)
        found[f"report-{lang}.html"] = files["html"]
        found[f"report-{lang}.pdf"] = files["pdf"]
    return found


def _references(services: Services, run: Run) -> dict[str, tuple[Run, Path]]:
    """The profilometer runs the run's specimen names that this server holds."""
    found = {}
    for key, value in run.specimen.items():
        if not key.endswith("_profile_run"):
            continue
        try:
            other = services.store.get_run(str(value))
        except RunNotFound:
            continue
        found[other.id] = (other, services.store.run_file(other.id))
    return found


def _run_part(services: Services, run: Run) -> RunPart:
    return RunPart(
        run=run,
        stand=services.stand_of(run),
        readings=StoredReadings(services, run),
        payload=results_payload(services, run),
        run_file=services.store.run_file(run.id),
        reports=_reports(lambda lang: run_report_bytes(services, run, lang, _EXPORT)),
        references=_references(services, run),
        sketches=_sketches(services, run),
        notes=services.notes.history(run.id),
    )


def _sketches(services: Services, run: Run) -> dict[str, bytes]:
    """Every version of the students' sketches on the run, by their member's name."""
    found = {}
    for sketch in services.sketches.history(run.id):
        kept = services.sketches.image(run.id, sketch.item, sketch.version)
        if kept is not None:
            found[sketch_member(sketch.item, sketch.version, sketch.media_type)] = kept[1]
    return found


def _archived_sketches(found: ArchivedRun, run: Run) -> list[tuple[int, sketch_images.SketchImage]]:
    """The archive's sketches checked as an upload is (422 naming the member), in the order
    of their versions."""
    images = []
    for name, sketch in sorted(found.sketches.items(), key=lambda s: (s[1].item, s[1].version)):
        try:
            sketch_item(run, sketch.item)
            data = sketch.path.read_bytes()
            images.append((sketch.item, sketch_images.checked(data, sketch.media_type)))
        except ApiProblem as exc:
            raise _refused(ArchiveRefused(name, exc.problem.detail or "")) from None
    return images


def _written(write: Callable[[IO[bytes]], None], prefix: str) -> str:
    """A temporary file that ``write`` fills (removed if it fails)."""
    handle, path = tempfile.mkstemp(prefix=prefix, suffix=".eln")
    try:
        with os.fdopen(handle, "wb") as target:
            write(target)
    except BaseException:
        os.unlink(path)
        raise
    return path


def _export_run(services: Services, run_id: str, publisher: Publisher) -> tuple[str, str]:
    run = load_run(services, run_id)
    part = _run_part(services, run)
    licence = licence_of(services.settings.license)
    made = datetime.now(UTC)
    path = _written(
        lambda target: write_run_archive(
            target, part, made=made, publisher=publisher, licence=licence
        ),
        "rig-eln-",
    )
    return run.id, path


def _export_series(services: Services, series_id: str, publisher: Publisher) -> tuple[str, str]:
    detail, members = detail_and_members(services, series_id)
    series = SeriesPart(
        detail=detail,
        runs_csv=series_csv(detail),
        reports=_reports(lambda lang: series_report_bytes(services, series_id, lang, _EXPORT)),
    )
    licence = licence_of(services.settings.license)
    made = datetime.now(UTC)
    runs = (_run_part(services, m.run) for m in members)
    path = _written(
        lambda target: write_series_archive(
            target, series, runs, made=made, publisher=publisher, licence=licence
        ),
        "rig-eln-",
    )
    return detail.id, path


def _archive_response(name: str, path: str) -> FileResponse:
    return FileResponse(
        path,
        media_type=ELN_MEDIA_TYPE,
        filename=f"{name}.eln",
        background=BackgroundTask(os.unlink, path),
    )


_ELN_ANSWER: dict[int | str, dict[str, Any]] = {200: {"content": {ELN_MEDIA_TYPE: {}}}}


@router.get(
    "/runs/{run_id}/export.eln",
    summary="The run as an .eln archive (RO-Crate 1.1): its file, CSVs, reports, metadata",
    description="The ELN consortium's format, which eLabFTW, Kadi4Mat, PASTA, SampleDB, "
    "RSpace and NOMAD import: one root folder with ro-crate-metadata.json (schema.org and "
    "tribAIn terms: the run, operator, stand and limits of error, specimens and materials, "
    "rig's version, the results with units and uncertainties, the licence) and the run's "
    "HDF5 file, the tidy CSVs and the report in English and Russian (docs/eln.md).",
    response_class=FileResponse,
    responses=_ELN_ANSWER,
    dependencies=[ReadAccess],
)
async def export_run(run_id: str, request: Request, services: ServicesDep) -> FileResponse:
    name, path = await run_in_threadpool(_export_run, services, run_id, _publisher(request))
    return _archive_response(name, path)


@router.get(
    "/series/{series_id}/export.eln",
    summary="The series as an .eln archive: each run's folder, the statistics, the report",
    description="When reports the archive packs are not rendered yet, they are rendered in "
    "the background and the request is answered 202 at once, with `Retry-After`, "
    "`Location` (this URL) and the progress (`reports_done` of `reports_total`): ask again "
    "until it answers 200 with the archive.",
    response_class=FileResponse,
    responses={**_ELN_ANSWER, 202: {"description": "the archive's reports are rendering"}},
    dependencies=[ReadAccess],
)
async def export_series(series_id: str, request: Request, services: ServicesDep) -> Response:
    missing = await run_in_threadpool(_missing_reports, services, series_id)
    if missing:
        progress = services.exports.start(series_id, missing)
        return _preparing(series_id, progress, services)
    name, path = await run_in_threadpool(_export_series, services, series_id, _publisher(request))
    return _archive_response(name, path)


def _missing_reports(services: Services, series_id: str) -> list[Render]:
    """The reports a series archive packs that are not rendered yet: each member run's and
    the series', in each language; each a render to call."""
    _, members = detail_and_members(services, series_id)
    missing: list[Render] = []
    for lang in LANGS:
        for member in members:
            run = member.run
            if not run_report_kept(services, run, lang):
                missing.append(partial(run_report_bytes, services, run, lang, _EXPORT))
        if not series_report_kept(services, series_id, lang):
            missing.append(partial(series_report_bytes, services, series_id, lang, _EXPORT))
    return missing


def _preparing(series_id: str, progress: Progress, services: Services) -> JSONResponse:
    """202: the archive's reports are being rendered; where and when to ask again."""
    if progress.failed is not None and not progress.running:
        said = f"the reports of the archive could not be rendered: {progress.failed}"
        raise ApiProblem(500, "Export failed", f"{said}; ask again to try once more")
    here = f"/api/v1/series/{series_id}/export.eln"
    return JSONResponse(
        _status(progress),
        status_code=202,
        headers={
            "Location": here,
            "Retry-After": f"{services.settings.retry_after:g}",
            "Cache-Control": "no-store",
        },
    )


def _status(progress: Progress | None) -> dict[str, Any]:
    if progress is None:
        return {"state": "none", "reports_done": 0, "reports_total": 0}
    state = "failed" if progress.failed else "rendering" if progress.running else "ready"
    return {
        "state": state,
        "reports_done": progress.done,
        "reports_total": progress.total,
        "detail": progress.failed or f"{progress.done} of {progress.total} reports rendered",
    }


@router.get(
    "/series/{series_id}/export.eln/status",
    summary="How far the series archive's reports are rendered (the series page shows it)",
    dependencies=[ReadAccess],
)
async def export_series_status(series_id: str, services: ServicesDep) -> dict[str, Any]:
    await run_in_threadpool(load_series, services, series_id)
    return _status(services.exports.progress(series_id))


# --- import ------------------------------------------------------------------------------


def _refused(exc: ArchiveRefused) -> ApiProblem:
    errors = violations([{"loc": [exc.member], "msg": exc.detail}])
    return ApiProblem(422, "Archive refused", str(exc), errors)


def _recorded(services: Services, text: bytes) -> Run:
    """The run of an archive's run.json, read strictly (no nesting beyond the limit) and
    checked as ``POST /runs`` checks a run it opens (:class:`RunCreate`, the stand's
    configuration schema): 422 naming the field and its limit as that route does."""
    try:
        tree = json_member("run.json", text)
    except ArchiveRefused as exc:
        raise _refused(exc) from None
    try:
        stored = Run.model_validate(tree)
        opened = RunCreate.model_validate(stored.model_dump(mode="json", include=OPENED))
    except ValidationError as exc:
        errors = violations(exc.errors(), "run.json.")
        raise ApiProblem(422, "Archive refused", errors[0].message, errors) from None
    return stored.model_copy(update={"configuration": snapshot(services, opened, "run.json.")})


#: What of a stored run a lab PC posts to open it.
OPENED = set(RunCreate.model_fields)


def _unpack(
    services: Services, caller: ApiKey | None, archive: Path, directory: Path
) -> tuple[ArchivedRun, Run]:
    """The archive checked and its run as rig wrote it (run.json); 422 naming the member.
    The caller's scope is checked from run.json before anything else is unpacked."""
    settings = services.settings
    limits = ImportLimits(settings.import_unpacked_bytes, settings.import_disk_reserve)
    try:
        with archive.open("rb") as source, RunArchive(source, limits) as crate:
            run = _recorded(services, crate.run_json())
            require_write(caller, run.stand)
            found = crate.extract(directory)
    except NoRoom as exc:
        raise ApiProblem(507, "Storage full", str(exc)) from None
    except ArchiveRefused as exc:
        raise _refused(exc) from None
    if run.id != found.run_id:
        raise _refused(ArchiveRefused("run.json", f"holds run {run.id}, not {found.run_id}"))
    return found, run


def _corrections(path: Path, run: Run, stand: Stand) -> list[Correction]:
    """The corrections an archive's run file holds, each of a row it has and a value its
    channel's limit takes (else 422 naming the file)."""
    member = f"{run.id}.h5"
    try:
        found = file_corrections(path)
    except StorageError as exc:
        raise _refused(ArchiveRefused(member, str(exc))) from None
    if [c.n for c in found] != list(range(1, len(found) + 1)):
        raise _refused(ArchiveRefused(member, "its corrections are not numbered 1, 2, 3, ..."))
    for c in found:
        wrong = _wrong_correction(c, run, stand)
        if wrong is not None:
            raise _refused(ArchiveRefused(member, f"correction {c.n}: {wrong}"))
    return found


def _wrong_correction(c: Correction, run: Run, stand: Stand) -> str | None:
    """What is wrong with an archived correction of ``run``, or None."""
    decl = stand.group(c.group)
    if decl is None:
        return f"no channel group {c.group!r}"
    if not 0 <= c.row < run.rows.get(c.group, 0):
        return f"no row {c.row} in {c.group}"
    if c.channel is None:
        return None
    channel = decl.channel(c.channel)
    if channel is None:
        return f"no channel {c.channel!r} in {c.group}"
    problems = [] if c.now is None else check_cell(channel, c.now)
    return problems[0].message if problems else None


def _present(columns: dict[str, Any]) -> Iterator[dict[str, Any]]:
    """The rows of an aligned group's slice in runs of the same channels present, each with
    only those: a channel a batch did not carry is stored as NaN (a vendor's file without a
    temperature), and the batch was checked without it."""
    finite = {n: np.isfinite(np.asarray(v, dtype=np.float64)) for n, v in columns.items()}
    if all(mask.all() for mask in finite.values()):
        yield columns
        return
    pattern = np.stack(list(finite.values()), axis=1)
    rows = pattern.shape[0]
    starts = [0, *np.flatnonzero((pattern[1:] != pattern[:-1]).any(axis=1)) + 1, rows]
    for first, end in itertools.pairwise(starts):
        yield {n: np.asarray(v)[first:end] for n, v in columns.items() if finite[n][first]}


def _checked(
    batches: Iterator[tuple[int, Any, dict[str, Any]]], stand: Stand
) -> Iterator[tuple[int, Any, dict[str, Any]]]:
    """The batches of an archive's run file, each checked as a posted batch is (limits,
    ordering across batches); the NaN that stands for "not in that batch" left out: of the
    single measurements value by value, of an aligned group the channels a run of rows
    lacks."""
    last: dict[str, dict[str, float]] = {}
    for seq, stored, columns in batches:
        decl = stand.group(stored.group)
        if decl is None:
            raise _refused(ArchiveRefused("run file", f"no channel group {stored.group!r}"))
        if stored.group == MEASUREMENTS:
            parts = [{n: v[~np.isnan(v)] for n, v in columns.items() if (~np.isnan(v)).any()}]
        else:
            parts = list(_present(columns))
        for checked in parts:
            previous = last.setdefault(stored.group, {})
            found = check_columns(decl, checked, previous) if checked else []
            if found:
                raise ApiProblem(
                    422,
                    "Archive refused",
                    f"the run file's readings of group {stored.group!r} would be refused "
                    f"here: {found[0].message}",
                    found,
                )
            previous.update({n: float(v[-1]) for n, v in checked.items() if len(v)})
        yield seq, stored, columns


def _import(services: Services, found: ArchivedRun, original: Run, by: str) -> Run:
    """Recreate the archive's run here (a new id; readings, measurements and results
    computed again), all or nothing; its students' sketches and words written anew ``by``
    the importer, every version in its order."""
    if original.state is RunState.OPEN:
        raise ApiProblem(
            409,
            "Run was open",
            f"run {original.id} was still open when exported; export it again once it ended",
        )
    try:
        in_file = summary(found.run_file).run
    except StorageError as exc:
        raise _refused(ArchiveRefused(f"{original.id}.h5", str(exc))) from None
    if (in_file.id, in_file.stand, in_file.rows) != (original.id, original.stand, original.rows):
        raise _refused(
            ArchiveRefused(
                f"{original.id}.h5",
                f"the run file holds run {in_file.id} ({in_file.stand.value}, rows "
                f"{in_file.rows}); run.json says {original.id} ({original.stand.value}, rows "
                f"{original.rows})",
            )
        )
    stand = services.stands[original.stand].for_run(original.configuration)
    fixes = _corrections(found.run_file, original, stand)
    sketches = _archived_sketches(found, original)
    batches = sum(math.ceil(rows / IMPORT_ROWS) for rows in original.rows.values())
    origin = ImportedFrom(run_id=original.id, server=found.server, exported=found.exported)
    with ExitStack() as stack:
        references: dict[str, tuple[Run, Readings]] = {}
        for other_id, path in found.references.items():
            try:
                references[other_id] = (summary(path).run, FileReadings(path, stack))
            except StorageError as exc:
                raise _refused(ArchiveRefused(f"references/{other_id}.h5", str(exc))) from None
        readings = FileReadings(found.run_file, stack)
        for _ in range(ID_TRIES):
            run = original.model_copy(
                update={
                    "id": new_run_id(original.created),
                    "batches": batches,
                    "key_results": {},
                    "imported_from": origin,
                    "damage": None,
                    "corrections": len(fixes),
                }
            )
            payload: Mapping[str, Any] | None = None
            if run.state is RunState.FINISHED:
                computed = analyse(run, readings, references.get)
                payload = computed.payload
                run = run.model_copy(update={"key_results": computed.key_results})
            rows = _checked(file_batches(found.run_file, run), stand)
            if services.store.import_run(run, None, payload, rows, fixes):
                for item, image in sketches:
                    size, media_type = image.size, image.media_type
                    services.sketches.put(
                        run.id, item, image.data, media_type=media_type, size=size, by=by
                    )
                for words in found.notes:
                    services.notes.put(
                        run.id,
                        StudentNotesWrite.model_validate(
                            words.model_dump(include=set(StudentNotesWrite.model_fields))
                        ),
                        by=by,
                    )
                return services.store.get_run(run.id)
    raise ApiProblem(503, "No free run id", "try the import again", headers={"Retry-After": "1"})


async def _body_to(request: Request, path: Path, reserve: int) -> None:
    """The body written to ``path``, the disk's free space looked at every
    :data:`ROOM_STEP` bytes: 507 before it would leave less than ``reserve``."""
    written = 0
    with path.open("wb") as target:
        async for piece in request.stream():
            if written // ROOM_STEP != (written + len(piece)) // ROOM_STEP or written == 0:
                try:
                    room(path.parent, len(piece), reserve, "archive")
                except NoRoom as exc:
                    raise ApiProblem(507, "Storage full", str(exc)) from None
            written += len(piece)
            target.write(piece)


@router.post(
    "/runs/import",
    status_code=status.HTTP_201_CREATED,
    summary="Import a run from an .eln archive that a rig server exported",
    description="The archive as the body (`Content-Type: application/vnd.eln+zip`, at most "
    "`RIG_IMPORT_MAX_BYTES`). The run is recreated under a new id, its `imported_from` "
    "naming the original run and server: the same readings and measurements, the results "
    "computed again. An archive that is damaged or not rig's is refused (422 naming the "
    "member: no metadata, not made by rig, a member missing, given twice, undeclared or "
    "larger than declared, a path that climbs out, a zip bomb, a checksum mismatch); "
    "nothing of it is stored. run.json passes the checks of `POST /runs` (the same "
    "limits, 422 naming the field). Needs the scope `write:<stand>` of the run's stand, "
    "read from run.json before anything else is unpacked. At most `RIG_IMPORT_QUEUE` "
    "imports run at once, one key at most its `RIG_IMPORT_KEY_SHARE` of them (503 with "
    "Retry-After beyond); 507 when the members would leave less than "
    "`RIG_IMPORT_DISK_RESERVE` free on the disk.",
    responses={201: {"model": Run}},
    dependencies=[WriteAccess],
    openapi_extra=file_body(
        {ELN_MEDIA_TYPE: ELN_EXAMPLE}, "profile", "a profilometer run exported by a rig server"
    ),
)
async def import_run(request: Request) -> Response:
    services = services_of(request)
    caller = caller_of(request, services)
    media = media_type(request.headers.get("content-type"))
    if media != ELN_MEDIA_TYPE:
        raise ApiProblem(415, "Unsupported media type", f"send the archive as {ELN_MEDIA_TYPE}")
    with services.imports.admitted(client_of(request.scope, services)):
        directory = Path(await run_in_threadpool(tempfile.mkdtemp, prefix="rig-import-"))
        try:
            archive = directory / "archive.eln"
            await _body_to(request, archive, services.settings.import_disk_reserve)
            found, original = await run_in_threadpool(_unpack, services, caller, archive, directory)
            assert caller is not None  # _unpack found its write scope
            by = author(caller)
            run = await run_in_threadpool(_import, services, found, original, by)
        finally:
            await run_in_threadpool(shutil.rmtree, directory, True)
    return Response(run.model_dump_json(), status_code=201, media_type="application/json")
