"""Every stand's report and series report, rendered once per language from simulated runs
and laid out by WeasyPrint: shared by the layout, symbol and figure tests.

Generic over :class:`schemas.stands.StandKind`: a new stand's simulator, analysis and report
module are covered by these tests as soon as they exist.
"""

from __future__ import annotations

import shutil
import subprocess
import unicodedata
from collections.abc import Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from functools import lru_cache
from typing import Any

from matplotlib.figure import Figure

from rigserver.analysis.series import Member, series_statistics
from rigserver.reports import plots
from rigserver.reports.i18n import Lang
from rigserver.reports.run_report import build_report, render_report
from rigserver.reports.series_report import render_series_report, series_context
from schemas.series import Series, SeriesPurpose
from schemas.stands import StandKind
from tests.reports.simulated import MADE, Simulated, simulated

#: The seeds of the three runs of a series: two specimens, and the first run's readings
#: handed in twice (a copy, as a teaching lab sees it: the report flags identical data).
SERIES_SEEDS = (7, 8, 7)
POPPLER = shutil.which("pdftotext")


@dataclass(frozen=True)
class Box:
    """A laid-out box that leaves the page's content area, in pt."""

    page: int
    tag: str
    kind: str
    text: str
    right: float
    bottom: float


@dataclass(frozen=True)
class Rendered:
    """A report: its HTML, the PDF made from it, the boxes outside the page, the PDF's text."""

    name: str
    html: str
    pdf: bytes
    pages: int
    outside: list[Box]
    figures: list[Figure] = field(default_factory=list)
    stranded: list[str] = field(default_factory=list)

    @property
    def text(self) -> str:
        return pdf_text(self.pdf)


def _outside(document: Any) -> list[Box]:
    """Every box of the laid-out pages that extends beyond its page's content area (the
    page-number margin boxes are outside it by design)."""
    from weasyprint.formatting_structure.boxes import MarginBox  # type: ignore[import-untyped]

    found: list[Box] = []
    for number, page in enumerate(document.pages, start=1):
        box = page._page_box
        left, top = box.content_box_x(), box.content_box_y()
        right, bottom = left + box.width, top + box.height
        roots = [c for c in box.children if not isinstance(c, MarginBox)]
        for root in roots:
            for d in root.descendants():
                if not hasattr(d, "border_width") or d.width is None:
                    continue
                if d.element_tag in ("html", "body"):  # containers: their contents are checked
                    continue
                x1 = d.border_box_x() + d.border_width()
                y1 = d.border_box_y() + d.border_height()
                if x1 > right + 0.5 or y1 > bottom + 0.5 or d.border_box_x() < left - 0.5:
                    text = getattr(d, "text", "") or ""
                    found.append(
                        Box(
                            number,
                            str(d.element_tag),
                            type(d).__name__,
                            text[:60],
                            x1 - right,
                            y1 - bottom,
                        )
                    )
    return found


#: A table split across pages keeps at least this many of its body rows on each.
ROWS_KEPT = 3
#: The last page holds at least this many lines of text (the footer's not counted).
LAST_LINES = 5
#: What leads into the content after it: a heading, a table's caption or its formulas.
LEADS = {"h1", "h2", "h3"}
LEAD_CLASSES = {"caption", "formulas"}


def _stranded(document: Any) -> list[str]:
    """Awkward page breaks: a heading, a table's caption or formulas as the last line of a
    page (its content on the next), a figure's caption as the first (its plot on the one
    before), a page of nothing but the footer ("Made by rig ..."), a table that goes on to
    another page leaving fewer than :data:`ROWS_KEPT` rows of its body on one, a last page
    of fewer than :data:`LAST_LINES` lines."""
    from weasyprint.formatting_structure.boxes import (
        LineBox,
        MarginBox,
        TableBox,
        TableRowGroupBox,
    )

    found: list[str] = []
    rows: dict[int, dict[int, int]] = {}  # table element -> page -> its body rows there
    names: dict[int, str] = {}
    for number, page in enumerate(document.pages, start=1):
        for table in page._page_box.descendants():
            if isinstance(table, TableBox) and table.element is not None:
                body = [g for g in table.children if isinstance(g, TableRowGroupBox)]
                count = sum(len(g.children) for g in body if not g.is_header)
                key = id(table.element)
                names[key] = table.element.get("id") or "a table"
                by_page = rows.setdefault(key, {})
                by_page[number] = by_page.get(number, 0) + count
        roots = [c for c in page._page_box.children if not isinstance(c, MarginBox)]
        boxes = [d for root in roots for d in root.descendants()]
        lines = [d for d in boxes if isinstance(d, LineBox)]
        if not lines:
            continue
        last, first = lines[-1], lines[0]
        classes = set((last.element.get("class") or "").split()) if last.element else set()
        # the room left for the students on paper follows a heading without a line of text
        room = any(_classes(d) & {"space"} for d in boxes[boxes.index(last) :])
        lead = last.element_tag in LEADS or (last.element_tag == "p" and classes & LEAD_CLASSES)
        if lead and not room:
            found.append(f"page {number} ends with <{last.element_tag}> {_line_text(last)!r}")
        if all(line.element_tag == "footer" for line in lines):
            found.append(f"page {number} holds only the footer {_line_text(first)!r}")
        if first.element_tag == "figcaption" and number > 1:
            found.append(f"page {number} starts with a figure's caption {_line_text(first)!r}")
    for key, by_page in rows.items():
        if len(by_page) > 1:
            for number, count in by_page.items():
                if count < ROWS_KEPT:
                    found.append(f"{names[key]} leaves {count} row(s) on page {number}")
    last = document.pages[-1]._page_box
    boxes = [d for c in last.children if not isinstance(c, MarginBox) for d in c.descendants()]
    text = sum(_lines(d) for d in boxes)
    if len(document.pages) > 1 and text < LAST_LINES:
        found.append(f"the last page holds {text} line(s) of text")
    return found


