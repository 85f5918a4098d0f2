"""What every store checks and shares: a new run's stored form; a batch's fit, digest, padding
and receipt.

The API has checked the readings against their limits (``schemas.channels.check_columns``);
a store checks only what it needs to store the batch sensibly: the group belongs to the
run's stand, the channel names are the group's, the channels of an aligned group come
all together (or, where the group declares ``required`` sets, at least one set of them: the
others are stored as NaN) with equal lengths.

In a non-aligned group (``measurements``) a batch may carry any subset of the channels, of
any lengths; the stores keep every channel of a group at the same length by padding the
absent or shorter channels with NaN, so a NaN there means "not in that batch", and
:func:`last_finite` is what counts as a channel's latest value.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache

import numpy as np
import xxhash
from numpy.typing import ArrayLike, NDArray

from rigserver.storage.base import NewBatch
from rigserver.storage.errors import KeyReused, SequenceConflict
from schemas.channels import ChannelGroup
from schemas.readings import BatchReceipt
from schemas.runs import Run, RunState
from schemas.stands import StandKind, default_stands


@dataclass(frozen=True, slots=True)
class Batch:
    """A batch as the stores handle it.

    Attributes
    ----------
    group : str
        The channel group.
    columns : dict of str to ndarray
        Channel name -> 1-D little-endian float64 values, as posted, sorted by name.
    rows : int
        Rows the batch adds to its group: the longest column.
    digest : bytes
        XXH3-128 of the group, the channel names and lengths and the values: a retry's
        fingerprint (a seq reused for other readings differs in it but for a 2^-128
        chance; it runs at memory speed, a cryptographic hash ten times slower).
    """

    group: str
    columns: dict[str, NDArray[np.float64]]
    rows: int
    digest: bytes


@dataclass(frozen=True, slots=True)
class StoredBatch:
    """What a store remembers of every batch, for ever: enough to answer a retry."""

    group: str
    rows: int
    group_rows: int
    digest: bytes


def new_run(run: Run) -> Run:
    """The run as a store keeps it when created: open, no batches, every group at 0 rows."""
    if run.state is not RunState.OPEN or run.ended is not None:
        raise ValueError(f"a new run must be open, not {run.state.value}")
    rows = {g.name: 0 for g in stand_groups(run.stand)}
    return run.model_copy(deep=True, update={"batches": 0, "rows": rows})


#: What a run is opened with: a retried opening (the same Idempotency-Key) asks the same.
_OPENED_WITH = {"stand", "operator", "title", "specimen", "test_plan", "notes", "configuration"}


def reopened(existing: Run, run: Run, key: str) -> Run:
    """The run opened before with ``key``; ``KeyReused`` if ``run`` asks for another."""
    if existing.model_dump(include=_OPENED_WITH) != run.model_dump(include=_OPENED_WITH):
        raise KeyReused(
            f"the Idempotency-Key {key[:80]!r} opened run {existing.id} with other values; "
            "a new run needs a new key",
            existing.id,
        )
    return existing


def posted(nb: NewBatch) -> Batch:
    """A posted batch as the stores keep it (:func:`prepare`); ``ValueError`` for a
    negative seq (those number the batches taken back from a run file) or bad columns."""
    if nb.seq < 0:
        raise ValueError(f"seq must be >= 0, not {nb.seq}")
    return prepare(nb.group, nb.columns)


def posted_or_refusal(nb: NewBatch) -> Batch | ValueError:
    """The batch as stored (:func:`posted`), or why it cannot be."""
    try:
        return posted(nb)
    except ValueError as exc:
        return exc


def prepare(group: str, columns: Mapping[str, ArrayLike]) -> Batch:
    """The batch as contiguous float64 columns of its own with its digest; ``ValueError``
    if a column is not a flat list of numbers."""
    cols: dict[str, NDArray[np.float64]] = {}
    for name in sorted(columns):
        try:
            values = _owned(columns[name])
        except (TypeError, ValueError) as exc:
            raise ValueError(f"channel {name!r} of group {group!r} must be numbers") from exc
        if values.ndim != 1:
            raise ValueError(f"channel {name!r} of group {group!r} must be a flat list")
        cols[name] = values
    try:
        digest = xxhash.xxh3_128(group.encode())
        for name, values in cols.items():
            digest.update(b"\0" + name.encode() + b"\0" + len(values).to_bytes(8, "little"))
            digest.update(values.data)
    except UnicodeEncodeError as exc:
        raise ValueError(f"a channel name of group {group!r} is not valid text: {exc}") from None
    rows = max((len(v) for v in cols.values()), default=0)
    return Batch(group=group, columns=cols, rows=rows, digest=digest.digest())


def _owned(values: ArrayLike) -> NDArray[np.float64]:
    """The values as a contiguous little-endian float64 array that nobody else can change:
    a read-only array over immutable ``bytes`` or over memory of its own (a binary batch's
    column, :mod:`rigserver.api.npz`) as it is, others copied."""
    if (
        isinstance(values, np.ndarray)
        and (isinstance(values.base, bytes) or values.flags.owndata)
        and not values.flags.writeable
        and values.dtype == np.dtype("<f8")
        and values.flags.c_contiguous
    ):
        return values
    return np.array(values, dtype="<f8", order="C")


@cache
def _groups(stand: StandKind) -> dict[str, ChannelGroup]:
    return {g.name: g for g in default_stands()[stand].groups}


def stand_groups(stand: StandKind) -> tuple[ChannelGroup, ...]:
    """The channel groups of a stand kind, in declaration order."""
    return tuple(_groups(stand).values())


def channel_group(stand: StandKind, group: str) -> ChannelGroup:
    """The declaration of ``group``; ``ValueError`` if the stand has no such group."""
    found = _groups(stand).get(group)
    if found is None:
        known = ", ".join(_groups(stand))
        raise ValueError(f"stand {stand.value!r} has no channel group {group!r} (known: {known})")
    return found


def channel_names(decl: ChannelGroup, channels: list[str] | None) -> list[str]:
    """The channels asked for (all, in declaration order, if ``None``); ``ValueError``."""
    if channels is None:
        return [c.name for c in decl.channels]
    for name in channels:
        if decl.channel(name) is None:
            raise ValueError(f"group {decl.name!r} has no channel {name!r}")
    return list(channels)


def check(stand: StandKind, batch: Batch) -> ChannelGroup:
    """The batch's group declaration, once the batch fits it; ``ValueError`` otherwise."""
    decl = channel_group(stand, batch.group)
    if not batch.columns:
        raise ValueError(f"the batch of group {batch.group!r} carries no channel")
    known = [c.name for c in decl.channels]
    unknown = sorted(set(batch.columns) - set(known))
    if unknown:
        raise ValueError(
            f"group {batch.group!r} has no channel {unknown[0]!r} (known: {', '.join(known)})"
        )
    if decl.aligned:
        lacks = decl.missing(batch.columns.keys())
        if lacks is not None:
            raise ValueError(lacks)
        if len({len(v) for v in batch.columns.values()}) > 1:
            detail = ", ".join(f"{n}: {len(v)}" for n, v in batch.columns.items())
            raise ValueError(f"channels of group {decl.name!r} differ in length ({detail})")
    return decl


