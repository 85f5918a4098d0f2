"""``/runs/{id}/readings``: post a batch (JSON columns or binary npz), read readings back.

The binary form is a NumPy ``.npz`` archive (``numpy.savez``) with one 1-D array per channel,
posted with ``Content-Type: application/x-npz`` and ``?seq=&group=`` in the query. It skips
JSON parsing of the numbers, for high-rate channels.
"""

from __future__ import annotations

import csv
import io
import zipfile
from collections.abc import Iterator
from typing import Annotated, Any, Literal

import numpy as np
from fastapi import APIRouter, Query, Request, Response
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import FileResponse, StreamingResponse
from numpy.typing import NDArray
from pydantic import ValidationError

from rigserver.api.deps import CallerDep, ReadAccess, Services, ServicesDep, require_write
from rigserver.api.problems import ApiProblem
from rigserver.api.routes.runs import load_run
from schemas.channels import ChannelGroup, Violation, check_columns
from schemas.readings import NPZ_MEDIA_TYPE, BatchReceipt, ReadingBatch
from schemas.runs import Run
from schemas.stands import Stand

router = APIRouter(prefix="/runs/{run_id}/readings", tags=["readings"])

MAX_ROWS_JSON = 1_000_000

_BATCH_BODY: dict[str, Any] = {
    "requestBody": {
        "required": True,
        "content": {
            "application/json": {"schema": {"$ref": "#/components/schemas/ReadingBatch"}},
            NPZ_MEDIA_TYPE: {
                "schema": {"type": "string", "format": "binary"},
                "description": "numpy.savez archive, one 1-D array per channel; "
                "seq and group in the query",
            },
        },
    }
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


def ingest(
    services: Services, run: Run, seq: int, group_name: str, columns: dict[str, Any]
) -> BatchReceipt:
    """Check a batch against the stand's declaration and store it (once per seq)."""
    group = _group_of(services.stands[run.stand], group_name)
    store = services.store
    with services.run_locks[run.id]:
        if store.receipt(run.id, seq) is not None:
            arrays = {k: np.asarray(v, dtype=np.float64) for k, v in columns.items()}
            return store.append(run.id, seq, group.name, arrays)
        arrays, violations = check_columns(group, columns, store.last_values(run.id, group.name))
        if violations:
            raise ApiProblem(
                422,
                "Readings refused",
                f"{violations[0].message} (nothing of this batch was stored)",
                violations,
            )
        return store.append(run.id, seq, group.name, arrays)


def _parse_npz(body: bytes) -> dict[str, NDArray[Any]]:
    try:
        with np.load(io.BytesIO(body), allow_pickle=False) as archive:
            return {name: archive[name] for name in archive.files}
    except (ValueError, OSError, zipfile.BadZipFile, EOFError) as exc:
        raise ApiProblem(
            422, "Unreadable binary batch", f"the body is not a numpy .npz archive: {exc}"
        ) from None


@router.post(
    "",
    summary="Post a batch of readings (JSON columns or binary npz)",
    description="Answers 201 with the receipt once the batch is durable, 200 with the same "
    "receipt when the seq was stored before (a retry), 422 naming the field, index, value "
    "and limit when a reading is refused (nothing of the batch is stored), 409 when the run "
    "is not open. Needs the scope `write:<stand>`.",
    status_code=201,
    responses={200: {"description": "a retried batch, stored before"}},
    openapi_extra=_BATCH_BODY,
)
async def post_readings(
    run_id: str,
    request: Request,
    response: Response,
    services: ServicesDep,
    caller: CallerDep,
    seq: Annotated[int | None, Query(ge=0, description="binary form only")] = None,
    group: Annotated[str | None, Query(max_length=40, description="binary form only")] = None,
) -> BatchReceipt:
    run = await run_in_threadpool(load_run, services, run_id)
    require_write(caller, run.stand)
    body = await request.body()
    media = request.headers.get("content-type", "application/json").split(";")[0].strip()
    columns: dict[str, Any]
    if media == NPZ_MEDIA_TYPE:
        if seq is None or group is None:
            raise ApiProblem(
                422, "seq and group needed", "the binary form takes ?seq=&group= in the query"
            )
        columns = _parse_npz(body)
    elif media == "application/json":
        try:
            batch = ReadingBatch.model_validate_json(body)
        except ValidationError as exc:
            errors = [
                Violation(
                    field=".".join(str(p) for p in e["loc"]) or "body",
                    message=f"{'.'.join(str(p) for p in e['loc']) or 'body'}: {e['msg']}",
                )
                for e in exc.errors()[:20]
            ]
            raise ApiProblem(422, "Invalid batch", errors[0].message, errors) from None
        seq, group, columns = batch.seq, batch.group, dict(batch.columns)
    else:
        raise ApiProblem(
            415, "Unsupported media type", f"send application/json or {NPZ_MEDIA_TYPE}"
        )
    receipt = await run_in_threadpool(ingest, services, run, seq, group, columns)
    if receipt.duplicate:
        response.status_code = 200
    return receipt


Format = Literal["json", "csv", "hdf5"]


@router.get(
    "",
    summary="Read the readings back as JSON, CSV or the run's HDF5 file",
    dependencies=[ReadAccess],
    responses={
        200: {
            "content": {
                "text/csv": {},
                "application/x-hdf5": {},
            }
        }
    },
)
def get_readings(
    run_id: str,
    services: ServicesDep,
    group: Annotated[str | None, Query(max_length=40)] = None,
    format: Format = "json",
    start: Annotated[int, Query(ge=0)] = 0,
    stop: Annotated[int | None, Query(ge=0)] = None,
) -> Any:
    run = load_run(services, run_id)
    stand = services.stands[run.stand]
    if format == "hdf5":
        return FileResponse(
            services.store.run_file(run.id),
            media_type="application/x-hdf5",
            filename=f"{run.id}.h5",
        )
    if group is None:
        if format == "csv":
            raise ApiProblem(422, "group needed", "CSV holds one channel group: add ?group=")
        return {g.name: _json_group(services, run, g, start, stop) for g in stand.groups}
    chosen = _group_of(stand, group)
    if format == "csv":
        return StreamingResponse(
            _csv_rows(services, run, chosen),
            media_type="text/csv",
            headers={"Content-Disposition": f'attachment; filename="{run.id}-{chosen.name}.csv"'},
        )
    return {chosen.name: _json_group(services, run, chosen, start, stop)}


def _json_group(
    services: Services, run: Run, group: ChannelGroup, start: int, stop: int | None
) -> dict[str, Any]:
    if not group.aligned:
        data = services.store.read(run.id, group.name)
        return {
            "units": {c.name: c.unit for c in group.channels},
            "columns": {name: values.tolist() for name, values in data.items()},
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
    return {
        "rows": max(end - start, 0),
        "units": {c.name: c.unit for c in group.channels},
        "columns": {name: values.tolist() for name, values in data.items()},
    }


def _csv_rows(services: Services, run: Run, group: ChannelGroup) -> Iterator[str]:
    out = io.StringIO()
    writer = csv.writer(out)
    if not group.aligned:
        writer.writerow(["channel", "unit", "value"])
        units = {c.name: c.unit for c in group.channels}
        for name, values in services.store.read(run.id, group.name).items():
            writer.writerows((name, units[name], v) for v in values.tolist())
        yield out.getvalue()
        return
    names = [c.name for c in group.channels]
    writer.writerow([f"{c.name} [{c.unit}]" for c in group.channels])
    for chunk in services.store.iter_chunks(run.id, group.name, names, rows=65_536):
        writer.writerows(zip(*(chunk[n].tolist() for n in names), strict=True))
        yield out.getvalue()
        out.seek(0)
        out.truncate()
    yield out.getvalue()
