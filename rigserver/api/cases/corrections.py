"""A stored reading corrected or struck out, keeping the value as typed; a finished run's
results computed again and its reports rendered again."""

from __future__ import annotations

from rigserver.api.auth import ApiKey
from rigserver.api.cases.found import load_run
from rigserver.api.cases.notes import author
from rigserver.api.cases.reports import render_finished
from rigserver.api.deps import Services, require_write
from rigserver.api.problems import ApiProblem
from rigserver.api.run_results import compute_results
from rigserver.storage.corrections import CorrectionRefused
from schemas.corrections import CorrectedRow, CorrectionWrite, StrikeWrite
from schemas.runs import RunState


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
