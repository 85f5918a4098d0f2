"""The catalogue's columns, the same in the embedded store's SQLite journal and the cluster's
PostgreSQL catalogue: a run's entry, and the filters of a run query."""

from __future__ import annotations

import json
from collections.abc import Callable
from datetime import datetime

from rigserver.storage._time import as_utc
from schemas.runs import Run, RunQuery

#: The columns of :func:`entry`, in its order.
ENTRY_COLUMNS = (
    "id, stand, operator, state, created, ended, run, batches, rows, key_results, results"
)


def entry(run: Run, results: str | None, time: Callable[[datetime], object]) -> tuple[object, ...]:
    """The run's catalogue entry (:data:`ENTRY_COLUMNS`): the filters' columns, the run as
    JSON, its counters, its results' text; its times as ``time`` gives them."""
    return (
        run.id,
        run.stand.value,
        run.operator,
        run.state.value,
        time(run.created),
        None if run.ended is None else time(run.ended),
        run.model_dump_json(),
        run.batches,
        json.dumps(run.rows),
        json.dumps(run.key_results),
        results,
    )


def run_filters(query: RunQuery) -> list[tuple[str, str, object]]:
    """The catalogue columns ``query`` filters on: (column, operator, value), values as
    text but the times (``since <= created < until``), which are aware UTC."""
    found: list[tuple[str, str, object]] = [
        (column, "=", getattr(value, "value", value))
        for column, value in (
            ("stand", query.stand),
            ("operator", query.operator),
            ("state", query.state),
        )
        if value is not None
    ]
    for bound, op in ((query.since, ">="), (query.until, "<")):
        if bound is not None:
            found.append(("created", op, as_utc(bound)))
    return found
