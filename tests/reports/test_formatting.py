"""Numbers with four significant figures and the symbols' scripts, as the reports print them."""

from __future__ import annotations

import pytest

from rigserver.reports.formatting import fmt, html_symbol, pairs, tex


@pytest.mark.parametrize(
    ("value", "printed"),
    [
        # the expected texts are written out by hand from the values
        (0.398527367263139, "0.3985"),
        (3.833462446638811e-08, "3.833·10⁻⁸"),
        (696272.15, "6.963·10⁵"),
        (15000.0, "1.5·10⁴"),
        (324.0, "324"),
        (-5299769.6, "-5.3·10⁶"),
        (0.0001234, "0.0001234"),  # fixed notation down to 1e-4, as Python's .4g
        (1e-5, "1·10⁻⁵"),
        (2120.5750411731105, "2121"),
        (-0.0, "0"),
        (7, "7"),
    ],
)
def test_four_significant_figures(value: float, printed: str) -> None:
    assert fmt(value) == printed


@pytest.mark.parametrize("value", [None, float("nan"), float("inf"), True])
def test_no_number_prints_a_dash(value: float | None) -> None:
    assert fmt(value) == "—"


def test_scripts_in_html_and_mathtext() -> None:
    assert html_symbol("S_1^{-1}") == "S<sub>1</sub><sup>-1</sup>"
    assert html_symbol("I_{h,exp} = 2") == "I<sub>h,exp</sub> = 2"
    assert html_symbol("f_э/f_э1: ratio") == "f<sub>э</sub>/f<sub>э1</sub>: ratio"
    assert html_symbol("a<b_x") == "a&lt;b<sub>x</sub>"  # text is escaped
    assert tex("f_э, fluid film") == "$f_{э}$, fluid film"
    assert tex("0.4·I_theor … 2.6·I_theor") == "0.4·$I_{theor}$ … 2.6·$I_{theor}$"
    assert tex("ε") == "ε"


def test_free_form_values() -> None:
    assert pairs({"loads": [500.0, 1500.0], "pin": "St3sp", "simulated": True}) == (
        "loads: 500, 1500; pin: St3sp; simulated: True"
    )
