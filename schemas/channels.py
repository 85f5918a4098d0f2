"""Channels declared as data: name, unit, limits, ordering; and the check of a batch.

A stand's readings come in channel groups. In an *aligned* group (the SMTs-2 friction
record, the rows of table 3.1) every batch carries every channel with the same length; in
the ``measurements`` group (masses, zero readings, the end of the load zone) a batch may
carry any subset, and the latest value of each channel counts.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from enum import StrEnum
from functools import cached_property
from math import inf, isfinite, nan

import numpy as np
from numpy.typing import NDArray
from pydantic import BaseModel, ConfigDict, Field, model_validator

from schemas.units import UnitSymbol


class Order(StrEnum):
    """What a channel's values must do along the batch (and across batches)."""

    ANY = "any"
    INCREASING = "increasing"
    NON_DECREASING = "non_decreasing"


class Limit(BaseModel):
    """What one value of a channel may be; prints itself the way a lab user reads it.

    ``low``/``high`` bound the value; ``nominal`` with ``tolerance`` (relative) allows only
    values near one of a few settings (the SMTs-2 speeds, 300, 500 or 1000 rpm ± 10 %);
    ``integer`` asks for whole numbers (codes, counters).
    """

    model_config = ConfigDict(frozen=True)

    low: float | None = None
    high: float | None = None
    nominal: tuple[float, ...] | None = None
    tolerance: float = Field(default=0.0, ge=0.0)
    integer: bool = False

    def describe(self, unit: str) -> str:
        """The limit in words, e.g. ``"200 <= value <= 5000 N"``."""
        u = "" if unit in ("1", "code") else f" {unit}"
        parts: list[str] = []
        if self.nominal is not None:
            values = ", ".join(f"{v:g}" for v in self.nominal)
            tol = f" (± {self.tolerance * 100:g} %)" if self.tolerance else ""
            parts.append(f"one of {values}{u}{tol}")
        if self.low is not None and self.high is not None:
            parts.append(f"{self.low:g} <= value <= {self.high:g}{u}")
        elif self.low is not None:
            parts.append(f"value >= {self.low:g}{u}")
        elif self.high is not None:
            parts.append(f"value <= {self.high:g}{u}")
        if self.integer:
            parts.append("a whole number")
        return "; ".join(parts) if parts else "any finite number"

    def violations(self, values: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Mask of the finite values that break this limit."""
        bad = np.zeros(values.shape, dtype=bool)
        if self.low is not None:
            bad |= values < self.low
        if self.high is not None:
            bad |= values > self.high
        if self.nominal is not None:
            near = np.zeros(values.shape, dtype=bool)
            for v in self.nominal:
                near |= np.abs(values - v) <= self.tolerance * abs(v)
            bad |= ~near
        if self.integer:
            bad |= values != np.round(values)
        return bad

    def holds_for(self, values: NDArray[np.float64]) -> bool:
        """True if the values are all finite and within this limit (and not empty).

        Judged from the least and the greatest value: two passes over the values instead of
        a mask per rule, so a large good batch is accepted quickly. False is no verdict when
        the values keep to two or more nominal settings (their extremes cannot tell):
        :meth:`violations` has the last word.
        """
        if not values.size:
            return False
        least, greatest = values.min(), values.max()  # a NaN makes both NaN
        if not (isfinite(least) and isfinite(greatest)):
            return False
        if (self.low is not None and least < self.low) or (
            self.high is not None and greatest > self.high
        ):
            return False
        if self.nominal is not None and not any(
            abs(least - v) <= self.tolerance * abs(v)
            and abs(greatest - v) <= self.tolerance * abs(v)
            for v in self.nominal
        ):
            return False
        return not self.integer or bool((np.round(values) == values).all())


class Channel(BaseModel):
    """One measured quantity: its name on the wire, unit, meaning and limits."""

    model_config = ConfigDict(frozen=True)

    name: str
    unit: UnitSymbol
    long_name: str
    limit: Limit = Limit()
    order: Order = Order.ANY
    unit_from: str | None = Field(
        default=None,
        description="the configuration field that sets the unit (``unit`` is its default)",
    )


class ChannelGroup(BaseModel):
    """Channels posted together; an aligned group has every channel in every batch."""

    model_config = ConfigDict(frozen=True)

    name: str
    long_name: str
    aligned: bool
    channels: tuple[Channel, ...]
    signals: tuple[str, ...] = Field(
        default=(),
        description="the measured quantities the group's default plot shows, the first the "
        "main one (NeXus NXdata @signal, the others @auxiliary_signals)",
    )
    axis: str | None = Field(
        default=None, description="the channel they are plotted against (NXdata @axes)"
    )
    required: tuple[tuple[str, ...], ...] = Field(
        default=(),
        description="an aligned group whose channels need not all come: a batch carries "
        "every channel of at least one of these sets, the others may be left out (stored as "
        "NaN); empty: every channel in every batch",
    )

    @model_validator(mode="after")
    def _plot_names_channels(self) -> ChannelGroup:
        names = {c.name for c in self.channels}
        for name in (*self.signals, *([self.axis] if self.axis else [])):
            if name not in names:
                raise ValueError(f"group {self.name!r} plots {name!r}, not one of its channels")
        if self.axis in self.signals:
            raise ValueError(f"group {self.name!r} plots {self.axis!r} against itself")
        for needed in self.required:
            if not needed or not set(needed) <= names:
                raise ValueError(f"group {self.name!r} requires {needed!r}: not its channels")
        return self

    def channel(self, name: str) -> Channel | None:
        return next((c for c in self.channels if c.name == name), None)

    def missing(self, names: Collection[str]) -> str | None:
        """Why an aligned batch carrying the channels ``names`` lacks what it needs, or
        None when it has it (every channel, or one of the :attr:`required` sets)."""
        if not self.aligned:
            return None
        if not self.required:
            absent = [c.name for c in self.channels if c.name not in names]
            if not absent:
                return None
            return f"channel {absent[0]!r} is missing; group {self.name!r} needs all its channels"
        if any(set(needed) <= set(names) for needed in self.required):
            return None
        options = " or ".join(_and(needed) for needed in self.required)
        return f"group {self.name!r} needs {options} in every batch"

    @cached_property
    def quick_check(self) -> _QuickCheck:
        """The accept test of small batches (a group never changes: frozen)."""
        return _QuickCheck(self)


def configured_groups(
    groups: tuple[ChannelGroup, ...], configuration: Mapping[str, object]
) -> tuple[ChannelGroup, ...]:
    """The groups with the units that ``configuration`` sets (:attr:`Channel.unit_from`),
    e.g. the slide-bearing manometers read in ``gauge_unit``; the same groups if none."""

    def unit(c: Channel) -> object:
        return c.unit if c.unit_from is None else configuration.get(c.unit_from, c.unit)

    if all(unit(c) == c.unit for g in groups for c in g.channels):
        return groups
    return tuple(
        g.model_copy(
            update={
                "channels": tuple(
                    c if unit(c) == c.unit else Channel.model_validate({**dict(c), "unit": unit(c)})
                    for c in g.channels
                )
            }
        )
        for g in groups
    )


class Violation(BaseModel):
    """One reason a batch was refused: where, what value, which limit."""

    field: str = Field(examples=["columns.friction_moment[12]"])
    value: float | str | None = Field(default=None, examples=[15.7])
    limit: str | None = Field(default=None, examples=["0 <= value <= 15 N*m"])
    message: str = Field(examples=["friction_moment[12] = 15.7 N*m is outside 0 <= value <= 15"])


MAX_VIOLATIONS = 20


def check_columns(
    group: ChannelGroup,
    columns: Mapping[str, Sequence[float] | NDArray[np.float64]],
    last_values: Mapping[str, float] | None = None,
) -> list[Violation]:
    """Check a batch of columns against the group's declaration.

    Returns the violations (at most :data:`MAX_VIOLATIONS`; empty when the batch is good).
    ``last_values`` are the last stored values of ordered channels, so ordering holds across
    batches too. A good batch of a few rows is accepted without NumPy (a single reading
    would spend more in NumPy's calls than in the checks).
    """
    last = {} if last_values is None else last_values
    if group.quick_check.accepts(columns, last):
        return []
    return _violations(group, columns, last)


def _violations(
    group: ChannelGroup,
    columns: Mapping[str, Sequence[float] | NDArray[np.float64]],
    last: Mapping[str, float],
) -> list[Violation]:
    problems: list[Violation] = []
    known = {c.name for c in group.channels}
    for name in columns:
        if name not in known:
            problems.append(
                Violation(
                    field=f"columns.{name}",
                    value=name,
                    limit=f"one of {', '.join(sorted(known))}",
                    message=f"{group.name!r} has no channel {name!r}",
                )
            )
    if group.aligned and not group.required:
        missing = [c.name for c in group.channels if c.name not in columns]
        problems.extend(
            Violation(
                field=f"columns.{m}",
                message=f"channel {m!r} is missing; group {group.name!r} needs all its channels",
            )
            for m in missing
        )
    elif columns and (lacks := group.missing(columns.keys())) is not None:
        problems.append(Violation(field="columns", message=lacks))
    if not columns:
        problems.append(Violation(field="columns", message="the batch carries no channel"))
    lengths = {name: len(col) for name, col in columns.items() if name in known}
    if group.aligned and len(set(lengths.values())) > 1:
        detail = ", ".join(f"{n}: {k}" for n, k in lengths.items())
        problems.append(
            Violation(
                field="columns",
                message=f"channels of group {group.name!r} must have equal lengths ({detail})",
            )
        )
    for name, k in lengths.items():
        if k == 0:
            problems.append(Violation(field=f"columns.{name}", message=f"{name} is empty"))
    for ch in group.channels:
        if ch.name not in columns or len(problems) >= MAX_VIOLATIONS:
            continue
        try:
            values = np.asarray(columns[ch.name], dtype=np.float64)
        except (TypeError, ValueError):
            problems.append(
                Violation(field=f"columns.{ch.name}", message=f"{ch.name} must be numbers")
            )
            continue
        if values.ndim != 1:
            problems.append(
                Violation(field=f"columns.{ch.name}", message=f"{ch.name} must be a flat list")
            )
            continue
        problems.extend(_value_violations(ch, values, last))
    return problems[:MAX_VIOLATIONS]


def check_cell(
    ch: Channel, value: float, before: float | None = None, after: float | None = None
) -> list[Violation]:
    """A corrected cell of channel ``ch`` (field ``values.<channel>``): finite, within the
    channel's limit and, for an ordered channel, in order between the row's neighbours
    ``before`` and ``after`` (their values as they read; None at a group's ends)."""
    where = f"values.{ch.name}"
    if not isfinite(value):
        return [
            Violation(
                field=where,
                value=str(value),
                limit="a finite number",
                message=f"{ch.name} = {value} is not a finite number",
            )
        ]
    if ch.limit.violations(np.array([value])).any():
        text = ch.limit.describe(ch.unit)
        return [
            Violation(
                field=where,
                value=value,
                limit=text,
                message=f"{ch.name} = {value:g} {ch.unit} is outside the limit: {text}",
            )
        ]
    if ch.order is Order.ANY:
        return []
    word = "increase" if ch.order is Order.INCREASING else "not decrease"
    for neighbour, pair, side in (
        (before, (before, value), "before"),
        (after, (value, after), "after"),
    ):
        if (
            neighbour is not None
            and isfinite(neighbour)
            and not _in_order(ch.order, np.array(pair, dtype=np.float64), None)
        ):
            return [
                Violation(
                    field=where,
                    value=value,
                    limit=f"must {word} along the rows (the value {side} it is "
                    f"{neighbour:g} {ch.unit})",
                    message=f"{ch.name} = {value:g} must {word} along the rows; the value "
                    f"{side} it is {neighbour:g} {ch.unit}",
                )
            ]
    return []


def follows(
    group: ChannelGroup,
    columns: Mapping[str, Sequence[float] | NDArray[np.float64]],
    last_values: Mapping[str, float],
) -> bool:
    """True if each ordered channel's first value keeps its order after the run's last
    stored one: all that :func:`check_columns` with ``last_values`` adds to a batch it
    found good without them."""
    for ch in group.channels:
        previous = last_values.get(ch.name)
        values = columns.get(ch.name)
        if ch.order is Order.ANY or previous is None or values is None or not len(values):
            continue
        first = float(values[0])
        if first < previous or (ch.order is Order.INCREASING and first == previous):
            return False
    return True


class _QuickCheck:
    """Accepts a good batch of at most :data:`QUICK_VALUES` values in plain Python.

    The same limits and orderings as :meth:`Limit.violations` and :func:`_value_violations`
    (the tests hold the two to agreement); anything it does not accept, a refusal or a
    larger batch, goes to them for the verdict and the violations.
    """

    def __init__(self, group: ChannelGroup) -> None:
        self.aligned = group.aligned
        self.group = group
        self.names = frozenset(c.name for c in group.channels)
        #: name -> (low, high, ((nominal, tolerance), ...), integer, order)
        self.rules = {
            c.name: (
                -inf if c.limit.low is None else c.limit.low,
                inf if c.limit.high is None else c.limit.high,
                tuple((v, c.limit.tolerance * abs(v)) for v in c.limit.nominal or ()),
                c.limit.integer,
                c.order,
            )
            for c in group.channels
        }

    def accepts(
        self,
        columns: Mapping[str, Sequence[float] | NDArray[np.float64]],
        last: Mapping[str, float],
    ) -> bool:
        names = columns.keys()
        if not names or not names <= self.names or self.group.missing(names) is not None:
            return False
        lengths = {len(v) for v in columns.values()}
        if 0 in lengths or (self.aligned and len(lengths) > 1):
            return False
        if sum(len(v) for v in columns.values()) > QUICK_VALUES:
            return False
        for name, values in columns.items():
            low, high, nominal, integer, order = self.rules[name]
            previous = last.get(name, nan)
            for value in _plain(values):
                if not isinstance(value, float):  # not a number, or an integer or float32 array
                    return False
                if not (isfinite(value) and low <= value <= high):
                    return False
                if nominal and not any(abs(value - v) <= tol for v, tol in nominal):
                    return False
                if integer and value != round(value):
                    return False
                if order is Order.INCREASING and value <= previous:
                    return False
                if order is Order.NON_DECREASING and value < previous:
                    return False
                previous = value
        return True


def _plain(
    values: Sequence[float] | NDArray[np.float64],
) -> Sequence[float] | NDArray[np.float64]:
    """A float64 array's values as Python floats (NumPy iterates an array by indexing it
    until an IndexError, whose message it formats: more than the values' checks cost);
    anything else as it is, so that an integer or float32 array still goes to the full
    check."""
    if isinstance(values, np.ndarray) and values.dtype == np.float64:
        plain: list[float] = values.tolist()
        return plain
    return values


#: The largest batch (channels times rows) that :class:`_QuickCheck` looks at.
QUICK_VALUES = 64


def _value_violations(
    ch: Channel, values: NDArray[np.float64], last_values: Mapping[str, float] | None
) -> list[Violation]:
    previous = None if last_values is None else last_values.get(ch.name)
    if ch.limit.holds_for(values) and _in_order(ch.order, values, previous):
        return []  # the common case, decided without a mask per rule
    found: list[Violation] = []
    finite = np.isfinite(values)
    all_finite = bool(finite.all())  # then no index search for NaN and inf
    if not all_finite:
        for i in np.flatnonzero(~finite)[:MAX_VIOLATIONS]:
            found.append(
                Violation(
                    field=f"columns.{ch.name}[{i}]",
                    value=str(values[i]),
                    limit="a finite number",
                    message=f"{ch.name}[{i}] = {values[i]} is not a finite number",
                )
            )
    broken = ch.limit.violations(values if all_finite else np.where(finite, values, 0.0))
    if not all_finite:
        broken &= finite
    if broken.any():
        text = ch.limit.describe(ch.unit)
        for i in np.flatnonzero(broken)[:MAX_VIOLATIONS]:
            found.append(
                Violation(
                    field=f"columns.{ch.name}[{i}]",
                    value=float(values[i]),
                    limit=text,
                    message=f"{ch.name}[{i}] = {values[i]:g} {ch.unit} is outside the limit: "
                    f"{text}",
                )
            )
    if ch.order is not Order.ANY and values.size and all_finite:
        seq = values if previous is None else np.concatenate(([previous], values))
        step = np.diff(seq)
        bad = step <= 0 if ch.order is Order.INCREASING else step < 0
        if not bad.any():
            return found
        word = "increase" if ch.order is Order.INCREASING else "not decrease"
        offset = 0 if previous is None else 1
        for j in np.flatnonzero(bad)[:MAX_VIOLATIONS]:
            i = j + 1 - offset
            before = f"{seq[j]:g}"
            found.append(
                Violation(
                    field=f"columns.{ch.name}[{i}]",
                    value=float(values[i]),
                    limit=f"must {word} (previous value {before} {ch.unit})",
                    message=f"{ch.name}[{i}] = {values[i]:g} must {word}; the value before "
                    f"it is {before} {ch.unit}",
                )
            )
    return found


def _in_order(order: Order, values: NDArray[np.float64], previous: float | None) -> bool:
    """True if finite ``values`` keep ``order``, after ``previous`` (the last stored value)."""
    if order is Order.ANY:
        return True
    later, earlier = values[1:], values[:-1]
    if order is Order.INCREASING:
        return bool((later > earlier).all()) and not (
            previous is not None and values[0] <= previous
        )
    return bool((later >= earlier).all()) and not (previous is not None and values[0] < previous)


def _and(names: Sequence[str]) -> str:
    """``a``, ``a and b``, ``a, b and c``."""
    return names[0] if len(names) == 1 else f"{', '.join(names[:-1])} and {names[-1]}"
