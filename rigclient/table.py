"""A stand's CSV/TSV file read row by row: the header, the units, decimal commas.

The first line is the header. Its cells name the channels, or the map (:mod:`rigclient.mapping`)
says which cell is which channel; a unit in the cell (``load [kN]``, ``load (kN)``, and in
files not separated by commas ``load, kN``) or in the map is converted to the channel's unit.
The separator is a tab if the header has one, else a semicolon if it has one, else a comma; in
a file separated by tabs or semicolons a comma in a number is the decimal comma. A line that
cannot be read is an :class:`InputError` naming the file, the line and the column.
"""

from __future__ import annotations

import csv
import re
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rigclient.errors import InputError
from rigclient.mapping import StandMap, unit_factor
from schemas.channels import ChannelGroup

_BRACKETED = re.compile(r"^(?P<name>.*?)\s*(?:\[(?P<a>[^\]]*)\]|\((?P<b>[^)]*)\))$")
_COMMA = re.compile(r"^(?P<name>[^,]*?)\s*,\s*(?P<unit>[^,]+)$")


def split_header(cell: str, delimiter: str) -> tuple[str, str | None]:
    """A header cell as (name, unit or None): ``load [kN]``, ``load (kN)``, ``load, kN``."""
    found = _BRACKETED.match(cell)
    if found:
        return found["name"].strip(), (found["a"] or found["b"] or "").strip() or None
    found = _COMMA.match(cell) if delimiter != "," else None
    if found:
        return found["name"].strip(), found["unit"].strip()
    return cell.strip(), None


def sniff(header: str) -> str:
    """The separator of a file from its header line."""
    return "\t" if "\t" in header else ";" if ";" in header else ","


@dataclass(frozen=True, slots=True)
class Field:
    """A file column that feeds a channel: its index, header text, channel and factor."""

    index: int
    header: str
    channel: str
    factor: float


@dataclass(frozen=True, slots=True)
class Table:
    """How the rows of one file become a group's columns."""

    file: str
    delimiter: str
    fields: tuple[Field, ...]
    width: int
    ignored: tuple[str, ...]

    @property
    def decimal_comma(self) -> bool:
        return self.delimiter != ","

    @property
    def channels(self) -> tuple[str, ...]:
        return tuple(f.channel for f in self.fields)

    @classmethod
    def from_header(
        cls, header: str, *, file: str, group: ChannelGroup, mapping: StandMap | None
    ) -> Table:
        """Read the header line against the group's channels and the map."""
        delimiter = sniff(header)
        cells = _cells(header.lstrip("\ufeff"), delimiter)
        units = {c.name: c.unit for c in group.channels}
        listed = mapping is not None and bool(mapping.columns)
        fields: list[Field] = []
        ignored: list[str] = []
        for index, cell in enumerate(cells):
            name, unit = split_header(cell, delimiter)
            mapped = mapping.column(cell, name) if mapping is not None else None
            if mapped is not None:
                channel = mapped.channel
            elif name in units:
                channel = name
            elif listed or not cell:
                ignored.append(cell)
                continue
            else:
                raise InputError(
                    f"{cell!r} is not a channel of {group.name!r} ({', '.join(units)}); "
                    "name it in the map's [columns]",
                    file=file,
                    line=1,
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
                    line=1,
                    column=cell,
                )
            if mapped is not None and mapped.factor is not None:
                factor = mapped.factor
            else:
                source = (mapped.unit if mapped is not None else None) or unit
                factor = 1.0 if source is None else unit_factor(source, units[channel], where=cell)
            fields.append(Field(index, cell, channel, factor))
        seen = [f.channel for f in fields]
        twice = sorted({c for c in seen if seen.count(c) > 1})
        if twice:
            raise InputError(f"two columns feed {', '.join(twice)}", file=file, line=1)
        missing = [c for c in units if c not in seen]
        if group.aligned and missing:
            raise InputError(
                f"no column for {', '.join(missing)} of {group.name!r} (the header has "
                f"{', '.join(cells)}); name them in the map's [columns]",
                file=file,
                line=1,
            )
        if not fields:
            raise InputError(f"no column feeds a channel of {group.name!r}", file=file, line=1)
        return cls(file, delimiter, tuple(fields), len(cells), tuple(ignored))

    def parse(self, text: str, line: int) -> list[float]:
        """One data line as the channels' values, in the order of :attr:`channels`."""
        cells = _cells(text, self.delimiter)
        if len(cells) < self.width:
            raise InputError(
                f"{len(cells)} cells where the header has {self.width}",
                file=self.file,
                line=line,
                column=self.fields[-1].header if len(cells) <= self.fields[-1].index else "",
            )
        values = []
        for f in self.fields:
            cell = cells[f.index].strip()
            number = cell.replace(",", ".") if self.decimal_comma else cell
            try:
                value = float(number)
            except ValueError:
                raise InputError(
                    f"{cell!r} is not a number", file=self.file, line=line, column=f.header
                ) from None
            values.append(value * f.factor)
        return values

    def columns(self, rows: list[list[float]]) -> dict[str, NDArray[np.float64]]:
        """Rows from :meth:`parse` as the group's columns."""
        array = np.asarray(rows, dtype=np.float64).reshape(len(rows), len(self.fields))
        return {f.channel: array[:, k].copy() for k, f in enumerate(self.fields)}


def _cells(text: str, delimiter: str) -> list[str]:
    return next(csv.reader([text.rstrip("\r\n")], delimiter=delimiter), [])
