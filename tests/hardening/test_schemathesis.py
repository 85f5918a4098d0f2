"""Schemathesis against the OpenAPI document, in process over HDF5 storage: no answer is a
500, and every answer conforms to the document (status, content type, headers, schema).

Not checked here: whether the service refuses every request the document would refuse and
takes every one it allows (schemathesis' negative_data_rejection and
positive_data_acceptance). The document cannot say which configuration keys a stand takes
or which model inputs are outside a formula's domain (refused with 422), and pydantic
takes ``false`` for a number and a number for a date-time."""

from __future__ import annotations

import atexit
import shutil
import tempfile
from pathlib import Path

import pytest
import schemathesis
from fastapi.testclient import TestClient
from hypothesis import HealthCheck, given, settings
from schemathesis import checks
from schemathesis.schemas import APIOperation
from starlette.types import ASGIApp, Receive, Scope, Send

from rigserver.reports.eln import ELN_MEDIA_TYPE
from schemas.readings import NPZ_MEDIA_TYPE
from schemas.stands import StandKind
from tests.api.conftest import WRITER, auth
from tests.hardening.conftest import API, hdf5_app


class _StoreStaysOpen:
    """The app without its lifespan: schemathesis runs one per call, and the app's closes
    the store. The store is closed when the tests end."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "lifespan":
            await self.app(scope, receive, send)
            return
        while (await receive())["type"] != "lifespan.shutdown":
            await send({"type": "lifespan.startup.complete"})
        await send({"type": "lifespan.shutdown.complete"})


_DATA = Path(tempfile.mkdtemp(prefix="rig-schemathesis-"))
_APP = hdf5_app(_DATA)
atexit.register(shutil.rmtree, _DATA, ignore_errors=True)
atexit.register(_APP.state.services.store.close)
# the binary batch form and an .eln archive are bytes on the wire, as application/octet-stream
schemathesis.serializer.alias(NPZ_MEDIA_TYPE, "application/octet-stream")
schemathesis.serializer.alias(ELN_MEDIA_TYPE, "application/octet-stream")
NOT_CHECKED = [checks.negative_data_rejection, checks.positive_data_acceptance]
# the model calculators (/models) are left to their own tests: their solvers take minutes on
# the extreme inputs schemathesis sends (e.g. a move to 1e307 rad)
schema = schemathesis.openapi.from_asgi("/openapi.json", _StoreStaysOpen(_APP)).exclude(
    path_regex="^/api/v1/models/"
)


_RUNS = [
    TestClient(_APP)
    .post(f"{API}/runs", json={"stand": stand.value, "operator": "x"}, headers=auth(WRITER))
    .json()["id"]
    for stand in StandKind
]


#: One test per operation, named by it ("GET /api/v1/runs"): pytest-xdist tells tests apart by
#: their ids, and ``schema.parametrize()`` gives every operation the same one.
OPERATIONS = [result.ok() for result in schema.get_all_operations()]


@pytest.mark.parametrize("operation", OPERATIONS, ids=lambda operation: operation.label)
def test_no_500_and_no_schema_violation(operation: APIOperation) -> None:
    @given(case=operation.as_strategy())
    @settings(max_examples=25, deadline=None, suppress_health_check=list(HealthCheck))
    def answered(case: schemathesis.Case) -> None:
        run_id = (case.path_parameters or {}).get("run_id")
        if isinstance(run_id, str) and len(run_id) % 5:  # four cases in five: a real run
            case.path_parameters["run_id"] = _RUNS[len(run_id) % len(_RUNS)]  # type: ignore[index]
        case.call_and_validate(headers=auth(WRITER), excluded_checks=NOT_CHECKED)

    answered()
