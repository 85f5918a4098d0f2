"""A run's results printed for a person at the lab PC (rich tables): the results with their
declared labels, in the display units (:mod:`schemas.labels`). ``rigclient import`` prints
them once the run is finished; ``rigsim`` prints the same tables."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from rich.table import Table

from schemas import labelled
from schemas.labels import Label, Part, plain_symbol, theory_outside
from schemas.stands import StandKind
from schemas.units import UNITS


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
