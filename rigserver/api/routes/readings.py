"""``/runs/{id}/readings``: post a batch (JSON columns or binary npz), read readings back.

The binary form is a NumPy ``.npz`` archive (``numpy.savez``) with one 1-D array per channel,
posted with ``Content-Type: application/x-npz`` and ``?seq=&group=`` in the query. It skips
JSON parsing of the numbers, for high-rate channels.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Query, Request, Response
from fastapi.responses import FileResponse, StreamingResponse
from starlette.background import BackgroundTask

from rigserver.api.cases.found import load_run
from rigserver.api.cases.readings import group_of, stand_of_run, store_posted
from rigserver.api.deps import (
    ReadAccess,
    Services,
    ServicesDep,
    WriteAccess,
    caller_of,
    require_write,
    services_of,
)
from rigserver.api.examples import NPZ_EXAMPLE
from rigserver.api.media import media_type
from rigserver.api.problems import ApiProblem
from rigserver.api.run_results import StoredReadings
from rigserver.reports.arrow import group_arrow
from rigserver.reports.export import group_csv
from rigserver.storage.corrections import applied, last_values, struck_rows
from rigserver.storage.runfile import corrected_copy
from schemas.channels import ChannelGroup, Violation
from schemas.corrections import Correction
from schemas.readings import ARROW_MEDIA_TYPE, NPZ_MEDIA_TYPE, BatchReceipt
from schemas.runs import Run
from schemas.wire import Text, ascii_count

router = APIRouter(prefix="/runs/{run_id}/readings", tags=["readings"])

MAX_ROWS_JSON = 1_000_000
MAX_SEQ = 2**62  # as ReadingBatch.seq

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


async def post_readings(request: Request) -> Response:
    # the hot path of ingest, called by rigserver.api.ingest_lane (not by the router):
    # run_id, seq and group are documented in _BATCH_BODY. Authenticated
    # (rigserver.api.gate); the head parsed, the scope checked, and only then a place in
    # the queue taken and the body read.
    run_id: str = request.path_params["run_id"]
    services = services_of(request)
    caller = caller_of(request, services)
    media = media_type(request.headers.get("content-type", "application/json"))
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
    chosen = group_of(stand, group)
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
