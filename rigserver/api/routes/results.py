"""``/runs/{id}/results``: what the lab manual asks for, computed through the model library."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter
from fastapi.concurrency import run_in_threadpool

from rigserver.api.cases.found import load_run
from rigserver.api.deps import ReadAccess, ServicesDep
from rigserver.api.run_results import results_payload_async
from rigserver.reports import results_view
from rigserver.reports.i18n import DEFAULT, Lang, Messages
from schemas.quantities import Quantity

router = APIRouter(prefix="/runs/{run_id}/results", tags=["results"], dependencies=[ReadAccess])


@router.get(
    "",
    summary="The run's results with units",
    description="For a finished run, the results stored when it finished; for an open run, "
    "computed on the readings that have arrived so far (once per new batch, shared by "
    "every request; 503 with Retry-After when the server already computes as many runs' "
    "results as `--results-workers` allows).",
    responses={503: {"description": "every results worker is busy with other runs"}},
)
async def get_results(run_id: str, services: ServicesDep) -> dict[str, Any]:
    run = await run_in_threadpool(load_run, services, run_id)
    return await results_payload_async(services, run)


@router.get(
    "/table",
    summary="The run's single results as a table, as the pages list them",
    description="One row per result: the manual's words and symbol in `lang`, the value "
    "and its standard uncertainty in the display unit (full precision), the unit as "
    "printed, the part of the report. What `rigclient.Lab` turns into a DataFrame.",
    responses={503: {"description": "every results worker is busy with other runs"}},
)
async def get_results_table(
    run_id: str, services: ServicesDep, lang: Lang = DEFAULT
) -> list[Quantity]:
    run = await run_in_threadpool(load_run, services, run_id)
    payload = await results_payload_async(services, run)
    return results_view.quantities(Messages(lang), run.stand, payload)
