"""``/runs/{id}/sketches``: the students' sketches on a run, an image (PNG or JPEG) for each
sketch item of their lab's report list (:mod:`rigserver.reports.contents`), printed in the
run's report in place of the frame to draw in (:mod:`rigserver.storage.sketches`). An
upload never replaces: it is the item's next version, the earlier ones kept."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path, Query, Request, Response, status
from fastapi.concurrency import run_in_threadpool

from rigserver.api.cases.found import load_run
from rigserver.api.cases.sketches import upload_sketch
from rigserver.api.deps import (
    ReadAccess,
    ServicesDep,
    WriteAccess,
    caller_of,
    services_of,
)
from rigserver.api.examples import SKETCH_EXAMPLES, file_body
from rigserver.api.problems import ApiProblem
from rigserver.api.sketch_images import checked, too_large
from schemas.sketches import SKETCH_MAX_BYTES, SKETCH_TYPES, Sketch, Sketches

router = APIRouter(prefix="/runs/{run_id}", tags=["runs"])

ItemPath = Annotated[
    int, Path(ge=1, le=99, description="the item's number in the lab's list", examples=[4])
]


async def body_of(request: Request) -> bytes:
    """The request's body, at most :data:`SKETCH_MAX_BYTES` (413 past it, before the rest
    is read)."""
    declared = request.headers.get("content-length", "")
    if declared.isdigit() and int(declared) > SKETCH_MAX_BYTES:
        raise too_large(int(declared))
    body = bytearray()
    async for chunk in request.stream():
        body += chunk
        if len(body) > SKETCH_MAX_BYTES:
            raise too_large()
    return bytes(body)


@router.get(
    "/sketches",
    summary="The students' sketches on the run: every version of each item's",
    description="The latest version of an item is the one the report prints.",
    dependencies=[ReadAccess],
)
def list_sketches(run_id: str, services: ServicesDep) -> Sketches:
    return Sketches(sketches=services.sketches.history(load_run(services, run_id).id))


#: The largest version number asked for: more uploads than any item has, within every
#: store's integer (a larger one is refused at the door, not by SQLite).
VERSIONS = 2**31 - 1


@router.get(
    "/sketches/{item}",
    summary="The image of the run's sketch of an item (the latest, or ?version=)",
    response_class=Response,
    responses={200: {"content": {t: {} for t in SKETCH_TYPES}}},
    dependencies=[ReadAccess],
)
def get_sketch(
    run_id: str,
    item: ItemPath,
    services: ServicesDep,
    version: Annotated[
        int | None, Query(ge=1, le=VERSIONS, description="an earlier version")
    ] = None,
) -> Response:
    run = load_run(services, run_id)
    found = services.sketches.image(run.id, item, version)
    if found is None:
        which = f"version {version} of " if version else ""
        raise ApiProblem(
            404, "Sketch not found", f"run {run.id} has no {which}sketch of item {item}"
        )
    sketch, data = found
    return Response(
        data,
        media_type=sketch.media_type,
        headers={
            "ETag": f'"{sketch.sha256}"',
            "Content-Disposition": f'inline; filename="{run.id}-sketch-{item}-v{sketch.version}'
            f'.{sketch.media_type.removeprefix("image/").replace("jpeg", "jpg")}"',
        },
    )


@router.put(
    "/sketches/{item}",
    status_code=status.HTTP_201_CREATED,
    summary="Upload the students' sketch of an item (its next version; the earlier kept)",
    description="The image as the body, `Content-Type: image/png` or `image/jpeg` as its "
    f"bytes are, at most {SKETCH_MAX_BYTES} bytes (413 beyond) and 8000 pixels a side, "
    "40 megapixels in all (422 beyond, read from its header before it is decoded). A body "
    "that is no such image, or not the type its header says, is refused with 415; a "
    "damaged one with 422. `item` is a sketch item of the run's lab's report list (422 "
    "naming them). Needs the run's stand's write scope (`write:<stand>` or `write:*`).",
    responses={201: {"model": Sketch}},
    dependencies=[WriteAccess],
    openapi_extra=file_body(SKETCH_EXAMPLES, "sketch", "a sketch"),
)
async def put_sketch(run_id: str, item: ItemPath, request: Request) -> Response:
    services = services_of(request)
    caller = caller_of(request, services)
    body = await body_of(request)
    image = await run_in_threadpool(checked, body, request.headers.get("content-type"))
    sketch = await run_in_threadpool(upload_sketch, services, run_id, item, image, caller)
    return Response(sketch.model_dump_json(), status_code=201, media_type="application/json")
