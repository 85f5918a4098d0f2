"""A run's results printed for a person at the lab PC (rich tables): the results with their
declared labels, in the display units (:mod:`schemas.labels`). ``rigclient import`` prints
them once the run is finished; ``rigsim`` prints the same tables."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from rich.table import Table

from schemas import labelled
from schemas.digits import count, result_places, stated_uncertainty
from schemas.labels import Label, Part, plain_symbol
from schemas.stands import StandKind, theory_outside
from schemas.units import UNITS


def _shown(label: Label, value: Any, stored: str, uncertainty: float | None = None) -> str:
    """A result as its label declares it (display unit, digits, 0 below its resolution),
    a count whole, a percentage to 0.1, a value with an uncertainty to its place
    (:func:`schemas.digits.result_places`, GUM 7.2.6)."""
    if value is None:
        return ""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return str(value)
    places = result_places(label, value, stored, uncertainty)
    if places is None:
        return f"{label.shown(value, stored):.{label.digits}g}"
    if label.count:
        return str(count(label.displayed(value, stored)))
    return f"{round(label.noiseless(value, stored), places):.{max(places, 0)}f}"


def _unit(label: Label) -> str:
    return "" if label.unit == "1" else UNITS[label.unit].symbol.replace("um", "µm")


def results_tables(results: Mapping[str, Any], width: int = 100) -> list[Table]:
    """The single results in the declared order with their labels, in the display units
    (:mod:`schemas.labels`: µm, mg, mm³), then one table per per-row table (steps, ...),
    printed in parts of at most ``width`` characters, each part led by the table's first
    column (the load of a step), as the report splits its wide tables."""
    kind = StandKind(results["stand"])
    main = Table(title=f"results ({kind.value})")
    main.add_column("quantity")
    main.add_column("symbol")
    main.add_column("value", justify="right")
    main.add_column("unit")
    outside = theory_outside(kind, results.get("values", {}))
    scalars = labelled.scalars(kind, results)
    values = {e.path: e.value for e in scalars}
    for e in scalars:
        value = _shown(e.label, e.value, e.stored, stated_uncertainty(e.path, values))
        if outside and e.label.part is Part.THEORY and isinstance(e.value, int | float):
            value += " (theory outside its range)"
        main.add_row(_name(e.label), plain_symbol(e.label.symbol), value, _unit(e.label))
    tables = [main]
    for found in labelled.row_tables(kind, results):
        heads = []
        for c in found.columns:
            unit = _unit(c.label)
            head = plain_symbol(c.symbol) or c.label.text
            heads.append(f"{head} [{unit}]" if unit else head)
        cells = [
            [_shown(c.label, cell, c.stored) for c, cell in zip(found.columns, row, strict=True)]
            for row in found.rows
        ]
        parts = _parts(
            [max([len(h)] + [len(r[i]) for r in cells]) for i, h in enumerate(heads)], width
        )
        for number, part in enumerate(parts, 1):
            title = found.table.caption
            if len(parts) > 1:
                title += f" ({number}/{len(parts)})"
            table = Table(title=title)
            for i in part:
                table.add_column(heads[i], justify="right")
            for row in cells:
                table.add_row(*(row[i] for i in part))
            tables.append(table)
    return tables


def result_notes(results: Mapping[str, Any]) -> list[str]:
    """The analysis' notes of a run's results, each a line: what a result rests on (a
    distance from the planned speed, a default of the stand's) and what departs from the
    method."""
    notes = results.get("values", {}).get("notes", [])
    return [f"note: {note}" for note in notes if isinstance(note, str)]


def _parts(widths: list[int], width: int) -> list[list[int]]:
    """The columns (by index) of each part of a table whose columns need ``widths``
    characters: as many as fit in ``width`` (3 characters of rule and padding each), the
    first column repeated at the head of every part."""
    parts: list[list[int]] = []
    part = [0]
    used = widths[0] + 4
    for i in range(1, len(widths)):
        if len(part) > 1 and used + widths[i] + 3 > width:
            parts.append(part)
            part, used = [0], widths[0] + 4
        part.append(i)
        used += widths[i] + 3
    parts.append(part)
    return parts


def quantity(label: Label, value: Any, stored: str) -> str:
    """A result on one line as a person reads it: the manual's symbol (else its name), the
    value in the display unit with the label's digits, and the unit (``Ra = 0.8 µm``)."""
    unit = _unit(label)
    name = plain_symbol(label.symbol) or label.text
    return f"{name} = {_shown(label, value, stored)}" + (f" {unit}" if unit else "")


def _name(label: Label) -> str:
    return f"{label.text} ({label.equation})" if label.equation else label.text
