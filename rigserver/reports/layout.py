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


def split(table: Table, continued: str, width: float = COLUMN_MM) -> list[Table]:
    """``table`` as parts no wider than ``width`` (mm), each repeating the key columns
    (``table.keys``, else its name columns, else the first); the captions of the parts after
    the first say they continue it (``continued`` holds ``{caption}``), once: a table that
    is itself a continuation keeps its caption."""
    widths = column_widths(table)
    if sum(widths) <= width or len(widths) < 2:
        return [table]
    keys = table.keys or table.labels or 1
    keys = min(keys, len(widths) - 1)
    fixed = sum(widths[:keys])
    parts: list[list[int]] = [[]]
    used = fixed
    for i in range(keys, len(widths)):
        if parts[-1] and used + widths[i] > width:
            parts.append([])
            used = fixed
        parts[-1].append(i)
        used += widths[i]
    if len(parts) == 1:
        return [table]
    # a part of a table printed in parts already (the manual's 4.4) keeps its caption
    later = Markup(continued).format(caption="")
    again = str(table.caption).endswith(str(later))
    found = []
    for number, chosen in enumerate(parts):
        columns = [*range(keys), *chosen]
        found.append(
            dataclasses.replace(
                table,
                caption=table.caption
                if number == 0 or again
                else Markup(continued).format(caption=table.caption),
                header=[table.header[i] for i in columns],
                rows=[[row[i] for i in columns if i < len(row)] for row in table.rows],
                note=table.note if number == len(parts) - 1 else "",
                formulas=table.formulas if number == 0 else "",
            )
        )
    return found


def fit(report: Report, continued: str) -> Report:
    """``report`` with every table split to the column's width."""

    def blocks(section: Section) -> Section:
        out: list[object] = []
        for block in section.blocks:
            out.extend(split(block, continued) if isinstance(block, Table) else [block])
        return dataclasses.replace(section, blocks=out)  # type: ignore[arg-type]

    return dataclasses.replace(report, sections=[blocks(s) for s in report.sections])


__all__: Sequence[str] = ["COLUMN_MM", "column_widths", "fit", "split", "text_mm"]
