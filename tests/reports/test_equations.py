"""The formula beside each computed quantity where a report first cites its equation number;
later citations give the number only (issue 27, item 8)."""

from __future__ import annotations

import re
from functools import lru_cache

import pytest

from rigserver.reports.equations import EQUATIONS, citations, cited, formula
from rigserver.reports.i18n import LANGS, Lang, Messages
from schemas.stands import StandKind
from tests.reports.rendered import run_html

CASES = [(kind, lang) for kind in StandKind for lang in LANGS]
#: The places of a report a reader takes in turn: a table with its caption and note, a
#: figure, a paragraph, an item of a list, a section's title, the run's particulars.
_PLACES = re.compile(
    r'<div class="table.*?</div>|<figure>.*?</figure>|<li>.*?</li>|<p>.*?</p>|<h2>.*?</h2>'
    r'|<table class="particulars">.*?</table>',
    flags=re.S,
)
#: A formula's span: it holds the spans of its unbreakable parts, and is followed by a line
#: break or the end of the element that holds it.
_FORMULA = re.compile(r'<span class="formula">(.*?)</span>(?=<br>|</(?!span))', flags=re.S)
_SVG = re.compile(r"<svg\b.*?</svg>", flags=re.S)
_TAGS = re.compile(r"<[^>]+>")


@lru_cache
def html(kind: StandKind, lang: Lang) -> str:
    return _SVG.sub("", run_html(kind, lang))


def words(place: str) -> str:
    """What a place says in its own words: without the formulas printed in it."""
    return _TAGS.sub("", _FORMULA.sub("", place))


def test_only_citations_in_parentheses_count() -> None:
    text = (
        "f_e (4.16) and S_1 (4.21, E9); table values 4.13 and 2.8; (4.1)-(4.10); (1.3); "
        "k = (2.1 ± 0.1)·10⁻⁶; (table 3.2, E3); (Ra 0.4–3.2 µm); (item 10, (1.20))"
    )
    assert citations(text) == ["4.16", "4.21", "4.1", "4.10", "1.3", "1.20"]
    assert cited(text) == ["1.3", "1.20", "4.1", "4.10", "4.16", "4.21"]  # the manual's order


@pytest.mark.parametrize("lang", LANGS)
def test_every_formula_prints_scripts_not_markup(lang: Lang) -> None:
    t = Messages(lang)
    for number in EQUATIONS:
        shown = str(formula(t, number))
        assert not re.search(r"[_^{}]", _TAGS.sub("", shown)), f"({number}) {shown}"
        # a power after a subscript is a superscript (r_1^2), not part of the subscript
        assert not re.search(r"<sub>[^<]*[²³]", shown), f"({number}) {shown}"


@pytest.mark.parametrize(("kind", "lang"), CASES)
def test_the_formula_is_printed_where_its_number_is_first_cited(
    kind: StandKind, lang: Lang
) -> None:
    page = html(kind, lang)
    places = _PLACES.findall(page)
    cited_here = citations(" ".join(words(p) for p in places))
    assert not [n for n in cited_here if n not in EQUATIONS], "a cited number has no formula"
    printed = [f for p in places for f in _FORMULA.findall(p)]
    t = Messages(lang)
    for number in cited_here:
        shown = str(formula(t, number))
        first = next(p for p in places if number in citations(words(p)))
        assert shown in first, f"({number}) {shown} is not at its first citation: {first[:300]}"
        once = [f for f in printed if f in (shown, f"({number}) {shown}")]
        assert len(once) == 1, f"({number}) printed {len(once)} times"
    assert len(printed) == len(cited_here), "a formula printed that no place cites"


def test_the_formula_stands_under_the_quantity_in_the_reports_language() -> None:
    en, ru = html(StandKind.MTOS, "en"), html(StandKind.MTOS, "ru")
    nobreak = '<span class="formula"><span class="nobreak">{}</span></span>'
    assert nobreak.format("f<sub>e</sub> = F<sub>fr</sub>/N") in en
    assert nobreak.format("f<sub>э</sub> = F<sub>тр</sub>/N") in ru
    # under the first row that cites (4.16) only; the later rows give the number alone
    rows = re.findall(r"<td class=\"label\">([^<]*\(4\.16\)[^<]*)(<br>)?", en)
    assert rows[0][1] == "<br>" and all(not br for _, br in rows[1:]) and len(rows) > 1
    profilometer = html(StandKind.PROFILOMETER, "ru")
    ra = '<span class="nobreak">R<sub>a</sub> = 4,3·Δ<sup>1/2</sup></span>, '
    assert f'<span class="formula">{ra}<span class="nobreak">мкм</span></span>' in profilometer
    smts2 = html(StandKind.SMTS2, "en")
    # (2.9) cited first by the pin's mass before the test, in the input data
    assert re.search(
        r"m1, pin mass before the test \(2\.9\)<br><span class=\"formula\">"
        r"<span class=\"nobreak\">Δm = m<sub>1</sub> - m<sub>2</sub></span></span>",
        smts2,
    )


@pytest.mark.parametrize("lang", ["en", "ru"])
def test_a_formula_breaks_only_between_its_top_level_parts(lang: str) -> None:
    # (2.1) once broke inside its exponent: "(1+βt" at a line's end, ")/(1−β)" on the next
    t = Messages(lang)  # type: ignore[arg-type]
    for number in EQUATIONS:
        shown = str(formula(t, number))
        kept = re.findall(
            r'<span class="nobreak">(.*?)</span>(?=<span class="nobreak">|, | · |$)', shown
        )
        between = re.sub(
            r'<span class="nobreak">.*?</span>(?=<span class="nobreak">|, | · |$)', "", shown
        )
        assert set(between.replace(" · ", "").replace(", ", "")) == set(), (number, between)
        for part in kept:
            plain = re.sub(r"<[^>]+>", "", part)
            assert plain.count("(") == plain.count(")"), (number, plain)
    long = str(formula(t, "2.1"))
    assert long.count('class="nobreak"') >= 8  # its factors may go to the next line
