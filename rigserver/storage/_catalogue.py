"""The catalogue's filters of a run query, the same in the embedded store's SQLite journal
and the cluster's PostgreSQL catalogue."""

from __future__ import annotations

from rigserver.storage._time import as_utc
from schemas.runs import RunQuery


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
