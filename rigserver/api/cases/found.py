"""A run named in a request, loaded: a 404 that says why when it is not there (a malformed id
never reaches the store)."""

from __future__ import annotations

from rigserver.api.deps import Services
from rigserver.api.problems import ApiProblem
from schemas.runs import Run, is_run_id


def load_run(services: Services, run_id: str) -> Run:
    """The run, or a 404 that says why (a malformed id never reaches the store)."""
    if not is_run_id(run_id):
        raise ApiProblem(
            404,
            "Run not found",
            f"{run_id[:40]!r} is not a run id (they look like 20261122T114026Z-1a2b3c4d)",
        )
    return services.store.get_run(run_id)
