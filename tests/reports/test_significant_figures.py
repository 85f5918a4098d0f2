"""The printed report as a reader checks its numbers (issue 37, item 6; GUM 7.2.6): a
result to the place of its uncertainty, counts whole, percentages to 0.1, one number of
decimals in each column of a table. Read from the PDF's text, in both languages."""

from __future__ import annotations

import re

import pytest

from rigserver.reports.i18n import Lang
from schemas.stands import StandKind
from tests.reports.rendered import run_html, run_report, series_report

NUMBER = r"-?\d+(?:[.,]\d+)?"


def _decimals(number: str) -> int:
    return len(re.split(r"[.,]", number)[1]) if re.search(r"[.,]", number) else 0


@pytest.mark.parametrize("lang", ["en", "ru"])
def test_the_flat_report_prints_each_number_to_its_digits(lang: Lang) -> None:
    text = run_report(StandKind.RECIPROCATING, lang).text
    sign = "," if lang == "ru" else "."

    # the table of the strokes by blocks of cycles: three numbers a row, each column with
    # one number of decimals (0.549 and 0.55 were printed beside 0.5494)
    rows = re.findall(rf"^({NUMBER}) ({NUMBER}) ({NUMBER})$", text, flags=re.MULTILINE)
    assert len(rows) >= 20, text
    for column in zip(*rows, strict=True):
        assert len({_decimals(n) for n in column}) == 1, column
    assert all(sign in n for row in rows for n in row)

    # the cycles run are a count: a whole number (the record's 999.987)
    cycles = "пройдено циклов" if lang == "ru" else "cycles run"
    counted = re.findall(rf"{cycles} nc\s+(\S+)", text)
    assert counted and all(re.fullmatch(r"\d+", n) for n in counted), counted

    # a percentage to 0.1: the material ratios of ISO 13565-2
    ratios = re.findall(rf"Mr[12]\s+({NUMBER}) %", text)
    assert len(ratios) == 2 and all(_decimals(n) == 1 for n in ratios), ratios

    # μ with its expanded uncertainty: U to two significant digits, μ to the same place,
    # and μ in the results and in the conclusions to that place too
    value, expanded = re.findall(rf"μ ({NUMBER}) ± ({NUMBER}) \(k = 2\)", text)[0]
    assert len(expanded.lstrip("0,.").replace(sign, "")) == 2, expanded
    assert _decimals(value) == _decimals(expanded)
    assert f"μ = {value}" in text
    # k of the disc by its mass loss: U = 1.0·10⁻⁵, so k carries one decimal of 10⁻⁵
    k, u = re.findall(rf"\(({NUMBER}) ± ({NUMBER})\)·10⁻⁵ \(k = 2\)", text)[0]
    assert _decimals(k) == _decimals(u) == 1
    assert f"k = {k}·10⁻⁵" in text


def test_the_series_report_states_a_mean_to_its_standard_error() -> None:
    text = series_report(StandKind.RECIPROCATING, "en").text
    # μ_s of three runs: x̄, s, s/√n, the 95 % interval; s and s/√n to two significant
    # digits, the mean and the interval to the place of s/√n (GUM 7.2.6)
    found = re.search(
        rf"at the start 3 ({NUMBER}) ({NUMBER}) ({NUMBER}) ({NUMBER}) … ({NUMBER})", text
    )
    assert found, text
    mean, std, sem, low, high = found.groups()
    for spread in (std, sem):
        assert len(spread.replace(".", "").lstrip("0")) == 2, spread
    assert _decimals(mean) == _decimals(sem) == _decimals(low) == _decimals(high)
    # the runs' table: a column of one number of decimals (μ_s of the three runs)
    runs = re.findall(rf"^\S+ finished rigsim ({NUMBER}) ({NUMBER}) ", text, flags=re.MULTILINE)
    assert len(runs) == 3
    for column in zip(*runs, strict=True):
        assert len({_decimals(n) for n in column}) == 1, column


@pytest.mark.parametrize("lang", ["en", "ru"])
def test_the_percentages_of_the_conclusions_have_one_decimal(lang: Lang) -> None:
    # the slide bearing's mean |ΔΠ| against the short and long bearing (3.25)-(3.27), the
    # MTOS's mean |Δf| against f_T (4.10): percentages, printed to 0.1
    for kind in (StandKind.SLIDE_BEARING, StandKind.MTOS):
        text = re.sub(r"<[^>]+>", "", run_html(kind, lang))
        shares = re.findall(rf"\| = ({NUMBER}) %", text)
        assert shares, kind
        assert all(_decimals(n) == 1 for n in shares), (kind, shares)
