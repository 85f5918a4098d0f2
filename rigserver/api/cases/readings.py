"""A posted batch of readings: admitted by the ingest queue, read (JSON columns or binary
npz), checked against its channels' limits and the run's last values, and stored; the
API's post and the run page's rows alike."""

from __future__ import annotations

import json
from collections.abc import Mapping
from functools import partial
from typing import Any

import jiter
from fastapi import Request
from fastapi.concurrency import run_in_threadpool
from pydantic import ValidationError

from rigserver.api.auth import ApiKey
from rigserver.api.cases.found import load_run
from rigserver.api.deps import Services
from rigserver.api.ingest_queue import Place
from rigserver.api.npz import parse_npz
from rigserver.api.problems import ApiProblem, violations
from rigserver.storage.base import NewBatch
from schemas.channels import ChannelGroup, Violation, check_columns, follows
from schemas.readings import NPZ_MEDIA_TYPE, BatchReceipt, ReadingBatch
from schemas.stands import Stand
from schemas.strict_json import JsonRefused, strict_loads
from schemas.wire import ascii_count

#: Bodies up to this size are parsed and stored on the event loop (stored in groups, see
#: rigserver.api.ingest_queue); larger ones in a worker thread.
SMALL_BODY_BYTES = 64 << 10


def group_of(stand: Stand, name: str) -> ChannelGroup:
    """The stand's channel group ``name``; 422 naming the groups it has."""
    group = stand.group(name)
    if group is None:
        known = ", ".join(g.name for g in stand.groups)
        raise ApiProblem(
            422,
            "Unknown channel group",
            f"stand {stand.kind.value!r} has no channel group {name!r}; known: {known}",
            [Violation(field="group", value=name[:40], limit=f"one of {known}", message="")],
        )
    return group


def _refuse_violations(
    group: ChannelGroup, columns: Mapping[str, Any], last: Mapping[str, float]
) -> None:
    """The stand's limits and orderings, checked against the run's last stored values."""
    violations = check_columns(group, columns, last)
    if violations:
        raise ApiProblem(
            422,
            "Readings refused",
            f"{violations[0].message} (nothing of this batch was stored)",
            violations,
        )


def _refuse_across(
    group: ChannelGroup, columns: Mapping[str, Any], last: Mapping[str, float]
) -> None:
    """The order across batches of a batch found good on its own (under the store's lock,
    which :func:`_refuse_violations` on a large batch would hold for a millisecond)."""
    if not follows(group, columns, last):
        _refuse_violations(group, columns, last)


def _read_batch(
    media: str, body: bytes, limit: int, stand: Stand, seq: int, group: str, *, alone: bool
) -> tuple[int, ChannelGroup, Mapping[str, Any]]:
    """The body's batch: its seq and group (a JSON body's own; npz's ``seq`` and ``group``
    come from the query), its group's declaration and its columns; if ``alone``, checked on
    their own (limits, order within the batch: a large body's, in the thread that reads it)."""
    columns: Mapping[str, Any]
    if media == NPZ_MEDIA_TYPE:
        columns = parse_npz(body, limit)
    else:
        batch = _parse_json(body)
        seq, group, columns = batch.seq, batch.group, batch.columns
    decl = group_of(stand, group)
    if alone:
        _refuse_violations(decl, columns, {})
    return seq, decl, columns


def _parse_json(body: bytes) -> ReadingBatch:
    """The batch of a JSON body, strictly: one fast pass (jiter, which also catches a key
    given twice) and the model's strict types; a body jiter refuses is judged again by
    :func:`strict_loads`, for the message (and the lone surrogates that only it reads)."""
    try:
        tree = jiter.from_json(body, catch_duplicate_keys=True)
    except ValueError:
        try:
            tree = strict_loads(body)
        except json.JSONDecodeError as exc:
            where = exc.pos if isinstance(exc, JsonRefused) else "body"
            raise ApiProblem(
                422,
                "Invalid batch",
                f"{where}: invalid JSON: {exc.msg}",
                [Violation(field=str(where), message=f"{where}: invalid JSON: {exc.msg}")],
            ) from None
    try:
        return ReadingBatch.model_validate(tree)
    except ValidationError as exc:
        errors = violations(exc.errors())
        raise ApiProblem(422, "Invalid batch", errors[0].message, errors) from None


async def stand_of_run(services: Services, run_id: str) -> Stand:
    """The run's stand as its configuration sets it (the units in a refusal's message):
    remembered, or looked up (404 for an unknown run)."""
    stand = services.run_stands.get(run_id)
    if stand is None:
        stand = services.stand_of(await run_in_threadpool(load_run, services, run_id))
        services.remember_stand(run_id, stand)
    return stand


async def _body(request: Request, place: Place) -> bytes:
    """The body, each piece counted in the ingest queue as it arrives (503 once it
    overflows the key's share or the queue: read no further)."""
    chunks = []
    async for chunk in request.stream():
        if chunk:
            place.arrived(len(chunk))
            chunks.append(chunk)
    return b"".join(chunks)


def _declared_length(request: Request) -> int:
    value = request.headers.get("content-length", "")
    return ascii_count(value) or 0


async def store_posted(
    request: Request,
    services: Services,
    run_id: str,
    stand: Stand,
    writer: ApiKey,
    media: str = "application/json",
    seq: int = 0,
    group: str = "",
) -> BatchReceipt:
    """The batch of the request's body, checked and stored for ``writer`` (whose scope is
    checked): the API's post and the run page's rows alike (:mod:`rigserver.api.routes.entry`)."""
    with services.ingest.admit(_declared_length(request), writer.fingerprint) as place:
        body = await _body(request, place)
        small = len(body) <= SMALL_BODY_BYTES
        read = partial(
            _read_batch, media, body, services.settings.max_body_bytes, stand, seq, group
        )
        if small:  # the check with the run's last values, under the store's lock
            seq, decl, columns = read(alone=False)
            check = partial(_refuse_violations, decl)
        else:  # checked on its own here; only the order after the last values under the lock
            seq, decl, columns = await run_in_threadpool(partial(read, alone=True))
            check = partial(_refuse_across, decl)
        del body, read  # a JSON body is parsed: its bytes are not needed any more
        try:
            return await services.ingest.store(
                NewBatch(run_id, seq, decl.name, columns, check), small=small
            )
        except ValueError as exc:  # the store's own check of the batch's shape
            raise ApiProblem(422, "Batch does not fit its group", str(exc)) from None
