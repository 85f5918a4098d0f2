"""Runs: loaded (a 404 that says why), opened with their configuration's snapshot, ended
(finished with their results, or aborted)."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

from pydantic import ValidationError

from rigserver.api.auth import ApiKey
from rigserver.api.cases.found import load_run
from rigserver.api.cases.reports import render_finished
from rigserver.api.deps import Services, require_write
from rigserver.api.problems import ApiProblem, violations
from rigserver.api.run_results import compute_results
from rigserver.storage.errors import KeyReused
from schemas.runs import (
    Run,
    RunCreate,
    RunState,
    given_paths,
    new_run_id,
)
from schemas.stands import with_overrides


def snapshot(services: Services, body: RunCreate, prefix: str = "") -> dict[str, Any]:
    """The configuration snapshot of a run opened with ``body``: the stand's with the
    body's overrides, checked by its schema (422 naming the field, after ``prefix``). An
    imported run's is checked here too (``rigserver.api.routes.eln``)."""
    stand = services.stands[body.stand]
    try:
        configuration = with_overrides(stand.configuration, body.configuration)
    except ValidationError as exc:
        errors = violations(exc.errors(), f"{prefix}configuration.")
        raise ApiProblem(422, "Invalid configuration", errors[0].message, errors) from None
    return configuration.model_dump(mode="json")


def owned_key(caller: ApiKey | None, idempotency_key: str | None) -> str | None:
    """The Idempotency-Key as the store keeps it: prefixed by the fingerprint of the API
    key that sent it, so that another API key sending the same string opens a run of its
    own and never learns the run the first one opened."""
    if idempotency_key is None or caller is None:
        return idempotency_key
    return f"{caller.fingerprint}:{idempotency_key}"


def open_run(
    services: Services, caller: ApiKey | None, body: RunCreate, idempotency_key: str | None
) -> tuple[Run, bool]:
    """Open the run ``body`` asks for, for a key with its stand's write scope; with the run
    opened before under the same ``idempotency_key`` (and False) if there is one: the API's
    ``POST /runs`` and the page ``/runs/new`` alike."""
    require_write(caller, body.stand)
    run = Run(
        id=new_run_id(),
        stand=body.stand,
        operator=body.operator,
        title=body.title,
        specimen=body.specimen,
        test_plan=body.test_plan,
        notes=body.notes,
        configuration=snapshot(services, body),
        configuration_given=dict.fromkeys(given_paths(body.configuration), body.given_by),
        created=datetime.now(UTC),
    )
    try:
        stored = services.store.create_run(run, owned_key(caller, idempotency_key))
    except KeyReused as exc:
        raise ApiProblem(
            409,
            "Idempotency-Key reused",
            f"the Idempotency-Key {idempotency_key!r} opened run {exc.run_id} with other "
            "values; a new run needs a new key",
        ) from None
    return stored, stored.id == run.id


def end_run(run_id: str, services: Services, caller: Any, state: RunState) -> Run:
    """Finish (results computed and stored) or abort an open run, for a key with its
    stand's write scope: the API's and the run page's buttons alike."""
    run = load_run(services, run_id)
    require_write(caller, run.stand)
    _require_open(run)
    with services.run_locks[run_id]:
        run = services.store.get_run(run_id)  # as the lock leaves it: no batch lands now
        _require_open(run)  # a concurrent finish or abort came first
        results = None
        if state is RunState.FINISHED:
            results = services.results.for_finish(run, lambda: compute_results(services, run))
            services.store.set_results(run_id, results.payload, results.key_results)
        ended = services.store.end_run(run_id, state)
    if results is not None and services.settings.reports_on_finish:
        values = results.payload["values"]
        services.reports.soon(
            f"rendering the reports of run {run_id}",
            lambda: render_finished(services, run_id, values),
        )
    return ended


def _require_open(run: Run) -> None:
    if run.state is not RunState.OPEN:
        raise ApiProblem(409, "Run is not open", f"run {run.id} is already {run.state.value}")
