"""``/runs/{id}/notes``: the student's own words on a run (the group, the students' names,
their conclusions), written by the run's operator and printed in the run's report beside
the computed verdicts (:mod:`rigserver.storage.notes`)."""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.concurrency import run_in_threadpool

from rigserver.api.cases.found import load_run
from rigserver.api.cases.notes import write_notes
from rigserver.api.deps import (
    CallerDep,
    ReadAccess,
    ServicesDep,
    WriteAccess,
)
from rigserver.api.strict_json import StrictJsonRoute
from schemas.student_notes import StudentNotes, StudentNotesWrite

router = APIRouter(prefix="/runs/{run_id}", tags=["runs"], route_class=StrictJsonRoute)


@router.get(
    "/notes",
    summary="The student's own words on the run: group, students, conclusions",
    description="Empty (version 0) until written; `by` and `written` say who wrote the "
    "last version and when.",
    dependencies=[ReadAccess],
)
def get_notes(run_id: str, services: ServicesDep) -> StudentNotes:
    return services.notes.get(load_run(services, run_id).id)


@router.put(
    "/notes",
    summary="Write the student's own words on the run (every field replaces the last)",
    description="Needs the run's stand's write scope (`write:<stand>` or `write:*`). The "
    "run's report prints the group and the students at the top and the conclusions beside "
    "the computed ones; every version is kept with who wrote it and when.",
    dependencies=[WriteAccess],
)
async def put_notes(
    run_id: str, body: StudentNotesWrite, services: ServicesDep, caller: CallerDep
) -> StudentNotes:
    return await run_in_threadpool(write_notes, services, run_id, body, caller)
