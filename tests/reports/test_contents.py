"""Each lab's report list (:mod:`rigserver.reports.contents`) against the rendered PDF: every
item's heading, every formula it asks for (its number cited, its formula written out), every
table and plot by its caption, in both languages. An item added to a list that the report
does not produce fails here."""

from __future__ import annotations

import re

import pytest
from markupsafe import Markup

from rigserver.reports import equations
from rigserver.reports.contents import Item, Students
from rigserver.reports.formatting import html_symbol
from rigserver.reports.i18n import LANGS, MESSAGES, Lang, Messages
from rigserver.reports.kits import KITS
from schemas.stands import StandKind
from tests.reports.rendered import run_report, squeezed

CASES = [(kind, lang) for kind in StandKind for lang in LANGS]
_TAGS = re.compile(r"<[^>]+>")


def plain(text: str) -> str:
    """What a caption or formula reads as in the PDF's text: no markup, no whitespace."""
    return squeezed(Markup(_TAGS.sub("", str(text))).unescape())


def caption(t: Messages, key: str) -> str:
    """A table's or plot's caption up to its first value (``Table 3.2. ... φ = {phi}``); a
    bare number names the manual's table (``4.1``)."""
    if re.fullmatch(r"\d\.\d+", key):
        return plain(t.gettext(MESSAGES["table_number"]).format(n=key))
    text = re.split(r"(?<!\{)\{(?!\{)", t.gettext(MESSAGES[key]))[0]
    return plain(html_symbol(text.replace("{{", "{").replace("}}", "}")))


def missing(kind: StandKind, lang: Lang, items: tuple[Item, ...]) -> list[str]:
    """What of ``items`` the report of ``kind`` in ``lang`` does not show."""
    t = Messages(lang)
    text = squeezed(run_report(kind, lang).text)
    cited = set(equations.citations(run_report(kind, lang).text))
    gone: list[str] = []
    for item in items:
        where = f"item {item.number} ({item.manual})"
        if item.heading and plain(t.gettext(item.heading)) not in text:
            gone.append(f"{where}: heading {t.gettext(item.heading)!r}")
        for number in item.formulas:
            if number not in cited:
                gone.append(f"{where}: no citation of ({number})")
            if plain(equations.formula(t, number)) not in text:
                gone.append(f"{where}: formula ({number}) {equations.formula(t, number)!r}")
        for keys in (*item.tables, *item.figures):
            if not any(caption(t, key) in text for key in keys.split("|")):
                gone.append(f"{where}: caption {keys!r} {caption(t, keys.split('|')[0])!r}")
        gone += [f"{where}: {w!r}" for w in item.words if plain(t.gettext(w)) not in text]
    return gone


@pytest.mark.parametrize(("kind", "lang"), CASES, ids=[f"{k.value}-{lang}" for k, lang in CASES])
def test_the_report_holds_every_item_of_its_list(kind: StandKind, lang: Lang) -> None:
    gone = missing(kind, lang, KITS[kind].contents.of_part(1))
    assert not gone, "\n".join(gone)


@pytest.mark.parametrize("kind", list(StandKind))
def test_the_students_sections_print_as_room_on_paper_when_empty(kind: StandKind) -> None:
    html = run_report(kind, "en").html
    for item in KITS[kind].contents.students():
        t = Messages("en")
        section = html.split(f"<h2>{t.gettext(item.heading)}</h2>", 1)[1].split("</section>")[0]
        room = "space frame" if item.students is Students.SKETCH else "space ruled"
        assert room in section, item


def test_every_formula_the_lists_ask_for_has_its_text() -> None:
    asked = {n for kit in KITS.values() for i in kit.contents.items for n in i.formulas}
    assert not asked - set(equations.EQUATIONS)


def test_an_item_not_produced_is_found_missing() -> None:
    # the check itself can fail: a caption, a formula and a heading no report prints
    absent = Item(99, "nothing", "No such heading", formulas=("2.16",), figures=("w.fig_wear",))
    assert len(missing(StandKind.MTOS, "en", (absent,))) == 4


def test_a_translation_cites_the_equations_its_english_cites() -> None:
    # the Russian label of X_set once dropped "(3.16)", and with it the formula's place
    from tests.i18n.test_catalogs import catalog

    def cites(text: str | tuple[str, ...]) -> list[list[str]]:
        """Each form's citations (a count's message has several forms)."""
        forms = text if isinstance(text, tuple) else (text,)
        return [sorted(equations.citations(form)) for form in forms]

    differ = [
        f"{m.id!r} -> {m.string!r}"
        for m in catalog("ru")
        if m.id and any(c != cites(m.id)[0] for c in cites(m.string))
    ]
    assert not differ, "\n".join(differ)
