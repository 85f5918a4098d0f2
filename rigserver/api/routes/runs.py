"""``/runs``: open, list, look up, finish and abort runs."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Header, Query, Response, status

from rigserver.api.cases.found import load_run
from rigserver.api.cases.runs import end_run, open_run
from rigserver.api.deps import (
    CallerDep,
    ReadAccess,
    ServicesDep,
    WriteAccess,
)
from rigserver.api.strict_json import StrictJsonRoute
from schemas.runs import (
    Run,
    RunCreate,
    RunPage,
    RunQuery,
    RunState,
)

#: An Idempotency-Key: printable ASCII, no spaces (a UUID, a counter, a hash).
IDEMPOTENCY_KEY_PATTERN = r"^[!-~]+$"

router = APIRouter(prefix="/runs", tags=["runs"], route_class=StrictJsonRoute)


@router.post(
    "",
    status_code=status.HTTP_201_CREATED,
    summary="Open a run on a stand",
    description="Needs a key with the scope `write:<stand>`. The run keeps a snapshot of the "
    "stand's configuration with the overrides given here. With an `Idempotency-Key` header "
    "(any unique string, e.g. a UUID, sent again with every retry) a retried opening is "
    "answered 200 with the run the first one opened; 409 if it asks for another. An "
    "Idempotency-Key belongs to the API key that sent it: sent with another API key, it "
    "opens a run of its own. Values that cannot be stored or shown are refused (422 naming "
    "the field): NaN, infinities and numbers beyond a double's range, whole numbers beyond "
    "±2^63, NUL characters.",
    responses={200: {"description": "the run opened before with this Idempotency-Key"}},
    dependencies=[WriteAccess],
)
def create_run(
    body: RunCreate,
    services: ServicesDep,
    caller: CallerDep,
    response: Response,
    idempotency_key: Annotated[
        str | None,
        Header(
            min_length=1,
            max_length=200,
            pattern=IDEMPOTENCY_KEY_PATTERN,
            description="makes retries safe: printable ASCII without spaces, e.g. a UUID",
        ),
    ] = None,
) -> Run:
    stored, new = open_run(services, caller, body, idempotency_key)
    if not new:
        response.status_code = status.HTTP_200_OK
    return stored


@router.get("", summary="List and search runs, newest first", dependencies=[ReadAccess])
def list_runs(query: Annotated[RunQuery, Query()], services: ServicesDep) -> RunPage:
    return services.store.list_runs(query)


@router.get("/{run_id}", summary="One run: metadata, state, rows stored", dependencies=[ReadAccess])
def get_run(run_id: str, services: ServicesDep) -> Run:
    return load_run(services, run_id)


@router.post(
    "/{run_id}/finish",
    summary="Finish a run: compute and store its results, finalize its file",
    dependencies=[WriteAccess],
)
def finish_run(run_id: str, services: ServicesDep, caller: CallerDep) -> Run:
    return end_run(run_id, services, caller, RunState.FINISHED)


@router.post(
    "/{run_id}/abort",
    summary="Abort a run: keep its readings, take no more",
    dependencies=[WriteAccess],
)
def abort_run(run_id: str, services: ServicesDep, caller: CallerDep) -> Run:
    return end_run(run_id, services, caller, RunState.ABORTED)
