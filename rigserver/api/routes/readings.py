"""``/runs/{id}/readings``: post a batch (JSON columns or binary npz), read readings back.

The binary form is a NumPy ``.npz`` archive (``numpy.savez``) with one 1-D array per channel,
posted with ``Content-Type: application/x-npz`` and ``?seq=&group=`` in the query. It skips
JSON parsing of the numbers, for high-rate channels.
"""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Mapping
from functools import partial
from pathlib import Path
from typing import Annotated, Any, Literal

import jiter
from fastapi import APIRouter, Query, Request, Response
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import FileResponse, StreamingResponse
from pydantic import ValidationError
from starlette.background import BackgroundTask

from rigserver.api.auth import ApiKey
from rigserver.api.cases.runs import load_run
from rigserver.api.deps import (
    ReadAccess,
    Services,
    ServicesDep,
    WriteAccess,
    caller_of,
    require_write,
    services_of,
)
from rigserver.api.ingest_queue import Place
from rigserver.api.npz import parse_npz
from rigserver.api.problems import ApiProblem, violations
from rigserver.api.routes.api_docs import NPZ_EXAMPLE
from rigserver.api.run_results import StoredReadings
from rigserver.reports.arrow import group_arrow
from rigserver.reports.export import group_csv
from rigserver.storage.base import NewBatch
from rigserver.storage.corrections import applied, last_values, struck_rows
from rigserver.storage.runfile import corrected_copy
from schemas.channels import ChannelGroup, Violation, check_columns, follows
from schemas.corrections import Correction
from schemas.readings import ARROW_MEDIA_TYPE, NPZ_MEDIA_TYPE, BatchReceipt, ReadingBatch
from schemas.runs import Run
from schemas.stands import Stand
from schemas.strict_json import JsonRefused, strict_loads
from schemas.wire import Text, ascii_count

router = APIRouter(prefix="/runs/{run_id}/readings", tags=["readings"])

MAX_ROWS_JSON = 1_000_000
MAX_SEQ = 2**62  # as ReadingBatch.seq
#: Bodies up to this size are parsed and stored on the event loop (stored in groups, see
#: rigserver.api.ingest_queue); larger ones in a worker thread.
SMALL_BODY_BYTES = 64 << 10

_BATCH_BODY: dict[str, Any] = {
    "requestBody": {
        "required": True,
        "content": {
            "application/json": {"schema": {"$ref": "#/components/schemas/ReadingBatch"}},
            NPZ_MEDIA_TYPE: {
                "schema": {
                    "type": "string",
                    "format": "binary",
                    "description": "numpy.savez archive, one 1-D array per channel; "
                    "seq and group in the query",
                },
                "examples": {
                    "friction": {
                        "summary": "the JSON example's columns as numpy.savez writes them",
                        "externalValue": NPZ_EXAMPLE,
                    }
                },
            },
        },
    },
    "parameters": [
        {"name": "run_id", "in": "path", "required": True, "schema": {"type": "string"}},
        {
            "name": "seq",
            "in": "query",
            "required": False,
            "description": "binary form only: the batch's sequence number",
            "schema": {"type": "integer", "minimum": 0, "maximum": 2**62},
            "example": 1,
        },
        {
            "name": "group",
            "in": "query",
            "required": False,
            "description": "binary form only: the channel group",
            "schema": {"type": "string", "maxLength": 40},
            "example": "friction",
        },
    ],
}


def _group_of(stand: Stand, name: str) -> ChannelGroup:
    group = stand.group(name)
    if group is None:
        known = ", ".join(g.name for g in stand.groups)
        raise ApiProblem(
            422,
            "Unknown channel group",
            f"stand {stand.kind.value!r} has no channel group {name!r}; known: {known}",
            [Violation(field="group", value=name[:40], limit=f"one of {known}", message="")],
        )
    return group


def _refuse_violations(
    group: ChannelGroup, columns: Mapping[str, Any], last: Mapping[str, float]
) -> None:
    """The stand's limits and orderings, checked against the run's last stored values."""
    violations = check_columns(group, columns, last)
    if violations:
        raise ApiProblem(
            422,
            "Readings refused",
            f"{violations[0].message} (nothing of this batch was stored)",
            violations,
        )


