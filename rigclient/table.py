"""A stand's file read row by row: the header, the units, the constants, the checks.

The header's cells name the channels, or the map (:mod:`rigclient.mapping`) says which cell
is which channel; a unit in the cell (``load [kN]``, ``Time (s)``, and in files not
separated by commas ``load, kN``) or in the map is converted to the channel's unit. The
map's ``[constants]`` give the channels the file lacks (a test setting such as the normal
load). The dialect (delimiter, decimal mark) is :mod:`rigclient.dialect`'s. A line that
cannot be read is an :class:`InputError` naming the file, the line and the column; so is a
value outside its channel's limits or against its order, which the server would refuse
with the whole batch.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from rigclient.dialect import cells, header_cells, header_names, name_key, number, split_header
from rigclient.errors import InputError
from rigclient.mapping import ColumnMap, StandMap
from rigclient.units import dimension, unit_factor
from schemas.channels import Channel, ChannelGroup, Order


@dataclass(frozen=True, slots=True)
class Field:
    """A file column that feeds a channel: its index, header text, channel, and the
    channel's value as the file's × ``factor`` + ``offset``."""

    index: int
    header: str
    channel: str
    factor: float
    offset: float = 0.0


@dataclass(slots=True)
class Clock:
    """A time that restarts (at each step, block or file: a UMT's, a recipe's) continued
    from where it ended: a value not after the last one taken starts a new part, shifted so
    that its first row follows the last row taken by the step between the last two (the
    map's ``[file] continue_time = true``)."""

    offset: float = 0.0
    step: float = 0.0
    _pending: tuple[float, float] | None = None  # offset and step if the row is taken

    def time(self, value: float, last: float | None) -> float:
        """The continued time of a row whose time reads ``value``; ``last``: the time of
        the last row taken (continued)."""
        offset, step = self.offset, self.step
        shifted = value + offset
        if last is not None and shifted <= last:  # the time restarted
            offset = last + step - value
            shifted = value + offset
        elif last is not None:
            step = shifted - last
        self._pending = (offset, step)
        return shifted

    def taken(self) -> None:
        """The row read last was taken (a row refused changes nothing)."""
        if self._pending is not None:
            self.offset, self.step = self._pending
            self._pending = None


@dataclass(slots=True)
class Table:
    """How the rows of one file (from one header line on) become a group's columns."""

    file: str
    delimiter: str
    decimal: str | None
    fields: tuple[Field, ...]
    width: int
    ignored: tuple[str, ...]
    constants: dict[str, float]
    group: ChannelGroup
    names: frozenset[str] = frozenset()  # the header's names (name_key), to know it again
    last: dict[str, float] = field(default_factory=dict)  # ordered channels' last values
    clock: Clock | None = None  # the map's continue_time: a time that restarts goes on
    _checks: dict[str, Channel] = field(default_factory=dict)
    _rules: list[_Rule] = field(default_factory=list)

    def __post_init__(self) -> None:
        self._checks = {c.name: c for c in self.group.channels}
        self._rules = [_rule(self._checks[f.channel]) for f in self.fields]

    @property
    def channels(self) -> tuple[str, ...]:
        return tuple(f.channel for f in self.fields)

    @classmethod
    def from_header(
        cls,
        header: str,
        *,
        file: str,
        group: ChannelGroup,
        mapping: StandMap | None,
        line: int = 1,
        delimiter: str | None = None,
        decimal: str | None = None,
        width: int | None = None,
        units_row: list[str] | None = None,
    ) -> Table:
        """Read the header line (number ``line``) against the group's channels and the map;
        ``width``: the cells of the rows under it, if known; ``units_row``: the cells of
        its units line (``g,g,mm,...``), if it has one."""
        delimiter = delimiter or sniff(header)
        found = header_cells(header.lstrip("\ufeff"), delimiter, width)
        units = {c.name: c.unit for c in group.channels}
        keys = {name_key(c): c for c in units}
        listed = mapping is not None and bool(mapping.columns)
        fields: list[Field] = []
        ignored: list[str] = []
        for index, raw in enumerate(found):
            cell = raw.strip()
            name, unit = split_header(cell, delimiter)
            if unit is None and units_row is not None and index < len(units_row):
                unit = units_row[index] or None
            mapped = mapping.column(cell, name) if mapping is not None else None
            if mapped is not None:
                channel = mapped.channel
            elif name_key(name) in keys:
                channel = keys[name_key(name)]
            elif listed or not cell:
                ignored.append(cell)
                continue
            else:
                raise InputError(
                    f"{cell!r} is not a channel of {group.name!r} ({', '.join(units)}); "
                    "name it in the map's [columns]",
                    file=file,
                    line=line,
                    column=cell,
                )
            if not channel:
                ignored.append(cell)
                continue
            if channel not in units:
                raise InputError(
                    f"the map sends it to {channel!r}, not a channel of {group.name!r} "
                    f"({', '.join(units)})",
                    file=file,
                    line=line,
                    column=cell,
                )
            factor, offset = (mapped.factor, mapped.offset) if mapped is not None else (1.0, 0.0)
            try:
                scale = _scale(mapped, unit, units[channel])
            except InputError as exc:
                message = str(exc).split(": ", 1)[-1]
                raise InputError(message, file=file, line=line, column=cell) from None
            fields.append(Field(index, cell, channel, factor * scale, offset * scale))
        constants = _constants(mapping, units, file)
        seen = [f.channel for f in fields]
        twice = sorted({c for c in seen if seen.count(c) > 1})
        if twice:
            raise InputError(f"two columns feed {', '.join(twice)}", file=file, line=line)
        both = sorted(set(seen) & set(constants))
        if both:
            raise InputError(
                f"{', '.join(both)}: both a column and a constant of the map's [constants]",
                file=file,
                line=line,
            )
        missing = [c for c in units if c not in seen and c not in constants]
        if group.required:  # a tribometer: time and μ, or time, F_t and F_N
            lacks = group.missing([*seen, *constants])
            if lacks is not None:
                raise InputError(
                    f"{lacks} (the header has {', '.join(c.strip() for c in found)}); name them "
                    "in the map's [columns], or give them in its [constants]",
                    file=file,
                    line=line,
                )
        elif group.aligned and missing:
            raise InputError(
                f"no column for {', '.join(missing)} of {group.name!r} (the header has "
                f"{', '.join(c.strip() for c in found)}); name them in the map's [columns], "
                "or give them in its [constants]",
                file=file,
                line=line,
            )
        if not fields:
            raise InputError(f"no column feeds a channel of {group.name!r}", file=file, line=line)
        names = header_names(found, delimiter)
        return cls(
            file,
            delimiter,
            decimal,
            tuple(fields),
            len(found),
            tuple(ignored),
            constants,
            group,
            names,
            clock=Clock() if mapping is not None and mapping.file.continue_time else None,
        )

    def carry(self, before: Table) -> Table:
        """This table (of a header met later: a new block, the next file) going on from
        ``before``: its channels' last values, and its clock."""
        self.last.update(before.last)
        if self.clock is not None and before.clock is not None:
            self.clock = before.clock
        return self

    def parse(self, text: str, line: int) -> list[float]:
        """One data line as the channels' values, in the order of :attr:`channels`: each a
        number within its channel's limits and order (:class:`InputError` names the cell)."""
        try:
            found = cells(text, self.delimiter)
        except InputError as exc:
            raise InputError(str(exc), file=self.file, line=line) from None
        if len(found) < self.width:
            raise InputError(
                f"{len(found)} cells where the header has {self.width}",
                file=self.file,
                line=line,
                column=self.fields[-1].header if len(found) <= self.fields[-1].index else "",
            )
        values = []
        for f, (low, high, nominal, tolerance, integer, order) in zip(
            self.fields, self._rules, strict=True
        ):
            try:
                value = number(found[f.index], self.decimal) * f.factor + f.offset
            except ValueError as exc:
                raise InputError(str(exc), file=self.file, line=line, column=f.header) from None
            if self.clock is not None and f.channel == "time":
                value = self.clock.time(value, self.last.get("time"))
            if (
                not (low <= value <= high and math.isfinite(value))  # a factor's overflow
                or (nominal and not any(abs(value - v) <= tolerance * abs(v) for v in nominal))
                or (integer and value != round(value))
            ):
                channel = self._checks[f.channel]
                raise InputError(
                    f"{value:g} {channel.unit} is outside the limit of {f.channel}: "
                    f"{channel.limit.describe(channel.unit)}",
                    file=self.file,
                    line=line,
                    column=f.header,
                )
            if order is not Order.ANY:
                self._in_order(f, order, value, line)
            values.append(value)
        for f, rule, value in zip(self.fields, self._rules, values, strict=True):
            if rule[-1] is not Order.ANY:
                self.last[f.channel] = value
        if self.clock is not None:
            self.clock.taken()
        return values

    def _in_order(self, f: Field, order: Order, value: float, line: int) -> None:
        last = self.last.get(f.channel)
        if last is not None and (
            (order is Order.INCREASING and value <= last)
            or (order is Order.NON_DECREASING and value < last)
        ):
            unit = self._checks[f.channel].unit
            raise InputError(
                f"{f.channel} = {value:g} {unit} after {last:g}: it must be "
                f"{order.value.replace('_', '-')}",
                file=self.file,
                line=line,
                column=f.header,
            )

    def is_header(self, text: str) -> bool:
        """Whether a line that is not a row is a header: two or more cells, each a word
        (not a number of any spelling), and a name this header or the group knows, or as
        many cells as this header."""
        try:
            found = [c.strip() for c in header_cells(text, self.delimiter) if c.strip()]
        except InputError:
            return False
        if len(found) < 2 or not all(_word(c) for c in found):
            return False
        names = header_names(found, self.delimiter)
        known = self.names | {name_key(c.name) for c in self.group.channels}
        return bool(names & known) or len(found) == self.width

    def columns(self, rows: list[list[float]]) -> dict[str, NDArray[np.float64]]:
        """Rows from :meth:`parse` as the group's columns (the constants repeated)."""
        array = np.asarray(rows, dtype=np.float64).reshape(len(rows), len(self.fields))
        out = {f.channel: array[:, k].copy() for k, f in enumerate(self.fields)}
        for name, value in self.constants.items():
            out[name] = np.full(len(rows), value)
        return out


#: A channel's limit and order as plain numbers: low, high, nominal, tolerance, integer,
#: order (the check of one value without numpy).
_Rule = tuple[float, float, tuple[float, ...], float, bool, Order]


def _rule(channel: Channel) -> _Rule:
    limit = channel.limit
    low = -math.inf if limit.low is None else limit.low
    high = math.inf if limit.high is None else limit.high
    return (low, high, limit.nominal or (), limit.tolerance, limit.integer, channel.order)


def _word(cell: str) -> bool:
    """A cell that holds a letter and that Python's ``float`` does not take (``nan``,
    ``inf``, ``3_05``, other scripts' digits are numbers of a spelling, not names)."""
    try:
        float(cell.replace(",", "."))
    except ValueError:
        return any(ch.isalpha() for ch in cell)
    return False


def _scale(mapped: ColumnMap | None, header: str | None, channel: str) -> float:
    """The factor from a column's unit to its channel's: the map's unit, else the header's
    (or the units line's), else none. A map's factor without a unit on a column whose
    header's unit is not the channel's quantity (``M, div``) is the factor into the
    channel's unit itself: the header's unit is then left aside."""
    if mapped is not None and mapped.unit is not None:
        return unit_factor(mapped.unit, channel)
    if header is None:
        return 1.0
    if mapped is not None and (mapped.factor, mapped.offset) != (1.0, 0.0):
        try:
            return unit_factor(header, channel)
        except InputError:
            return 1.0
    return unit_factor(header, channel)


def _constants(mapping: StandMap | None, units: Mapping[str, str], file: str) -> dict[str, float]:
    if mapping is None:
        return {}
    out = {}
    for name, (value, unit) in mapping.constants.items():
        if name not in units:
            raise InputError(
                f"{name!r} of [constants] is not a channel ({', '.join(units)})",
                file=mapping.source or file,
                column=name,
            )
        factor = 1.0 if unit is None else unit_factor(unit, units[name], where=name)
        out[name] = value * factor
    return out


def units_line(text: str, above: str, delimiter: str) -> bool:
    """Whether ``text`` is the units line of the header ``above`` (CETR/Bruker UMT: ``g,g,
    mm,...``): as many cells, each blank or a known unit (:mod:`rigclient.units`), one at
    least, and ``above`` a line of names with no unit among them."""
    try:
        found, names = cells(text, delimiter), cells(above, delimiter)
    except InputError:
        return False
    given = [c.strip() for c in found if c.strip()]
    if not given or len(found) != len(names) or not all(dimension(c) for c in given):
        return False
    return not any(dimension(c.strip()) for c in names if c.strip())


def sniff(header: str) -> str:
    """The separator of a header line alone: tab, semicolon, comma, else runs of spaces."""
    return next((d for d in ("\t", ";", ",") if d in header), " ")
