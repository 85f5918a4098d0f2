"""Results and truth printed for a person at the lab PC (rich tables): the results with
their declared labels, in the display units (:mod:`schemas.labels`)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import fields, is_dataclass
from typing import Any

import numpy as np
from rich.console import Console
from rich.table import Table

from schemas import labelled
from schemas.labels import Label, Part, plain_symbol, theory_outside
from schemas.stands import StandKind
from schemas.units import UNITS


def _text(value: Any) -> str:
    if isinstance(value, float) and not isinstance(value, bool):
        return f"{value:.5g}"
    return str(value)


def _shown(label: Label, value: Any, stored: str) -> str:
    """A result as its label declares it: display unit, digits, 0 below its resolution."""
    if value is None:
        return ""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return str(value)
    return f"{label.shown(value, stored):.{label.digits}g}"


def _unit(label: Label) -> str:
    return "" if label.unit == "1" else UNITS[label.unit].symbol.replace("um", "µm")


def results_tables(results: Mapping[str, Any]) -> list[Table]:
    """The single results in the declared order with their labels, in the display units
    (:mod:`schemas.labels`: µm, mg, mm³), then one table per per-row table (steps, ...)."""
    kind = StandKind(results["stand"])
    main = Table(title=f"results ({kind.value})")
    main.add_column("quantity")
    main.add_column("symbol")
    main.add_column("value", justify="right")
    main.add_column("unit")
    outside = theory_outside(kind, results.get("values", {}))
    for e in labelled.scalars(kind, results):
        value = _shown(e.label, e.value, e.stored)
        if outside and e.label.part is Part.THEORY and isinstance(e.value, int | float):
            value += " (theory outside its range)"
        main.add_row(_name(e.label), plain_symbol(e.label.symbol), value, _unit(e.label))
    tables = [main]
    for found in labelled.row_tables(kind, results):
        table = Table(title=found.table.caption)
        for c in found.columns:
            unit = _unit(c.label)
            head = plain_symbol(c.symbol) or c.label.text
            table.add_column(f"{head} [{unit}]" if unit else head, justify="right")
        for row in found.rows:
            table.add_row(
                *(
                    _shown(c.label, cell, c.stored)
                    for c, cell in zip(found.columns, row, strict=True)
                )
            )
        tables.append(table)
    return tables


def _name(label: Label) -> str:
    return f"{label.text} ({label.equation})" if label.equation else label.text


def truth_tables(truth: Any) -> list[Table]:
    """The simulator's truth (SI units, as documented on its class): its scalar fields, then
    one table per tuple of entries (the MTOS steps)."""
    table = Table(title=f"simulator truth ({type(truth).__name__}, SI units)")
    table.add_column("field")
    table.add_column("value", justify="right")
    entries: list[Table] = []
    if not is_dataclass(truth):
        return [table]
    for f in fields(truth):
        value = getattr(truth, f.name)
        if isinstance(value, tuple) and value and is_dataclass(value[0]):
            entries.append(_entries_table(f.name, value))
            continue
        if isinstance(value, np.ndarray):
            value = f"{value.size} values, mean {float(np.mean(value)):.5g}"
        table.add_row(f.name, _text(value))
    return [table, *entries]


def _entries_table(name: str, entries: tuple[Any, ...]) -> Table:
    columns = [
        f.name
        for f in fields(entries[0])
        if isinstance(getattr(entries[0], f.name), bool | int | float | str)
    ]
    table = Table(title=f"truth: {name}")
    for column in columns:
        table.add_column(column, justify="right")
    for entry in entries:
        table.add_row(*(_text(getattr(entry, c)) for c in columns))
    return table


def print_results(console: Console, results: Mapping[str, Any], truth: Any = None) -> None:
    for table in results_tables(results):
        console.print(table)
    if truth is not None:
        for table in truth_tables(truth):
            console.print(table)
