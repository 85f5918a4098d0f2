"""One symbol per quantity per report and per language: every stand's report (and series
report) is walked as a reader sees it, and fails when one symbol stands for two descriptions,
one description carries two symbols, a row or a column header repeats within a table, raw
markup (``_``, ``^``, braces) is printed, or an English report carries Cyrillic symbols."""

from __future__ import annotations

import re
from collections import defaultdict

import pytest

from rigserver.reports.i18n import LANGS, UNIT_LABELS, Lang, Messages
from rigserver.reports.series_report import text as series_text
from schemas.stands import StandKind
from tests.reports.rendered import Rendered, run_report, series_report
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


#: A scale a plot's axis divides out, before its unit ("L, 10³ m").
_SCALE = re.compile(r"^10[⁰¹²³⁴⁵⁶⁷⁸⁹⁻]+\s*")
#: The symbol a configuration field's description begins with ("λc of ...", "h0, ...").
_LEADING = re.compile(r"(\S+?)(?:,| of | =)")
#: A printed value with its symbol in running text: "λc = 0.8 mm".
_STATED = re.compile(r"(?<![\w(√·/])(\w+) = [−-]?\d[\d.,·⁰¹²³⁴⁵⁶⁷⁸⁹⁻]* ([^\s,.;:)]+)(?! \w)")


def _symbol(text: str) -> str:
    """A symbol as read, whatever wrote it: ``f<sub>э</sub>`` (HTML), ``$f_{э}$`` (mathtext)
    and ``f_э`` all read ``fэ``."""
    text = re.sub(r"\\mathrm\{([^}]*)\}", r"\1", text)
    return re.sub(r"[\s$_^{}]", "", text).replace("−", "-")


def _units(lang: Lang) -> dict[str, str]:
    """Each unit as printed in ``lang``, to the unit it prints."""
    m = Messages(lang)
    return {m.unit(u): u for u in UNIT_LABELS}


def _unit_of(tail: str, units: dict[str, str]) -> str | None:
    tail = _SCALE.sub("", tail.strip())
    return units.get(tail)


def _split(label: str, units: dict[str, str]) -> tuple[str, str, str] | None:
    """A header's or an axis's ``words symbol, unit``: its words, symbol and unit ("1" when
    it names none); None when it names no symbol."""
    head, comma, tail = label.rpartition(", ")
    unit = _unit_of(tail, units) if comma else None
    if unit is None:
        head, unit = label, "1"
    if "$" in head:  # the first symbol in mathtext names the quantity ("S₁ = μ_t·ω/p̄")
        words, _, rest = head.partition("$")
        return words.strip(), _symbol(rest.partition("$")[0]), unit
    words, _, symbol = head.partition(" = ")[0].strip().rpartition(" ")  # "z = Z/R" names z
    if not symbol or any(c.isdigit() for c in symbol[:1]) or len(symbol) > 6:
        return None
    return words.strip(), _symbol(symbol), unit


def _printed_units(rendered: Rendered, lang: Lang) -> dict[str, set[str]]:
    """Each symbol with the units it is printed in across a report: the quantity tables
    (symbol and unit columns), the configuration (its descriptions begin with the symbol,
    after their owner's name: ``disc: E, ...``), the tables' column headers (``p, at``), the
    plots' axes, and the values stated in the text (``λc = 0.8 mm``)."""
    m = Messages(lang)
    units = _units(lang)
    found: dict[str, set[str]] = defaultdict(set)
    described: list[tuple[str, str]] = []  # the configuration's rows: description, unit
    html = _FORMULA.sub("", rendered.html)
    for table in tables(html):
        head = [h.strip() for h in table.header]
        if m("col.symbol") in head and m("col.unit") in head:
            at, unit = head.index(m("col.symbol")), head.index(m("col.unit"))
            for row in table.rows:
                if len(row) > max(at, unit) and row[at].strip() and row[unit] in units:
                    found[_symbol(row[at])].add(units[row[unit]])
        elif head[:2] == [series_text(lang)("result"), series_text(lang)("unit")]:
            for row in table.rows:  # a series' "f: friction coefficient, steady part" and unit
                if len(row) > 1 and row[1] in units:
                    found[_symbol(row[0].partition(": ")[0])].add(units[row[1]])
        elif head[:3] == [m("col.description"), m("col.value"), m("col.unit")]:
            described += [(row[0].split("\n")[0], row[2]) for row in table.rows if len(row) > 2]
        for cell in head:
            split = _split(cell, units)
            if split is not None and not split[0]:  # a header of a symbol, not of words
                found[split[1]].add(split[2])
    for fig in rendered.figures:
        for ax in fig.axes:
            for label in (ax.get_xlabel(), ax.get_ylabel()):
                split = _split(label, units) if label else None
                if split is not None:
                    found[split[1]].add(split[2])
    for symbol, unit in _STATED.findall(_visible(html)):
        if unit in units:
            found[_symbol(symbol)].add(units[unit])
    for words, unit in described:  # "disc: E, ..." names E; "λc фильтра ..." a symbol known
        for text in (words, words.partition(": ")[2]):
            leading = _LEADING.match(text)
            first = leading[1] if leading else text.partition(" ")[0]
            if (leading or _symbol(first) in found) and unit in units:
                found[_symbol(first)].add(units[unit])
                break
    return found