def _refuse_across(
    group: ChannelGroup, columns: Mapping[str, Any], last: Mapping[str, float]
) -> None:
    """The order across batches of a batch found good on its own (under the store's lock,
    which :func:`_refuse_violations` on a large batch would hold for a millisecond)."""
    if not follows(group, columns, last):
        _refuse_violations(group, columns, last)


def _read_batch(
    media: str, body: bytes, limit: int, stand: Stand, seq: int, group: str, *, alone: bool
) -> tuple[int, ChannelGroup, Mapping[str, Any]]:
    """The body's batch: its seq and group (a JSON body's own; npz's ``seq`` and ``group``
    come from the query), its group's declaration and its columns; if ``alone``, checked on
    their own (limits, order within the batch: a large body's, in the thread that reads it)."""
    columns: Mapping[str, Any]
    if media == NPZ_MEDIA_TYPE:
        columns = parse_npz(body, limit)
    else:
        batch = _parse_json(body)
        seq, group, columns = batch.seq, batch.group, batch.columns
    decl = _group_of(stand, group)
    if alone:
        _refuse_violations(decl, columns, {})
    return seq, decl, columns


def _parse_json(body: bytes) -> ReadingBatch:
    """The batch of a JSON body, strictly: one fast pass (jiter, which also catches a key
    given twice) and the model's strict types; a body jiter refuses is judged again by
    :func:`strict_loads`, for the message (and the lone surrogates that only it reads)."""
    try:
        tree = jiter.from_json(body, catch_duplicate_keys=True)
    except ValueError:
        try:
            tree = strict_loads(body)
        except json.JSONDecodeError as exc:
            where = exc.pos if isinstance(exc, JsonRefused) else "body"
            raise ApiProblem(
                422,
                "Invalid batch",
                f"{where}: invalid JSON: {exc.msg}",
                [Violation(field=str(where), message=f"{where}: invalid JSON: {exc.msg}")],
            ) from None
    try:
        return ReadingBatch.model_validate(tree)
    except ValidationError as exc:
        errors = violations(exc.errors())
        raise ApiProblem(422, "Invalid batch", errors[0].message, errors) from None


async def stand_of_run(services: Services, run_id: str) -> Stand:
    """The run's stand as its configuration sets it (the units in a refusal's message):
    remembered, or looked up (404 for an unknown run)."""
    stand = services.run_stands.get(run_id)
    if stand is None:
        stand = services.stand_of(await run_in_threadpool(load_run, services, run_id))
        services.remember_stand(run_id, stand)
    return stand


def _binary_query(request: Request) -> tuple[int, str]:
    """``?seq=&group=`` of the binary form: a whole seq from 0 and a group name."""
    seq = request.query_params.get("seq", "")
    group = request.query_params.get("group", "")
    number = ascii_count(seq)
    errors = []
    if number is None or number > MAX_SEQ:
        errors.append(
            Violation(
                field="seq",
                value=seq[:40],
                limit=f"0 <= seq <= {MAX_SEQ}",
                message="seq: a whole number from 0 in ASCII digits, in the query",
            )
        )
    if not group or len(group) > 40:
        errors.append(
            Violation(field="group", value=group[:40], message="group: a channel group name")
        )
    if errors or number is None:
        raise ApiProblem(
            422,
            "seq and group needed",
            "the binary form takes ?seq=&group= in the query: "
            + "; ".join(e.message for e in errors),
            errors,
        )
    return number, group


async def _body(request: Request, place: Place) -> bytes:
    """The body, each piece counted in the ingest queue as it arrives (503 once it
    overflows the key's share or the queue: read no further)."""
    chunks = []
    async for chunk in request.stream():
        if chunk:
            place.arrived(len(chunk))
            chunks.append(chunk)
    return b"".join(chunks)


def _declared_length(request: Request) -> int:
    value = request.headers.get("content-length", "")
    return ascii_count(value) or 0


