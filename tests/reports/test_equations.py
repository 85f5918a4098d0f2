"""The list of the formulas a report uses: what it cites by the manual's numbers, in order."""

from __future__ import annotations

from rigserver.reports.equations import EQUATIONS, cited
from schemas.stands import StandKind
from tests.reports.test_report import report


def test_only_citations_in_parentheses_count_in_the_manuals_order() -> None:
    text = "f_e (4.16) and S_1 (4.21, E9); table values 4.13 and 2.8; (4.1)-(4.10); (1.3)"
    assert cited(text) == ["1.3", "4.10", "4.16", "4.21"]  # 4.1 has no formula listed


def test_every_report_lists_the_formulas_it_cites_in_its_language() -> None:
    en, ru = report(StandKind.MTOS, "en"), report(StandKind.MTOS, "ru")
    assert "<li>(4.16) f<sub>e</sub> = F<sub>fr</sub>/N</li>" in en
    assert "<li>(4.16) f<sub>э</sub> = F<sub>тр</sub>/N</li>" in ru  # the symbols translated
    profilometer = report(StandKind.PROFILOMETER, "ru")
    assert "<li>(1.10) R<sub>a</sub> = 4,3·Δ<sup>1/2</sup>, мкм</li>" in profilometer
    assert all(number in EQUATIONS for number in ("1.20", "2.16", "4.5"))
