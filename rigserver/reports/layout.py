"""Tables that fit the A4 column: a table wider than the page is split into parts, the way
the manual prints tables 4.1-4.3 and 4.4, each part repeating the table's key columns (the
names of the rows, the load of an MTOS step, the angle of a limb row).

The width of a column is estimated from its cells' text in the report's font (DejaVu Sans,
measured with the metrics matplotlib ships) at the table's size: numbers do not wrap, names
and headers wrap at spaces. ``tests/reports/test_layout.py`` lays every report out with
WeasyPrint and fails when any box leaves the page, so the estimate is checked, not trusted.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Sequence
from functools import lru_cache

from markupsafe import Markup

from rigserver.reports.document import Report, Section, Table, Text

#: The report's column (A4 less 14 mm margins each side), mm, with a reserve for the
#: estimate's error.
COLUMN_MM = 210.0 - 2 * 14.0 - 4.0
#: Table text size (pt) and the padding and borders of a cell (mm), as ``report.html``.
TABLE_PT = 8.0
CELL_MM = 2 * 0.35 * TABLE_PT * 25.4 / 72 + 0.4
#: A wrapped name column is given at most this many millimetres before the parts are cut.
NAME_MM = 60.0
_TAGS = re.compile(r"<[^>]+>")
_SCRIPTS = re.compile(r"<su[bp]>([^<]*)</su[bp]>")


@lru_cache(maxsize=1)
def _font() -> object:
    from matplotlib import font_manager
    from matplotlib.ft2font import FT2Font

    font = FT2Font(font_manager.findfont("DejaVu Sans"))
    font.set_size(TABLE_PT, 72)
    return font


@lru_cache(maxsize=4096)
def text_mm(text: str, size: float = TABLE_PT) -> float:
    """The width of ``text`` (plain) in DejaVu Sans at ``size`` pt, mm."""
    if not text:
        return 0.0
    font = _font()
    font.set_text(text, 0.0)  # type: ignore[attr-defined]
    width: float = font.get_width_height()[0] / 64.0  # type: ignore[attr-defined]
    return width / 72.0 * 25.4 * size / TABLE_PT


def plain(cell: Text) -> tuple[str, str]:
    """A cell's text as drawn, and its scripts apart (smaller): ``e<sub>x</sub>`` ->
    ``("e", "x")``."""
    if not isinstance(cell, Markup):
        return str(cell), ""
    html = str(cell)
    scripts = "".join(_SCRIPTS.findall(html))
    body = _SCRIPTS.sub("", html)
    return Markup(_TAGS.sub("", body)).unescape(), Markup(scripts).unescape()


def cell_mm(cell: Text, *, wraps: bool) -> float:
    """The width a cell needs: its whole text, or its longest word where it may wrap."""
    body, scripts = plain(cell)
    if wraps:
        words = body.split() or [""]
        width = max(text_mm(w) for w in words) + text_mm(scripts, 0.8 * TABLE_PT)
    else:
        width = text_mm(body) + text_mm(scripts, 0.8 * TABLE_PT)
    return width + CELL_MM


def column_widths(table: Table) -> list[float]:
    """Each column's estimated width, mm: the widest of its cells (names wrap, within
    :data:`NAME_MM`), or its header's longest word."""
    count = len(table.header)
    widths = [cell_mm(h, wraps=True) for h in table.header]
    for row in table.rows:
        for i, cell in enumerate(row[:count]):
            name = i < table.labels
            need = cell_mm(cell, wraps=name)
            if name:
                need = min(max(need, text_mm(plain(cell)[0]) + CELL_MM), NAME_MM)
            widths[i] = max(widths[i], need)
    return widths


def _parts(widths: Sequence[float], fixed: float, most: float) -> list[list[int]]:
    """The columns after the key columns in order, filled into parts no wider than ``most``
    (the first part holding a column too wide for ``most`` alone keeps it)."""
    parts: list[list[int]] = [[]]
    used = fixed
    for i, width in enumerate(widths):
        if parts[-1] and used + width > most:
            parts.append([])
            used = fixed
        parts[-1].append(i)
        used += width
    return parts


def split(table: Table, width: float = COLUMN_MM) -> list[Table]:
    """``table`` as parts no wider than ``width`` (mm), each repeating the key columns
    (``table.keys``, else its name columns, else the first). The parts are as few as the
    width allows and as even as they can be (no part left with a single column), and
    share ``part_of`` (the table's, else its caption): :func:`fit` numbers them."""
    widths = column_widths(table)
    if sum(widths) <= width or len(widths) < 2:
        return [table]
    keys = table.keys or table.labels or 1
    keys = min(keys, len(widths) - 1)
    fixed = sum(widths[:keys])
    rest = widths[keys:]
    count = len(_parts(rest, fixed, width))
    if count == 1:
        return [table]
    # the narrowest parts in as many: the least width at which the columns still fill
    # ``count`` parts (bisected; filling in order is optimal for a given width)
    low, high = fixed + max(rest), width
    while high - low > 0.5:
        middle = (low + high) / 2
        low, high = (middle, high) if len(_parts(rest, fixed, middle)) > count else (low, middle)
    parts = _parts(rest, fixed, high)
    part_of = table.part_of or str(table.caption)
    found = []
    for number, chosen in enumerate(parts):
        columns = [*range(keys), *(keys + i for i in chosen)]
        found.append(
            dataclasses.replace(
                table,
                header=[table.header[i] for i in columns],
                rows=[[row[i] for i in columns if i < len(row)] for row in table.rows],
                note=table.note if number == len(parts) - 1 else "",
                formulas=table.formulas if number == 0 else "",
                part_of=part_of,
            )
        )
    return found


def numbered(blocks: Sequence[object], part: str) -> list[object]:
    """``blocks`` with the captions of a table printed in parts numbered: the tables in a
    row that share ``part_of`` read ``… (part 2 of 3)`` (``part`` holds ``{caption}``,
    ``{part}`` and ``{parts}``)."""
    runs: list[list[object]] = []
    for block in blocks:
        key = block.part_of if isinstance(block, Table) else ""
        previous = runs[-1][-1] if runs else None
        if key and isinstance(previous, Table) and previous.part_of == key:
            runs[-1].append(block)
        else:
            runs.append([block])
    out: list[object] = []
    for run in runs:
        if len(run) == 1:
            out.extend(run)
            continue
        out.extend(
            dataclasses.replace(
                table,
                caption=Markup(part).format(caption=table.caption, part=n, parts=len(run)),
            )
            for n, table in enumerate(run, start=1)
            if isinstance(table, Table)
        )
    return out


def fit(report: Report, part: str) -> Report:
    """``report`` with every table split to the column's width, the parts of a table
    numbered (:func:`numbered`)."""

    def blocks(section: Section) -> Section:
        out: list[object] = []
        for block in section.blocks:
            out.extend(split(block) if isinstance(block, Table) else [block])
        return dataclasses.replace(section, blocks=numbered(out, part))  # type: ignore[arg-type]

    return dataclasses.replace(report, sections=[blocks(s) for s in report.sections])


__all__: Sequence[str] = ["COLUMN_MM", "column_widths", "fit", "numbered", "split", "text_mm"]
