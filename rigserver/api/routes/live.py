"""``/runs/{id}/live``: the readings of one channel group as they arrive (server-sent events).

Each ``rows`` event carries the rows ``start:stop`` of the group as JSON columns, with
``id: <stop>``, the number of rows the client has then seen. A browser's ``EventSource``
sends that id back as ``Last-Event-ID`` when it reconnects, so a dropped connection
resumes where it broke, with no row lost or repeated (``?from=`` sets the first row of a
new connection). When the run has ended and every row is sent, an ``end`` event carries
its state and the stream closes. A correction of a row of the group made while the stream is
open (a cell corrected, a row struck out: ``/runs/{id}/readings/{group}/{index}``) is told
by a ``corrected`` event carrying the correction (``row``, ``channel``, ``was``, ``now``,
``reason``; ``channel`` null for a row struck out); the ``rows`` events carry the values as
typed. The store tells when a run's batch is stored or the run ends
(:class:`~rigserver.storage.base.LiveStore`: the embedded stores in process, a cluster by
PostgreSQL's LISTEN/NOTIFY), which wakes the stream at once, and an idle stream costs
nothing until its keep-alive is due; a cluster's stream also reads the catalogue every
``NOTIFIED_POLL_SECONDS`` in case a notification was lost. A connection is closed after
``MAX_SECONDS`` (the client reconnects and resumes), and at once when the server is asked
to stop (its waiters are woken), so no stream holds up a server's shutdown; a client that
goes away is noticed at the next write (a keep-alive comment at the latest).
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import AsyncIterator
from typing import Annotated

from fastapi import APIRouter, Query, Request
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import StreamingResponse

from rigserver.api.cases.found import load_run
from rigserver.api.deps import ReadAccess, Services, ServicesDep
from rigserver.api.problems import ApiProblem
from schemas.channels import ChannelGroup
from schemas.runs import RunState
from schemas.stands import Stand
from schemas.wire import Text, ascii_count

router = APIRouter(prefix="/runs/{run_id}", tags=["live"], dependencies=[ReadAccess])

NOTIFIED_POLL_SECONDS = 5.0
"""How often a stream whose store may lose a notification (a cluster) reads the run's row
counts again."""
MAX_ROWS = 5_000
"""Most rows in one event; a longer backlog goes out in several."""
KEEPALIVE_SECONDS = 15.0
"""A comment line after this long without an event keeps proxies from closing the stream."""
MAX_SECONDS = 60.0
"""Lifetime of one connection; the client reconnects with ``Last-Event-ID``."""
RETRY_MS = 1000
"""The reconnection delay the client is told."""

EVENT_STREAM = "text/event-stream"


def live_group(stand: Stand, name: str | None) -> ChannelGroup:
    """The group asked for, or the stand's first aligned group (its record)."""
    aligned = [g for g in stand.groups if g.aligned]
    if name is None:
        return aligned[0]
    for group in aligned:
        if group.name == name:
            return group
    known = ", ".join(g.name for g in aligned)
    raise ApiProblem(
        422,
        "Unknown channel group",
        f"stand {stand.kind.value!r} streams the groups {known}, not {name[:40]!r}",
    )


def _first_row(last_event_id: str | None, start: int) -> int:
    if last_event_id is None:
        return start
    rows = ascii_count(last_event_id)
    if rows is None:
        raise ApiProblem(
            422,
            "Bad Last-Event-ID",
            f"Last-Event-ID is the number of rows already received, got {last_event_id[:40]!r}",
        )
    return rows


def _event(name: str, data: object, event_id: int | None = None) -> str:
    head = f"event: {name}\n" + (f"id: {event_id}\n" if event_id is not None else "")
    return f"{head}data: {json.dumps(data, separators=(',', ':'))}\n\n"


def _rows_event(services: Services, run_id: str, group: str, start: int, stop: int) -> str:
    columns = services.store.read(run_id, group, None, start, stop)
    data = {
        "start": start,
        "stop": stop,
        "columns": {
            name: [v if math.isfinite(v) else None for v in values.tolist()]
            for name, values in columns.items()
        },
    }
    return _event("rows", data, stop)


async def _stream(services: Services, run_id: str, group: str, seen: int) -> AsyncIterator[str]:
    yield f"retry: {RETRY_MS}\n\n"
    opened = last_sent = time.monotonic()
    store = services.store
    lossy = store.appends_lossy
    told = -1  # corrections told so far (-1: none read yet; those made before are not told)
    while True:
        run = await run_in_threadpool(store.get_run, run_id)
        total = run.rows.get(group, 0)
        while seen < total:
            stop = min(total, seen + MAX_ROWS)
            yield await run_in_threadpool(_rows_event, services, run_id, group, seen, stop)
            seen, last_sent = stop, time.monotonic()
        if told < 0:
            told = run.corrections
        elif run.corrections > told:
            found = await run_in_threadpool(store.corrections, run_id)
            for c in found[told:]:
                if c.group == group:
                    yield _event("corrected", c.model_dump(mode="json"), seen)
                    last_sent = time.monotonic()
            told = len(found)
        if run.state is not RunState.OPEN:
            yield _event("end", {"state": run.state.value, "rows": seen})
            return
        # Woken when a batch of the run is stored or it ends; an idle stream sleeps until
        # its keep-alive is due (and reads the catalogue again only if the store may lose
        # a notification).
        while True:
            if _expired(services, opened):
                return
            now = time.monotonic()
            due = last_sent + KEEPALIVE_SECONDS - now
            timeout = min(due, opened + MAX_SECONDS - now)
            if lossy:
                timeout = min(timeout, NOTIFIED_POLL_SECONDS)
            if await store.wait_for_appends(run_id, run.batches, max(timeout, 0.0)) or lossy:
                break
            if time.monotonic() - last_sent >= KEEPALIVE_SECONDS:
                yield ": keep-alive\n\n"
                last_sent = time.monotonic()


def _expired(services: Services, opened: float) -> bool:
    """The connection has lived its time, or the server is stopping."""
    return time.monotonic() - opened > MAX_SECONDS or services.stopping.is_set()


@router.get(
    "/live",
    summary="The readings of a channel group as they arrive (server-sent events, resumable)",
    description="Events: `rows` (`{start, stop, columns}`, with `id` = rows seen), "
    "`corrected` (a correction made meanwhile: `{row, channel, was, now, reason, ...}`) and "
    "`end` (`{state, rows}`) once the run has ended and every row was sent. Reconnect with "
    "`Last-Event-ID` (a browser's EventSource does) to resume.",
    response_class=StreamingResponse,
    responses={200: {"content": {EVENT_STREAM: {}}}},
)
async def live(
    run_id: str,
    request: Request,
    services: ServicesDep,
    group: Annotated[Text | None, Query(max_length=40, description="default: the record")] = None,
    start: Annotated[int, Query(alias="from", ge=0, description="first row to send")] = 0,
) -> StreamingResponse:
    run = await run_in_threadpool(load_run, services, run_id)
    chosen = live_group(services.stand_of(run), group)
    seen = _first_row(request.headers.get("last-event-id"), start)
    return StreamingResponse(
        _stream(services, run.id, chosen.name, seen),
        media_type=EVENT_STREAM,
        headers={"Cache-Control": "no-cache", "X-Accel-Buffering": "no"},
    )