def _lines(box: Any) -> int:
    """The lines a box gives the page: a line of text (the footer's not), a ruled line or a
    frame's lines to write or draw in (a students' section), a plot (as :data:`LAST_LINES`)."""
    from weasyprint.formatting_structure.boxes import LineBox

    if isinstance(box, LineBox):  # a plot is a replaced box on a line of its own
        plot = any(str(d.element_tag).endswith(("svg", "img")) for d in box.descendants())
        return LAST_LINES if plot else int(box.element_tag != "footer")
    classes = _classes(box)
    if "rule" in classes:
        return 1
    return LAST_LINES if "frame" in classes else 0


def _classes(box: Any) -> set[str]:
    element = getattr(box, "element", None)
    return set((element.get("class") or "").split()) if element is not None else set()


def _line_text(line: Any) -> str:
    return "".join(getattr(d, "text", "") or "" for d in line.descendants())[:60]


def laid_out(name: str, html: str, figures: list[Figure]) -> Rendered:
    from weasyprint import HTML

    document = HTML(string=html).render()
    pdf: bytes = document.write_pdf()
    pages = len(document.pages)
    return Rendered(name, html, pdf, pages, _outside(document), figures, _stranded(document))


@lru_cache(maxsize=64)
def pdf_text(pdf: bytes) -> str:
    """The PDF's text in content-stream order (poppler's pdftotext -raw)."""
    if POPPLER is None:
        raise RuntimeError("poppler-utils missing (pdftotext): apt-get install poppler-utils")
    done = subprocess.run(
        [POPPLER, "-raw", "-enc", "UTF-8", "-", "-"], input=pdf, capture_output=True, check=True
    )
    return done.stdout.decode()


def squeezed(text: str) -> str:
    """Text compared as read: Unicode-normalised, without whitespace (lines wrap in the PDF)."""
    text = unicodedata.normalize("NFKC", text).replace("−", "-")
    return "".join(text.split())


def run_html(kind: StandKind, lang: Lang) -> str:
    return report_html(simulated(kind), lang)


def report_html(s: Simulated, lang: Lang, sketches: Mapping[int, str] | None = None) -> str:
    """The report of an analysed run, as the service renders it (with the students' uploaded
    ``sketches``, data URIs by item, if any)."""
    return render_report(
        build_report(
            run=s.run,
            stand=s.stand,
            values=s.result.payload["values"],
            readings=s.readings,
            lang=lang,
            made=MADE,
            sketches=sketches or {},
        )
    )


@lru_cache
def run_report(kind: StandKind, lang: Lang) -> Rendered:
    """A stand's run report, laid out, with the figures it drew."""
    with plots.recording() as drawn:
        html = run_html(kind, lang)
    return laid_out(f"{kind.value} report ({lang})", html, drawn)


def series_runs(kind: StandKind) -> list[Simulated]:
    return [simulated(kind, seed) for seed in SERIES_SEEDS]


def series_context_of(kind: StandKind, lang: Lang) -> dict[str, Any]:
    """The series report's context for three simulated runs of ``kind`` (repeats)."""
    runs = series_runs(kind)
    members = [
        Member(
            run=r.run.model_copy(update={"id": f"20261125T120000Z-0000000{i}"}),
            level=None,
            values=r.result.payload["values"],
        )
        for i, r in enumerate(runs)
    ]
    series = Series(
        id="s-00000000000b",
        name="repeats",
        purpose=SeriesPurpose.REPEATABILITY,
        created=datetime(2026, 11, 25, 12, 0, tzinfo=UTC),
    )
    detail = series_statistics(series, members, [])
    readings = {m.run.id: r.readings for m, r in zip(members, runs, strict=True)}
    values = {m.run.id: m.values for m in members}
    return series_context(detail, values=values, readings=readings, lang=lang)


@lru_cache
def series_report(kind: StandKind, lang: Lang) -> Rendered:
    """A stand's series report (three simulated runs), laid out, with the figures it drew."""
    with plots.recording() as drawn:
        html = render_series_report(series_context_of(kind, lang), made=MADE)
    return laid_out(f"{kind.value} series report ({lang})", html, drawn)
