"""The language of a report, and a catalogue that has every text in both languages."""

from __future__ import annotations

import string

import pytest

from rigserver.reports.i18n import MESSAGES, UNIT_LABELS, Messages, negotiate
from schemas.stands import StandKind
from schemas.units import UNITS
from tests.reports.rendered import run_html
from tests.reports.simulated import tables


@pytest.mark.parametrize(
    ("requested", "header", "chosen"),
    [
        (None, "ru-RU,ru;q=0.9,en-US;q=0.8,en;q=0.7", "ru"),
        (None, "en-US,en;q=0.9,ru;q=0.8", "en"),
        (None, "de-DE, ru;q=0.5", "ru"),  # German is not offered; Russian is the best left
        (None, "ru;q=0, en", "en"),  # q=0 means "not this one"
        (None, "en;q=0.5, ru;q=0.6", "ru"),
        (None, None, "en"),
        (None, "*", "en"),
        ("ru", "en", "ru"),  # ?lang= wins over the header
        ("en", "ru", "en"),
    ],
)
def test_language_from_query_or_accept_language(
    requested: str | None, header: str | None, chosen: str
) -> None:
    assert negotiate(requested, header) == chosen


def test_an_unsupported_language_is_refused() -> None:
    with pytest.raises(ValueError, match="lang must be one of en, ru, got 'de'"):
        negotiate("de", None)


def test_every_unit_has_a_label_in_both_languages() -> None:
    assert set(UNIT_LABELS) == set(UNITS)
    assert Messages("ru").unit("Pa*s") == "Па·с"
    assert Messages("en").unit("um") == "µm"
    assert Messages("ru").unit("um") == "мкм"
    assert Messages("ru").unit("s") == "с"  # the unit, in the context "unit"


def test_both_languages_take_the_same_values() -> None:
    ru = Messages("ru")
    for key, en in MESSAGES.items():
        texts = (en, ru.gettext(en))
        fields = [{f for _, f, _, _ in string.Formatter().parse(text) if f} for text in texts]
        assert fields[0] == fields[1], key
    assert Messages("ru")("lab_work", n=3) == "Лабораторная работа № 3"


def test_the_gauges_technical_atmosphere_prints_as_the_manuals_atm() -> None:
    # lab 3's manometers read in "атм" (the manual's table 3.1, "p, атм"): the technical
    # atmosphere, 1 kgf/cm² = 9.80665 N / 10⁻⁴ m² (docs/models.md, section 3)
    assert UNITS["at"].factor == pytest.approx(9.80665 / 1e-4)
    assert UNITS["atm"].factor == 101_325.0  # the standard atmosphere, the other reading
    assert Messages("ru").unit("at") == "атм"
    assert Messages("ru").unit("atm") != Messages("ru").unit("at")
    assert (Messages("en").unit("at"), Messages("en").unit("atm")) == ("at", "atm")
    html = run_html(StandKind.SLIDE_BEARING, "ru")
    headers = {h for table in tables(html) for h in table.header}
    assert "p, атм" in headers
    assert not [h for h in headers if h.endswith(" ат")]