async def post_readings(request: Request) -> Response:
    # the hot path of ingest, called by rigserver.api.ingest_lane (not by the router):
    # run_id, seq and group are documented in _BATCH_BODY. Authenticated
    # (rigserver.api.gate); the head parsed, the scope checked, and only then a place in
    # the queue taken and the body read.
    run_id: str = request.path_params["run_id"]
    services = services_of(request)
    caller = caller_of(request, services)
    media = request.headers.get("content-type", "application/json").split(";")[0].strip()
    if media not in ("application/json", NPZ_MEDIA_TYPE):
        raise ApiProblem(
            415, "Unsupported media type", f"send application/json or {NPZ_MEDIA_TYPE}"
        )
    seq, group = _binary_query(request) if media == NPZ_MEDIA_TYPE else (0, "")
    stand = await stand_of_run(services, run_id)
    writer = require_write(caller, stand.kind)
    receipt = await store_posted(request, services, run_id, stand, writer, media, seq, group)
    return Response(
        receipt.model_dump_json(),
        status_code=200 if receipt.duplicate else 201,
        media_type="application/json",
    )


async def store_posted(
    request: Request,
    services: Services,
    run_id: str,
    stand: Stand,
    writer: ApiKey,
    media: str = "application/json",
    seq: int = 0,
    group: str = "",
) -> BatchReceipt:
    """The batch of the request's body, checked and stored for ``writer`` (whose scope is
    checked): the API's post and the run page's rows alike (:mod:`rigserver.api.routes.entry`)."""
    with services.ingest.admit(_declared_length(request), writer.fingerprint) as place:
        body = await _body(request, place)
        small = len(body) <= SMALL_BODY_BYTES
        read = partial(
            _read_batch, media, body, services.settings.max_body_bytes, stand, seq, group
        )
        if small:  # the check with the run's last values, under the store's lock
            seq, decl, columns = read(alone=False)
            check = partial(_refuse_violations, decl)
        else:  # checked on its own here; only the order after the last values under the lock
            seq, decl, columns = await run_in_threadpool(partial(read, alone=True))
            check = partial(_refuse_across, decl)
        del body, read  # a JSON body is parsed: its bytes are not needed any more
        try:
            return await services.ingest.store(
                NewBatch(run_id, seq, decl.name, columns, check), small=small
            )
        except ValueError as exc:  # the store's own check of the batch's shape
            raise ApiProblem(422, "Batch does not fit its group", str(exc)) from None


router.add_api_route(
    "",
    post_readings,
    methods=["POST"],
    dependencies=[WriteAccess],  # solved by no one: rigserver.api.gate reads it
    summary="Post a batch of readings (JSON columns or binary npz)",
    description="Answers 201 with the receipt once the batch is durable, 200 with the same "
    "receipt when the seq was stored before (a retry), 422 naming the field, index, value "
    "and limit when a reading is refused (nothing of the batch is stored), 409 when the run "
    "is not open, 503 with Retry-After when the ingest queue is full. Needs the scope "
    "`write:<stand>`.",
    status_code=201,
    response_model=BatchReceipt,
    responses={200: {"description": "a retried batch, stored before", "model": BatchReceipt}},
    openapi_extra=_BATCH_BODY,
)


Format = Literal["json", "csv", "arrow", "hdf5"]


