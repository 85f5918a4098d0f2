"""One symbol per quantity per report and per language: every stand's report (and series
report) is walked as a reader sees it, and fails when one symbol stands for two descriptions,
one description carries two symbols, a row or a column header repeats within a table, raw
markup (``_``, ``^``, braces) is printed, or an English report carries Cyrillic symbols."""

from __future__ import annotations

import re
from collections import defaultdict

import pytest

from rigserver.reports.i18n import LANGS, Lang, Messages
from schemas.stands import StandKind
from tests.reports.rendered import run_report, series_report
from tests.reports.simulated import HtmlTable, tables

CASES = [(kind, lang) for kind in StandKind for lang in LANGS]


def _columns(table: HtmlTable, lang: Lang) -> tuple[int, int] | None:
    """The columns of the quantity's words and of its symbol, where a table has both."""
    t = Messages(lang)
    head = [h.strip() for h in table.header]
    if t("col.quantity") in head and t("col.symbol") in head:
        return head.index(t("col.quantity")), head.index(t("col.symbol"))
    return None


#: The formula printed under the first row citing it (rigserver/reports/equations.py): not
#: part of the quantity's description.
_FORMULA = re.compile(r'<br><span class="formula">.*?</span>(?=<br>|</(?!span))', flags=re.S)


def _visible(html: str) -> str:
    html = re.sub(r"<(svg|style|script)\b.*?</\1>", " ", html, flags=re.S)
    return re.sub(r"<[^>]+>", " ", html)


@pytest.mark.parametrize(("kind", "lang"), CASES)
def test_one_symbol_per_quantity(kind: StandKind, lang: Lang) -> None:
    html = _FORMULA.sub("", run_report(kind, lang).html)
    meaning: dict[str, set[str]] = defaultdict(set)
    symbol: dict[str, set[str]] = defaultdict(set)
    for table in tables(html):
        found = _columns(table, lang)
        if found is None:
            continue
        words, sym = found
        for row in table.rows:
            if len(row) > max(words, sym) and row[sym].strip():
                meaning[row[sym].strip()].add(row[words].strip())
                symbol[row[words].strip()].add(row[sym].strip())
    assert meaning, "no table of quantities and symbols"
    twice = {s: sorted(d) for s, d in meaning.items() if len(d) > 1}
    assert not twice, f"one symbol, two meanings: {twice}"
    two = {d: sorted(s) for d, s in symbol.items() if len(s) > 1}
    assert not two, f"one quantity, two symbols: {two}"


@pytest.mark.parametrize(("kind", "lang"), CASES)
@pytest.mark.parametrize("which", ["run", "series"])
def test_no_row_or_header_repeats(kind: StandKind, lang: Lang, which: str) -> None:
    html = (run_report if which == "run" else series_report)(kind, lang).html
    for table in tables(html):
        heads = [h for h in table.header if h.strip()]
        assert len(heads) == len(set(heads)), f"{table.caption!r}: header repeats: {heads}"
        rows = [tuple(r) for r in table.rows if any(c.strip() for c in r)]
        repeated = {r for r in rows if rows.count(r) > 1}
        assert not repeated, f"{table.caption!r}: rows repeat: {sorted(repeated)}"


@pytest.mark.parametrize(("kind", "lang"), CASES)
@pytest.mark.parametrize("which", ["run", "series"])
def test_symbols_are_scripts_not_markup(kind: StandKind, lang: Lang, which: str) -> None:
    html = (run_report if which == "run" else series_report)(kind, lang).html
    text = _visible(html)
    raw = sorted(set(re.findall(r"\S*[_^{}]\S*", text)))
    assert not raw, f"raw symbol markup printed: {raw}"
    if lang == "en":
        cyrillic = sorted(set(re.findall(r"\S*[А-Яа-яЁё]\S*", text)))
        assert not cyrillic, f"Cyrillic on an English page: {cyrillic}"
