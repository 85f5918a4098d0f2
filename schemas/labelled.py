"""A results payload walked by its declared labels (:mod:`schemas.labels`): the single
results in the declared order, each with its part of the report (measured, theory,
comparison), and the per-row tables (the MTOS steps, tables 3.1-3.3, the bearing curve) with
one column per declared quantity. Pure data: the pages, the exports and rigsim's console
summary print what this gives.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from itertools import zip_longest
from typing import Any

from schemas.labels import PARTS, Label, Part, RowTable
from schemas.stands import DECLARATIONS, StandKind


@dataclass(frozen=True, slots=True)
class Entry:
    """One result: its path in the payload, its label, its stored value and unit."""

    path: str
    label: Label
    value: Any
    stored: str


@dataclass(frozen=True, slots=True)
class Column:
    """A column of a per-row table; ``key`` names the entry of a result that is a mapping
    (the MTOS temperature rises ``t2``..``t5``, the viscosities at the thermocouples)."""

    path: str
    label: Label
    stored: str
    key: str | None = None

    @property
    def symbol(self) -> str:
        if self.key is None:
            return self.label.symbol
        index = self.key.lstrip("t")
        if self.label.symbol.endswith("_i"):  # the running index takes the entry's (μ_i: μ_1)
            return f"{self.label.symbol[:-1]}{{{index}}}"
        return f"{self.label.symbol}_{{{index}}}"


@dataclass(frozen=True, slots=True)
class RowsOf:
    """A per-row table of a run's results: its declaration, its columns and rows."""

    table: RowTable
    columns: Sequence[Column]
    rows: Sequence[Sequence[Any]]


def _get(values: Mapping[str, Any], path: str) -> Any:
    node: Any = values
    for part in path.split("."):
        if not isinstance(node, Mapping):
            return None
        node = node.get(part)
    return node


def _column_values(values: Mapping[str, Any], path: str) -> list[Any]:
    """The values of a table column: ``steps[].chi`` (a field of each row) or ``levels``."""
    if "[]." in path:
        rows, field = path.split("[].", 1)
        found = _get(values, rows)
        return [_get(row, field) for row in found] if isinstance(found, list) else []
    found = _get(values, path)
    return list(found) if isinstance(found, list) else []


def _in_tables(kind: StandKind) -> set[str]:
    return {path for table in DECLARATIONS[kind].tables for path in table.columns}


def scalars(kind: StandKind, payload: Mapping[str, Any]) -> list[Entry]:
    """The single results present in ``payload``, in the declared order; a result that
    repeats an earlier one (the same symbol, equation and value: the sliding distance L
    (2.12) of the record and of the wear table) is listed once."""
    values: Mapping[str, Any] = payload.get("values", {})
    units: Mapping[str, str] = payload.get("units", {})
    tabled = _in_tables(kind)
    found: list[Entry] = []
    for path, label in DECLARATIONS[kind].labels.items():
        if path in tabled or "[]" in path:
            continue
        value = _get(values, path)
        if value is None or isinstance(value, list | dict):
            continue
        same = (label.symbol, label.equation, value)
        if label.symbol and any((e.label.symbol, e.label.equation, e.value) == same for e in found):
            continue
        found.append(Entry(path, label, value, units.get(path, label.unit)))
    return found


def by_part(entries: Sequence[Entry]) -> list[tuple[str, list[Entry]]]:
    """The entries grouped as in the report: measured, theory, comparison (titles are
    message ids)."""
    return [
        (PARTS[part], chosen)
        for part in Part
        if (chosen := [e for e in entries if e.label.part is part])
    ]


def row_tables(kind: StandKind, payload: Mapping[str, Any]) -> list[RowsOf]:
    """The stand's per-row tables that hold rows in ``payload``."""
    values: Mapping[str, Any] = payload.get("values", {})
    units: Mapping[str, str] = payload.get("units", {})
    labels = DECLARATIONS[kind].labels
    tables = []
    for table in DECLARATIONS[kind].tables:
        columns: list[Column] = []
        data: list[list[Any]] = []
        for path in table.columns:
            cells = _column_values(values, path)
            if not cells:
                continue
            stored = units.get(path, labels[path].unit)
            if isinstance(cells[0], Mapping):  # one column per entry of the mapping
                for key in cells[0]:
                    columns.append(Column(path, labels[path], stored, key))
                    data.append([cell.get(key) for cell in cells])
            else:
                columns.append(Column(path, labels[path], stored))
                data.append(cells)
        if columns:
            rows = [list(row) for row in zip_longest(*data, fillvalue=None)]
            tables.append(RowsOf(table, columns, rows))
    return tables
