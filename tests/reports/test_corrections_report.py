"""The report's section "Corrections": every correction printed (row, quantity, value as
typed and as corrected, unit, reason, who and when) in both languages, on A4 with nothing
cut, the tables above as corrected."""

from __future__ import annotations

import pytest

from rigserver.reports.i18n import LANGS, Lang
from rigserver.reports.run_report import build_report, render_report
from rigserver.storage.corrections import CorrectedReadings
from schemas.corrections import Correction
from schemas.stands import StandKind
from tests.reports.rendered import MADE, laid_out, pdf_text, squeezed
from tests.reports.simulated import simulated

#: The longest reason the API takes, in words a student writes
REASON = ("The manometer was read from the wrong scale; the instructor checked it. " * 8)[:500]


def _corrections() -> list[Correction]:
    s = simulated(StandKind.SLIDE_BEARING)
    typed = s.readings.read("rows", ["p3"])["p3"]
    return [
        Correction(
            n=1,
            group="rows",
            row=2,
            channel="p3",
            was=float(typed[2]),
            now=1.25,
            unit="at",
            reason="12.5 typed for 1.25",
            by="slide-bearing PC",
            at=MADE,
        ),
        Correction(
            n=2,
            group="rows",
            row=2,
            channel="p3",
            was=1.25,
            now=1.3,
            unit="at",
            reason=REASON,
            by="slide-bearing PC",
            at=MADE,
        ),
        Correction(n=3, group="rows", row=5, channel=None, reason="typed twice", by="k", at=MADE),
    ]


@pytest.mark.parametrize("lang", LANGS)
def test_the_corrections_are_printed_on_a4_with_nothing_cut(lang: Lang) -> None:
    s = simulated(StandKind.SLIDE_BEARING)
    fixes = _corrections()
    run = s.run.model_copy(update={"corrections": 3, "corrected_after_finish": True})
    html = render_report(
        build_report(
            run=run,
            stand=s.stand,
            values=s.result.payload["values"],
            readings=CorrectedReadings(s.readings, fixes),
            lang=lang,
            made=MADE,
            corrections=fixes,
        )
    )
    report = laid_out(f"corrected slide-bearing report ({lang})", html, [])
    assert not report.outside, [(b.tag, b.text, b.right) for b in report.outside[:5]]
    text = squeezed(pdf_text(report.pdf))
    words = {
        "en": ("Corrections", "rowstruckout", "correctedafteritwasfinished"),
        "ru": ("Исправления", "строкавычеркнута", "исправленпослезавершения"),
    }[lang]
    for word in (*words, "12.5typedfor1.25", squeezed(REASON[:60])):
        assert word in text, word
    # the typed value and both corrections: was and now, in the report's decimal sign
    sign = "," if lang == "ru" else "."
    assert f"1{sign}25" in text and f"1{sign}3" in text
