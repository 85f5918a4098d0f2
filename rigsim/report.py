"""Results and truth printed for a person at the lab PC (rich tables): the results with
their declared labels, in the display units (:mod:`rigclient.summary`), and the
simulator's truth."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import fields, is_dataclass
from typing import Any

import numpy as np
from rich.console import Console
from rich.table import Table

from rigclient.summary import results_tables


def _text(value: Any) -> str:
    if isinstance(value, float) and not isinstance(value, bool):
        return f"{value:.5g}"
    return str(value)


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
    for table in results_tables(results, console.width):
        console.print(table)
    if truth is not None:
        for table in truth_tables(truth):
            console.print(table)
