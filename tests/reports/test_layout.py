"""Every report fits A4 portrait in both languages with nothing cut: no laid-out box leaves
the page's content area (WeasyPrint's layout tree), and every table cell of the HTML report
is in the PDF's text. Each stand's run report and series report (three simulated runs) is
rendered once per language and shared by the assertions (``tests/reports/rendered.py``)."""

from __future__ import annotations

import pytest

from rigserver.reports.document import Table
from rigserver.reports.i18n import LANGS, Lang
from rigserver.reports.layout import split
from schemas.stands import StandKind
from tests.reports.rendered import Rendered, run_report, series_report, squeezed
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


def test_a_table_in_parts_says_continued_once() -> None:
    # thirty columns of 8-digit numbers are far wider than the A4 column
    head = [f"x{i}" for i in range(30)]
    rows = [[f"{i}.1234567" for i in range(30)]]
    continued = "{caption} (continued)"
    fresh = split(Table(caption="Table 4.4", header=head, rows=rows), continued)
    assert len(fresh) > 1
    assert [str(p.caption) for p in fresh] == ["Table 4.4"] + ["Table 4.4 (continued)"] * (
        len(fresh) - 1
    )
    # a part the lab prints as a continuation already (the manual's table 4.4) keeps its caption
    again = split(Table(caption="Table 4.4 (continued)", header=head, rows=rows), continued)
    assert {str(p.caption) for p in again} == {"Table 4.4 (continued)"}
