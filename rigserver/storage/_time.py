"""Times as the stores keep them: aware UTC, and a sortable ISO 8601 text."""

from __future__ import annotations

from datetime import UTC, datetime


def as_utc(t: datetime) -> datetime:
    """``t`` in UTC; a naive time is taken to be UTC already."""
    return t.replace(tzinfo=UTC) if t.tzinfo is None else t.astimezone(UTC)


def iso(t: datetime) -> str:
    """Fixed-width ISO 8601 in UTC (``2024-05-01T12:00:00.000000Z``): text order is time order."""
    return as_utc(t).strftime("%Y-%m-%dT%H:%M:%S.%fZ")


def now() -> datetime:
    return datetime.now(UTC)
