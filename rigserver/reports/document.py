"""A report as data: sections of tables, figures and paragraphs, rendered by one template.

The stand modules build these; ``templates/report.html`` prints them, the same for the
browser and for the PDF. Cell text is escaped when rendered; headers and captions may hold
the markup of :func:`rigserver.reports.formatting.html_symbol`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import ClassVar

from markupsafe import Markup

Text = str | Markup


@dataclass(frozen=True, slots=True)
class Table:
    """A table: a caption, one header row, rows of printed cells.

    The first ``labels`` columns hold names (left-aligned, wrapped), the others numbers.
    A table wider than the page is printed in parts (:mod:`rigserver.reports.layout`), each
    repeating the first ``keys`` columns (default: the name columns, else the first).
    ``formulas`` is printed under the caption of the first part (the formulas its caption,
    header or values cite first, :func:`rigserver.reports.equations.beside`). Tables in a
    row with the same ``part_of`` are the parts of one printed table (the manual's 4.4 in
    three), their captions numbered ``(part 2 of 3)``.
    """

    kind: ClassVar[str] = "table"
    caption: Text
    header: Sequence[Text]
    rows: Sequence[Sequence[Text]]
    labels: int = 0
    note: Text = ""
    keys: int = 0
    formulas: Text = ""
    part_of: str = ""


@dataclass(frozen=True, slots=True)
class Figure:
    """An inline SVG plot with its caption."""

    kind: ClassVar[str] = "figure"
    caption: Text
    svg: str


@dataclass(frozen=True, slots=True)
class Paragraph:
    kind: ClassVar[str] = "paragraph"
    text: Text


@dataclass(frozen=True, slots=True)
class Items:
    """A bulleted list (conclusions, what is still missing)."""

    kind: ClassVar[str] = "items"
    items: Sequence[Text]


@dataclass(frozen=True, slots=True)
class Space:
    """The students' own part of a report: what they wrote (markup of paragraphs) or the
    sketch they uploaded (``image``, a ``data:`` URI, fitted within the page), else room for
    it on paper: ruled lines to write on, or a frame to draw in (a sketch, a scheme),
    ``lines`` lines high."""

    kind: ClassVar[str] = "space"
    text: Text = ""
    frame: bool = False
    lines: int = 6
    image: str = ""


Block = Table | Figure | Paragraph | Items | Space


@dataclass(frozen=True, slots=True)
class Section:
    title: Text
    blocks: Sequence[Block] = field(default_factory=tuple)


@dataclass(frozen=True, slots=True)
class Report:
    """A whole report: the heading, the run's particulars and the sections."""

    lang: str
    title: str
    subtitle: str
    aim_label: str
    aim: str
    particulars: Sequence[tuple[str, str]]
    sections: Sequence[Section]
    footer: str
    tasks_label: str = ""
    tasks: Sequence[str] = ()
