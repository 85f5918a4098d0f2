"""``/runs/{id}/readings/{group}/{index}`` (PATCH, DELETE) and ``/runs/{id}/corrections``:
correct a mistyped reading, or strike a row out, keeping the value as typed.

A correction is checked as a post is (the channel's limits in the run's units, a known
channel, a row that exists, a reason), stored durably by the store
(:meth:`~rigserver.storage.base.RunStore.correct_reading`) and answered with the row as it
now reads. A finished run may be corrected too: its results are computed again on the
corrected readings and stored, and its reports rendered again (they are named by the run's
version, which counts its corrections); the run then says ``corrected_after_finish``.
"""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.concurrency import run_in_threadpool

from rigserver.api.cases.corrections import correct
from rigserver.api.cases.found import load_run
from rigserver.api.deps import (
    CallerDep,
    Group,
    Index,
    ReadAccess,
    ServicesDep,
    WriteAccess,
)
from rigserver.api.strict_json import StrictJsonRoute
from schemas.corrections import CorrectedRow, CorrectionList, CorrectionWrite, StrikeWrite

router = APIRouter(prefix="/runs/{run_id}", tags=["readings"], route_class=StrictJsonRoute)


_WHAT = (
    "Needs the run's stand's write scope (`write:<stand>`). Checked as a post is: 422 "
    "naming the field (`index`, `values.<channel>`, `reason`), its value and limit. The "
    "value as typed is kept: `GET /runs/{id}/readings?original=true` gives it, "
    "`GET /runs/{id}/corrections` lists every correction with the value before and after, "
    "the reason, the key's name and the time. A row that already reads so stores nothing "
    "(a retry is safe). A finished run's results are computed again."
)


@router.patch(
    "/readings/{group}/{index}",
    summary="Correct cells of a stored row (the value as typed is kept)",
    description=_WHAT,
    dependencies=[WriteAccess],
)
async def patch_reading(
    run_id: str,
    group: Group,
    index: Index,
    body: CorrectionWrite,
    services: ServicesDep,
    caller: CallerDep,
) -> CorrectedRow:
    return await run_in_threadpool(correct, services, run_id, group, index, body, caller)


@router.delete(
    "/readings/{group}/{index}",
    summary="Strike a stored row out (kept as typed, left out of the results)",
    description=_WHAT,
    dependencies=[WriteAccess],
)
async def strike_reading(
    run_id: str,
    group: Group,
    index: Index,
    body: StrikeWrite,
    services: ServicesDep,
    caller: CallerDep,
) -> CorrectedRow:
    return await run_in_threadpool(correct, services, run_id, group, index, body, caller)


@router.get(
    "/corrections",
    summary="The corrections of the run's readings, in the order made",
    dependencies=[ReadAccess],
)
def get_corrections(run_id: str, services: ServicesDep) -> CorrectionList:
    run = load_run(services, run_id)
    return CorrectionList(run_id=run.id, corrections=services.store.corrections(run.id))
