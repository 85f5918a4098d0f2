"""Corrections of stored readings, the same in every store: what a correction may change, the
records it leaves, and the readings as corrected.

A store never overwrites a reading: it keeps the values as typed and, beside them, the
corrections in the order made (:class:`schemas.corrections.Correction`: a cell's ``was`` and
``now``, or a row struck out, with the reason, the key's name and the time). The readings
*as corrected* are the stored ones with each correction applied in turn and the struck rows
left out; row indices are always those of the rows as stored, so a correction names its
row the same way before and after a strike.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime
from typing import NoReturn, Protocol

import numpy as np
from numpy.typing import NDArray

from rigserver.storage._checks import channel_group, last_finite
from schemas.channels import ChannelGroup, Violation, check_cell, configured_groups
from schemas.corrections import REASON_LIMIT, CorrectedRow, Correction
from schemas.runs import Run, RunState
from schemas.stands import MEASUREMENTS

Columns = dict[str, NDArray[np.float64]]
#: Reads rows ``start:stop`` of a group as stored (every channel).
RowReader = Callable[[int, int], Mapping[str, NDArray[np.float64]]]


class CorrectionRefused(ValueError):
    """A correction that cannot be stored: the violations name the field, value and limit."""

    def __init__(self, violations: Sequence[Violation]) -> None:
        super().__init__(violations[0].message)
        self.violations = list(violations)


@dataclass(frozen=True, slots=True)
class RowEdit:
    """One correction asked for: row ``index`` of ``group``, its new ``values`` (None: the
    row struck out), the ``reason`` and who asks (``by``, the key's name)."""

    group: str
    index: int
    values: dict[str, float] | None
    reason: str
    by: str


class RowEdits:
    """:meth:`RunStore.correct_reading` and :meth:`RunStore.strike_reading` of a store that
    implements ``_edit`` (``values`` None: the row struck out)."""

    def correct_reading(
        self,
        run_id: str,
        group: str,
        index: int,
        values: Mapping[str, float],
        reason: str,
        by: str,
    ) -> CorrectedRow:
        """Correct cells of row ``index`` of ``group`` (:meth:`RunStore.correct_reading`)."""
        return self._edit(run_id, RowEdit(group, index, dict(values), reason, by))

    def strike_reading(
        self, run_id: str, group: str, index: int, reason: str, by: str
    ) -> CorrectedRow:
        """Strike row ``index`` of ``group`` out (:meth:`RunStore.strike_reading`)."""
        return self._edit(run_id, RowEdit(group, index, None, reason, by))

    def _edit(self, run_id: str, edit: RowEdit) -> CorrectedRow:
        raise NotImplementedError


def struck_rows(corrections: Sequence[Correction], group: str) -> set[int]:
    return {c.row for c in corrections if c.group == group and c.strikes}


def applied(
    columns: Mapping[str, NDArray[np.float64]],
    corrections: Sequence[Correction],
    group: str,
    start: int = 0,
) -> Columns:
    """Rows ``start:start + n`` of ``group`` as stored (``columns``) as corrected: each
    correction of those rows applied in turn, the struck rows left out."""
    mine = [c for c in corrections if c.group == group]
    out = {name: np.array(values, dtype=np.float64) for name, values in columns.items()}
    if not mine or not out:
        return out
    n = max(len(v) for v in out.values())
    keep = np.ones(n, dtype=bool)
    for c in mine:
        i = c.row - start
        if not 0 <= i < n:
            continue
        if c.strikes:
            keep[i] = False
        elif c.channel in out and c.now is not None:
            out[c.channel][i] = c.now
    if keep.all():
        return out
    return {name: values[keep] for name, values in out.items()}


def last_values(columns: Mapping[str, NDArray[np.float64]]) -> dict[str, float]:
    """The last finite value of each channel (a single measurement's latest)."""
    found: dict[str, float] = {}
    for name, values in columns.items():
        value = last_finite(np.asarray(values, dtype=np.float64))
        if value is not None:
            found[name] = value
    return found


def corrected_row(
    run_id: str,
    group: str,
    index: int,
    original: Mapping[str, NDArray[np.float64]],
    corrections: Sequence[Correction],
) -> CorrectedRow:
    """Row ``index`` (``original``: that one row as stored) as it now reads."""
    typed = {name: _cell(values[0]) for name, values in original.items()}
    values = dict(typed)
    mine = [c for c in corrections if c.group == group and c.row == index]
    for c in mine:
        if c.channel is not None:
            values[c.channel] = c.now
    return CorrectedRow(
        run_id=run_id,
        group=group,
        index=index,
        struck=any(c.strikes for c in mine),
        values=values,
        original=typed,
        corrections=mine,
    )


def corrected_run(run: Run, every: Sequence[Correction]) -> Run:
    """The run's catalogue entry once ``every`` correction of it is made: their count, and
    whether any came after it finished."""
    after = run.state is RunState.FINISHED or run.corrected_after_finish
    update = {"corrections": len(every), "corrected_after_finish": after}
    return run.model_copy(deep=True, update=update)


def new_corrections(
    run: Run, edit: RowEdit, at: datetime, read: RowReader, earlier: Sequence[Correction]
) -> list[Correction]:
    """The records ``edit`` adds to ``run`` (made ``at``), checked as a post is checked;
    empty if the row already reads so (a retry).

    ``read`` gives rows as stored, ``earlier`` the run's corrections so far. Raises
    :class:`CorrectionRefused` naming the field (``group``, ``index``, ``values.<channel>``,
    ``reason``) with the value and the limit.
    """
    group, index, values, reason, by = edit.group, edit.index, edit.values, edit.reason, edit.by
    decl = _group(run, group)
    why = reason.strip() if isinstance(reason, str) else ""
    if not why or len(why) > REASON_LIMIT or "\x00" in why:
        shown = reason[:40] if isinstance(reason, str) else None
        _refuse("reason", shown, f"1 to {REASON_LIMIT} characters, no NUL")
    rows = run.rows.get(group, 0)
    if not 0 <= index < rows:
        limit = f"0 <= index < {rows}" if rows else "the group holds no rows yet"
        _refuse("index", index, limit, f"{group} has no row {index} ({limit})")
    struck = struck_rows(earlier, group)
    if index in struck:
        if values is None:
            return []
        _refuse("index", index, "a row not struck out", f"row {index} of {group} is struck out")
    lo, hi = max(index - 1, 0), min(index + 2, rows)
    window = applied(read(lo, hi), [c for c in earlier if c.row not in struck], group, lo)
    now = {name: float(v[index - lo]) for name, v in window.items()}
    n = len(earlier)
    if values is None:
        return [Correction(n=n + 1, group=group, row=index, channel=None, reason=why, by=by, at=at)]
    problems: list[Violation] = []
    found: list[Correction] = []
    for name, value in values.items():
        ch = decl.channel(name)
        if ch is None:
            known = ", ".join(c.name for c in decl.channels)
            problems.append(
                Violation(
                    field=f"values.{name}",
                    value=name[:40],
                    limit=f"one of {known}",
                    message=f"{group!r} has no channel {name[:40]!r}",
                )
            )
            continue
        was = now[name]
        if math.isnan(was):
            problems.append(
                Violation(
                    field=f"values.{name}",
                    message=f"row {index} of {group} holds no {name} (none was posted "
                    "there): post it as a reading",
                )
            )
            continue
        before = _neighbour(window, name, index - 1 - lo, index - 1, struck)
        after = _neighbour(window, name, index + 1 - lo, index + 1, struck)
        problems.extend(check_cell(ch, float(value), before, after))
        if float(value) != was:
            found.append(
                Correction(
                    n=n + len(found) + 1,
                    group=group,
                    row=index,
                    channel=name,
                    was=was,
                    now=float(value),
                    unit=ch.unit,
                    reason=why,
                    by=by,
                    at=at,
                )
            )
    if problems:
        raise CorrectionRefused(problems)
    return found


def _neighbour(
    window: Mapping[str, NDArray[np.float64]], name: str, i: int, row: int, struck: set[int]
) -> float | None:
    values = window[name]
    if row in struck or not 0 <= i < len(values):
        return None
    return float(values[i])


def _group(run: Run, group: str) -> ChannelGroup:
    try:
        channel_group(run.stand, group)
    except ValueError:
        _refuse("group", group[:40], "a channel group of the run's stand", f"no group {group!r}")
    # the limits in the run's configured units (the slide-bearing gauges' at or atm)
    (decl,) = (g for g in configured_groups((channel_group(run.stand, group),), run.configuration))
    return decl


def _refuse(field: str, value: object, limit: str, message: str | None = None) -> NoReturn:
    shown = value if isinstance(value, int | float | str) or value is None else str(value)
    raise CorrectionRefused(
        [
            Violation(
                field=field,
                value=shown,
                limit=limit,
                message=message or f"{field}: {limit}",
            )
        ]
    )


def _cell(value: float) -> float | None:
    number = float(value)
    return None if math.isnan(number) else number


class CorrectedReadings:
    """A run's readings (any :class:`~rigserver.analysis.Readings`) as corrected."""

    def __init__(self, inner: _Readings, corrections: Sequence[Correction]) -> None:
        self._inner = inner
        self.corrections = list(corrections)

    def rows(self, group: str) -> int:
        return self._inner.rows(group) - len(struck_rows(self.corrections, group))

    def read(self, group: str, channels: list[str] | None = None) -> Columns:
        if not self._touches(group):
            return self._inner.read(group, channels)
        return applied(self._inner.read(group, channels), self.corrections, group)

    def iter_chunks(
        self, group: str, channels: list[str] | None = None, rows: int = 1 << 20
    ) -> Iterator[Columns]:
        if not self._touches(group):
            yield from self._inner.iter_chunks(group, channels, rows)
            return
        start = 0
        for chunk in self._inner.iter_chunks(group, channels, rows):
            n = max((len(v) for v in chunk.values()), default=0)
            yield applied(chunk, self.corrections, group, start)
            start += n

    def measurements(self) -> dict[str, float]:
        if not self._touches(MEASUREMENTS):
            return self._inner.measurements()
        return last_values(self.read(MEASUREMENTS))

    def _touches(self, group: str) -> bool:
        return any(c.group == group for c in self.corrections)


class _Readings(Protocol):
    """What :class:`CorrectedReadings` reads: :class:`rigserver.analysis.Readings` (storage
    does not import the analysis)."""

    def rows(self, group: str) -> int: ...

    def read(self, group: str, channels: list[str] | None = None) -> Columns: ...

    def iter_chunks(
        self, group: str, channels: list[str] | None = None, rows: int = 1 << 20
    ) -> Iterator[Columns]: ...

    def measurements(self) -> dict[str, float]: ...