@pytest.mark.parametrize(("kind", "lang"), CASES)
@pytest.mark.parametrize("which", ["run", "series"])
def test_one_unit_per_symbol_across_tables_plots_and_text(
    kind: StandKind, lang: Lang, which: str
) -> None:
    # λc was printed in m in the configuration (page 1) and in mm in the ISO results
    found = _printed_units((run_report if which == "run" else series_report)(kind, lang), lang)
    assert found
    two = {symbol: sorted(units) for symbol, units in found.items() if len(units) > 1}
    assert not two, f"one symbol, two units: {two}"


@pytest.mark.parametrize(("kind", "lang"), CASES)
@pytest.mark.parametrize("which", ["run", "series"])
def test_one_symbol_per_quantity_on_the_plots(kind: StandKind, lang: Lang, which: str) -> None:
    """The axes of a report's plots: a quantity named in words carries one symbol, and a
    symbol names one quantity (as the tables' rows, :func:`test_one_symbol_per_quantity`)."""
    rendered = (run_report if which == "run" else series_report)(kind, lang)
    units = _units(lang)
    symbols: dict[str, set[str]] = defaultdict(set)
    words: dict[str, set[str]] = defaultdict(set)
    for fig in rendered.figures:
        for ax in fig.axes:
            for label in (ax.get_xlabel(), ax.get_ylabel()):
                split = _split(label, units) if label else None
                if split is not None and split[0]:
                    symbols[split[0]].add(split[1])
                    words[split[1]].add(split[0])
    two = {w: sorted(s) for w, s in symbols.items() if len(s) > 1}
    assert not two, f"one quantity, two symbols: {two}"
    shared = {s: sorted(w) for s, w in words.items() if len(w) > 1}
    assert not shared, f"one symbol, two quantities: {shared}"


@pytest.mark.parametrize("lang", LANGS)
def test_a_plot_names_its_curves_with_its_tables_symbols(lang: Lang) -> None:
    # table 3.2 printed Π_z and Π_m, its plot (3.29) Π_0 and Π_e
    rendered = run_report(StandKind.SLIDE_BEARING, lang)
    table_word = {"en": "Table", "ru": "Таблица"}[lang]
    heads = {
        number: {_symbol(h.partition(",")[0]) for h in t.header}
        for t in tables(rendered.html)
        for number in ("3.2", "3.3")
        if t.caption.startswith(f"{table_word} {number}.")
    }
    by_abscissa = {"φ": "3.3", "z": "3.2"}  # (3.28) against φ, (3.29) against z
    drawn = 0
    for fig in rendered.figures:
        for ax in fig.axes:
            legend = ax.get_legend()
            split = _split(ax.get_xlabel(), _units(lang))
            if legend is None or split is None or split[1] not in by_abscissa:
                continue
            named = {
                _symbol(s)
                for t in legend.get_texts()
                for s in re.findall(r"\$[^$]+\$", t.get_text())
            }
            assert named and named <= heads[by_abscissa[split[1]]], (split[1], named)
            drawn += 1
    assert drawn == 2
