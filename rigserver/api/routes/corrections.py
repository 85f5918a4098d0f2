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

from typing import Annotated

from fastapi import APIRouter, Path
from fastapi.concurrency import run_in_threadpool

from rigserver.api.auth import ApiKey
from rigserver.api.deps import (
    CallerDep,
    ReadAccess,
    Services,
    ServicesDep,
    WriteAccess,
    require_write,
)
from rigserver.api.problems import ApiProblem
from rigserver.api.report_answers import render_finished
from rigserver.api.routes.notes import author
from rigserver.api.routes.runs import load_run
from rigserver.api.run_results import compute_results
from rigserver.api.strict_json import StrictJsonRoute
from rigserver.storage.corrections import CorrectionRefused
from schemas.corrections import CorrectedRow, CorrectionList, CorrectionWrite, StrikeWrite
from schemas.runs import RunState

router = APIRouter(prefix="/runs/{run_id}", tags=["readings"], route_class=StrictJsonRoute)

Group = Annotated[str, Path(max_length=40, description="the channel group, e.g. 'rows'")]
Index = Annotated[
    int, Path(ge=0, le=2**62, description="the row's index in its group as stored, from 0")
]


def correct(
    services: Services,
    run_id: str,
    group: str,
    index: int,
    body: CorrectionWrite | StrikeWrite,
    caller: ApiKey | None,
) -> CorrectedRow:
    """Correct (a :class:`CorrectionWrite`) or strike out (a :class:`StrikeWrite`) a stored
    row for a key with the run's stand's write scope; a finished run's results are computed
    again and its reports rendered again."""
    run = load_run(services, run_id)
    key = require_write(caller, run.stand)
    store = services.store
    with services.run_locks[run.id]:  # one at a time with the run's finish
        try:
            if isinstance(body, CorrectionWrite):
                row = store.correct_reading(
                    run.id, group, index, body.values, body.reason, author(key)
                )
            else:
                row = store.strike_reading(run.id, group, index, body.reason, author(key))
        except CorrectionRefused as exc:
            raise ApiProblem(422, "Correction refused", str(exc), exc.violations) from None
        now = store.get_run(run.id)
        again = now.state is RunState.FINISHED and now.corrections != run.corrections
        if again:
            results = services.results.for_finish(now, lambda: compute_results(services, now))
            store.set_results(run.id, results.payload, results.key_results)
    if again and services.settings.reports_on_finish:
        values = results.payload["values"]
        services.reports.soon(
            f"rendering the reports of run {run.id} again (corrected)",
            lambda: render_finished(services, run.id, values),
        )
    return row


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
