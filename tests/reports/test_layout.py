"""Every report fits A4 portrait in both languages with nothing cut: no laid-out box leaves
the page's content area (WeasyPrint's layout tree), and every table cell of the HTML report
is in the PDF's text. Each stand's run report and series report (three simulated runs) is
rendered once per language and shared by the assertions (``tests/reports/rendered.py``)."""

from __future__ import annotations

import re
from dataclasses import replace

import pytest

from rigserver.reports.document import Table
from rigserver.reports.i18n import LANGS, Lang
from rigserver.reports.layout import numbered, split
from schemas.stands import StandKind
from tests.reports.rendered import Rendered, laid_out, run_report, series_report, squeezed
from tests.reports.simulated import tables

REPORTS = {"run": run_report, "series": series_report}


def cases() -> list[tuple[str, StandKind, Lang]]:
    return [(which, kind, lang) for which in REPORTS for kind in StandKind for lang in LANGS]


def rendered(which: str, kind: StandKind, lang: Lang) -> Rendered:
    return REPORTS[which](kind, lang)


@pytest.mark.parametrize(("which", "kind", "lang"), cases())
def test_no_box_leaves_the_page(which: str, kind: StandKind, lang: Lang) -> None:
    report = rendered(which, kind, lang)
    assert report.pages >= 1
    assert not report.outside, f"{report.name}: boxes outside the page:\n" + "\n".join(
        f"  page {b.page}: <{b.tag}> {b.kind} {b.text!r} right +{b.right:.1f} pt, "
        f"bottom +{b.bottom:.1f} pt"
        for b in report.outside[:20]
    )


@pytest.mark.parametrize(("which", "kind", "lang"), cases())
def test_no_heading_ends_a_page_and_no_caption_leaves_its_figure(
    which: str, kind: StandKind, lang: Lang
) -> None:
    report = rendered(which, kind, lang)
    assert not report.stranded, f"{report.name}: " + "; ".join(report.stranded)


@pytest.mark.parametrize(("rows", "left"), [(11, 1), (12, 2), (13, 0), (10, 0)])
def test_a_table_leaving_fewer_than_three_rows_on_a_page_is_found(rows: int, left: int) -> None:
    # pages whose content area is 100 mm high (120 mm less two 10 mm margins) and rows
    # 10 mm high hold 10 rows each: the 11th and 12th rows go on to page 2, too few there;
    # 13 rows leave three; a text of ten lines or more follows on page 2 (not a last page of
    # fewer than five lines)
    html = (
        "<style>@page { size: 100mm 120mm; margin: 10mm; } body { margin: 0; }"
        " table { border-collapse: collapse; } td { height: 10mm; padding: 0; border: 0;"
        " box-sizing: border-box; }</style>"
        '<table id="t">' + "<tr><td>x</td></tr>" * rows + "</table>" + "<p>line</p>" * 5
    )
    found = laid_out("synthetic", html, []).stranded
    assert found == ([f"t leaves {left} row(s) on page 2"] if left else []), found


def test_a_last_page_of_fewer_than_five_lines_is_found() -> None:
    # ten lines of 10 mm fill a page; two more make a last page of two lines
    html = (
        "<style>@page { size: 100mm 120mm; margin: 10mm; } body { margin: 0; }"
        " p { height: 10mm; margin: 0; }</style>" + "<p>line</p>" * 12
    )
    assert laid_out("synthetic", html, []).stranded == ["the last page holds 2 line(s) of text"]


@pytest.mark.parametrize(("which", "kind", "lang"), cases())
def test_every_table_cell_is_in_the_pdf(which: str, kind: StandKind, lang: Lang) -> None:
    report = rendered(which, kind, lang)
    text = squeezed(report.text)
    cells = [
        (table.caption, cell)
        for table in tables(report.html)
        for row in [table.header, *table.rows]
        for cell in row
        if squeezed(cell)
    ]
    assert cells
    missing = [(caption, cell) for caption, cell in cells if squeezed(cell) not in text]
    assert not missing, (
        f"{report.name}: {len(missing)} of {len(cells)} table cells are not in the PDF:\n"
        + "\n".join(f"  {caption[:50]!r}: {cell!r}" for caption, cell in missing[:20])
    )


def test_a_table_in_parts_is_numbered_and_evenly_cut() -> None:
    # seventeen columns of 8-digit numbers: two parts, the greedy cut would leave one column
    head = [f"x{i}" for i in range(17)]
    rows = [[f"{i}.1234567" for i in range(17)]]
    parts = split(Table(caption="Table 4.4", header=head, rows=rows))
    assert len(parts) == 2
    widths = [len(p.header) - 1 for p in parts]  # less the key column each repeats
    assert sum(widths) == 16 and max(widths) - min(widths) <= 1, widths
    # the pieces a lab prints as one table number on with the parts the layout cut
    theory = Table(caption="Table 4.4. Theory", header=head[:3], rows=[rows[0][:3]])
    pieces = [*parts, replace(theory, part_of="Table 4.4")]
    captions = [str(b.caption) for b in numbered(pieces, "{caption} (part {part} of {parts})")]
    assert captions == [
        "Table 4.4 (part 1 of 3)",
        "Table 4.4 (part 2 of 3)",
        "Table 4.4. Theory (part 3 of 3)",
    ]
    # a table in one part keeps its caption
    alone = numbered([theory, *parts[:1]], "{caption} (part {part} of {parts})")
    assert [str(b.caption) for b in alone] == ["Table 4.4. Theory", "Table 4.4"]


@pytest.mark.parametrize("kind", list(StandKind))
@pytest.mark.parametrize("lang", LANGS)
def test_no_caption_says_continued_or_end(kind: StandKind, lang: Lang) -> None:
    """A table in parts reads "(part 2 of 3)", never "…, end. … (continued)"."""
    for table in tables(run_report(kind, lang).html):
        assert not re.search(r"continued|продолжение|, end\b|Окончание", table.caption), (
            table.caption
        )