def padded(
    decl: ChannelGroup, columns: Mapping[str, NDArray[np.float64]], rows: int
) -> dict[str, NDArray[np.float64]]:
    """Every channel of the group, ``rows`` long, in declaration order, NaN where absent."""
    out: dict[str, NDArray[np.float64]] = {}
    for ch in decl.channels:
        values = columns.get(ch.name)
        if values is not None and len(values) == rows:
            out[ch.name] = values
        else:
            full = np.full(rows, np.nan)
            if values is not None:
                full[: len(values)] = values
            out[ch.name] = full
    return out


def last_finite(values: NDArray[np.float64]) -> float | None:
    """The last non-NaN value, or ``None``."""
    found = np.flatnonzero(~np.isnan(values))
    return float(values[found[-1]]) if found.size else None


def stored_receipt(run_id: str, seq: int, stored: StoredBatch, *, duplicate: bool) -> BatchReceipt:
    # validated all the same: pydantic's validator is a third of model_construct's cost
    return BatchReceipt(
        run_id=run_id,
        seq=seq,
        group=stored.group,
        rows=stored.rows,
        group_rows=stored.group_rows,
        duplicate=duplicate,
    )


def retry_receipt(run_id: str, seq: int, stored: StoredBatch, batch: Batch) -> BatchReceipt:
    """The first receipt again for a retried batch; ``SequenceConflict`` if it differs."""
    if stored.digest != batch.digest:
        raise SequenceConflict(
            f"seq {seq} of run {run_id} was stored with other readings ({stored.rows} rows of "
            f"group {stored.group!r}); a new batch needs a new seq"
        )
    return stored_receipt(run_id, seq, stored, duplicate=True)
