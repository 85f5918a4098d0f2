"""Results and truth printed for a person at the lab PC (rich tables)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import fields, is_dataclass
from typing import Any

import numpy as np
from rich.console import Console
from rich.table import Table


def _scalars(values: Mapping[str, Any], prefix: str = "") -> list[tuple[str, Any]]:
    out: list[tuple[str, Any]] = []
    for name, value in values.items():
        if isinstance(value, Mapping):
            out += _scalars(value, f"{prefix}{name}.")
        elif isinstance(value, bool | int | float | str) or value is None:
            out.append((f"{prefix}{name}", value))
    return out


#: The columns shown of each list of rows in the results (all, if a list is not named here).
ROW_COLUMNS: dict[str, tuple[str, ...]] = {
    "steps": (
        "load",
        "regime",
        "chi",
        "angle",
        "friction_measured",
        "friction_theory",
        "viscosity",
        "h_min",
        "film",
    ),
    "table": ("limb_angle", "phi_model", "pressure", "chi", "pi_measured", "pi_short", "pi_long"),
    "axial": ("z", "pressure", "pi_measured", "pi_short", "error"),
}


def _text(value: Any) -> str:
    if isinstance(value, float) and not isinstance(value, bool):
        return f"{value:.5g}"
    return str(value)


def results_tables(results: Mapping[str, Any]) -> list[Table]:
    """The results' scalars with units, then one table per list of rows (steps, table...)."""
    values: Mapping[str, Any] = results.get("values", {})
    units: Mapping[str, str] = results.get("units", {})
    main = Table(title=f"results ({results.get('stand', '?')})")
    main.add_column("quantity")
    main.add_column("value", justify="right")
    main.add_column("unit")
    for name, value in _scalars(values):
        if value not in (None, ""):
            main.add_row(name, _text(value), units.get(name, ""))
    tables = [main]
    for name, rows in values.items():
        if not (isinstance(rows, list) and rows and isinstance(rows[0], Mapping)):
            continue
        present = [k for k, _ in _scalars(rows[0])]
        columns = [c for c in ROW_COLUMNS.get(name, tuple(present)) if c in present]
        table = Table(title=name)
        for column in columns:
            unit = units.get(f"{name}[].{column}", "")
            table.add_column(f"{column} [{unit}]" if unit else column, justify="right")
        for row in rows:
            flat = dict(_scalars(row))
            table.add_row(*(_text(flat.get(c)) for c in columns))
        tables.append(table)
    return tables


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