@router.get(
    "",
    summary="Read the readings back as JSON, CSV, an Arrow stream or the run's HDF5 file",
    description="An aligned group gives its columns; the single measurements (masses, zero "
    "readings) are named single values, the latest posted of each channel. Every format "
    "gives the values as corrected (PATCH/DELETE `/readings/{group}/{index}`): the rows "
    "struck out left out (JSON names their indices as stored under `struck`); "
    "`original=true` gives them as typed. The HDF5 file as corrected keeps the table of "
    "corrections (`/entry/corrections`, with the values as typed). `format=arrow` gives "
    "one group as an Apache Arrow IPC stream (float64 columns, each field's `unit` and "
    "`long_name` in its metadata): what `rigclient.Lab` reads into a DataFrame.",
    dependencies=[ReadAccess],
    responses={
        200: {
            "content": {
                "text/csv": {},
                ARROW_MEDIA_TYPE: {},
                "application/x-hdf5": {},
            }
        }
    },
)
def get_readings(
    run_id: str,
    services: ServicesDep,
    group: Annotated[Text | None, Query(max_length=40)] = None,
    format: Format = "json",
    start: Annotated[int, Query(ge=0)] = 0,
    stop: Annotated[int | None, Query(ge=0)] = None,
    original: Annotated[
        bool,
        Query(
            description="the values as typed; by default as corrected (the corrections "
            "applied, the rows struck out left out)"
        ),
    ] = False,
) -> Any:
    run = load_run(services, run_id)
    stand = services.stand_of(run)
    fixes = [] if original or not run.corrections else services.store.corrections(run.id)
    if format == "hdf5":
        return _hdf5(services, run, corrected=bool(fixes))
    if group is None:
        if format in ("csv", "arrow"):
            holder = "CSV" if format == "csv" else "An Arrow stream"
            raise ApiProblem(422, "group needed", f"{holder} holds one channel group: add ?group=")
        return {g.name: _json_group(services, run, g, start, stop, fixes) for g in stand.groups}
    chosen = _group_of(stand, group)
    if format == "arrow":
        stream = group_arrow(StoredReadings(services, run, original=original), chosen)
        return StreamingResponse(
            stream.pieces,
            media_type=ARROW_MEDIA_TYPE,
            headers={
                "Content-Length": str(stream.size),
                "Content-Disposition": f'attachment; filename="{run.id}-{chosen.name}.arrows"',
            },
        )
    if format == "csv":
        return StreamingResponse(
            group_csv(StoredReadings(services, run, original=original), chosen),
            media_type="text/csv",
            headers={"Content-Disposition": f'attachment; filename="{run.id}-{chosen.name}.csv"'},
        )
    return {chosen.name: _json_group(services, run, chosen, start, stop, fixes)}


def _hdf5(services: Services, run: Run, *, corrected: bool) -> FileResponse:
    """The run's HDF5 file; with its readings as corrected, a copy made for this answer."""
    path = services.store.run_file(run.id)
    if not corrected:
        return FileResponse(path, media_type="application/x-hdf5", filename=f"{run.id}.h5")
    fd, name = tempfile.mkstemp(prefix=f"{run.id}.", suffix=".corrected.h5")
    os.close(fd)
    copy = Path(name)
    try:
        corrected_copy(path, copy)
    except BaseException:
        copy.unlink(missing_ok=True)
        raise
    return FileResponse(
        copy,
        media_type="application/x-hdf5",
        filename=f"{run.id}.h5",
        background=BackgroundTask(copy.unlink, missing_ok=True),
    )


def _json_group(
    services: Services,
    run: Run,
    group: ChannelGroup,
    start: int,
    stop: int | None,
    fixes: list[Correction],
) -> dict[str, Any]:
    mine = [c for c in fixes if c.group == group.name]
    if not group.aligned:  # named single values: the latest of each channel posted
        if not run.rows.get(group.name):
            values: dict[str, float] = {}
        elif mine:
            values = last_values(applied(services.store.read(run.id, group.name), mine, group.name))
        else:
            values = services.store.last_values(run.id, group.name)
        return {
            "units": {c.name: c.unit for c in group.channels if c.name in values},
            "values": values,
        }
    total = run.rows.get(group.name, 0)
    end = total if stop is None else min(stop, total)
    if end - start > MAX_ROWS_JSON:
        raise ApiProblem(
            422,
            "Too many rows for JSON",
            f"{group.name} has {end - start} rows in the range; ask for at most "
            f"{MAX_ROWS_JSON} with start= and stop=, or use format=hdf5",
        )
    data = services.store.read(run.id, group.name, None, start, end) if end > start else {}
    struck = sorted(r for r in struck_rows(mine, group.name) if start <= r < end)
    if mine and data:
        data = applied(data, mine, group.name, start)
    answer: dict[str, Any] = {
        "rows": max(end - start - len(struck), 0),
        "units": {c.name: c.unit for c in group.channels},
        "columns": {name: values.tolist() for name, values in data.items()},
    }
    if struck:  # their rows are left out: the indices as stored say which
        answer["struck"] = struck
    return answer
