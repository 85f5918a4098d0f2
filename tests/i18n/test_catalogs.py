"""Every message has its translation: a third language is a catalog, not code."""

from __future__ import annotations

import tomllib
from importlib import resources

import pytest
from babel.messages.pofile import read_po

from rigserver.reports.i18n import DEFAULT, DOMAIN, LANGS, Messages
from rigserver.web.pages import ROWS_RECEIVED
from tests.i18n.messages import ROOT, declared, every_message, extracted

CATALOGS = [lang for lang in LANGS if lang != DEFAULT]


def catalog(lang: str):  # type: ignore[no-untyped-def]
    po = resources.files("rigserver") / "locale" / lang / "LC_MESSAGES" / f"{DOMAIN}.po"
    with po.open("rb") as source:
        return read_po(source, locale=lang, domain=DOMAIN)


def test_babel_finds_the_messages_of_code_schemas_and_templates() -> None:
    places = {where.split(":")[0] for where in extracted().values()}
    assert {
        "rigserver/reports/i18n.py",
        "schemas/labels.py",
        "schemas/stands.py",
        "rigserver/web/templates/run.html",
    } <= places


def test_the_texts_declared_as_data_are_extracted() -> None:
    # else `pybabel update` would turn their translations obsolete
    assert not set(declared()) - set(extracted())


@pytest.mark.parametrize("lang", CATALOGS)
def test_every_message_is_translated(lang: str) -> None:
    found = catalog(lang)
    missing = []
    for (context, text), where in every_message().items():
        message = found.get(text, context=context)
        if message is None or not message.string or message.fuzzy:
            missing.append(f"{where}: {text!r}")
    assert not missing, "untranslated or fuzzy:\n" + "\n".join(missing)


@pytest.mark.parametrize("lang", CATALOGS)
def test_a_catalog_holds_no_fuzzy_or_empty_entries(lang: str) -> None:
    found = catalog(lang)
    assert not [m.id for m in found if m.id and (m.fuzzy or not m.string)]


def test_the_catalogs_are_package_data() -> None:
    # an installed (not editable) rig carries its catalogs: pyproject's package-data names them
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    patterns = config["tool"]["setuptools"]["package-data"]["rigserver"]
    shipped = {p for pattern in patterns for p in (ROOT / "rigserver").glob(pattern)}
    assert {
        ROOT / "rigserver" / "locale" / lang / "LC_MESSAGES" / f"{DOMAIN}.po" for lang in CATALOGS
    } <= shipped


@pytest.mark.parametrize(
    ("lang", "counts"),
    [
        ("en", {0: "rows received", 1: "row received", 2: "rows received", 21: "rows received"}),
        (
            "ru",
            {
                1: "строка получена",
                2: "строки получены",
                5: "строк получено",
                11: "строк получено",
                21: "строка получена",
                22: "строки получены",
            },
        ),
    ],
)
def test_a_count_takes_the_plural_form_of_its_language(lang: str, counts: dict[int, str]) -> None:
    """ "1 rows received" no more (issue 39, item 11): gettext's plural forms (Russian:
    1 and 21 one form, 2-4 and 22 another, 5-20 a third), and the forms a page's script
    picks by ``Intl.PluralRules`` category."""
    t = Messages(lang)
    for n, words in counts.items():
        assert t.plural(*ROWS_RECEIVED, n) == words
    forms = t.plural_forms(*ROWS_RECEIVED)
    assert forms["one"] == counts[1] and forms["many"] == forms["other"]
