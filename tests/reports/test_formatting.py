"""Numbers with four significant figures and the symbols' scripts, as the reports print them."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rigserver.reports.formatting import (
    fmt,
    html_symbol,
    number_locale,
    shown,
    tex,
    with_unit,
)
from rigserver.reports.i18n import Messages
from rigserver.reports.run_report import particulars_text
from schemas.labels import MTOS, PROFILOMETER, SLIDE_BEARING, round_to


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
    plan = {"loads_fluid": [500.0, 1500.0], "pin": "St3sp", "simulated": True, "own": "x"}
    assert particulars_text(Messages("en"), plan) == (
        "loads, fluid film: 500, 1500 N; pin: St3sp; simulated: yes; own: x"
    )
    with number_locale("ru"):
        assert particulars_text(Messages("ru"), {"load_N": 300.5}) == "нагрузка: 300,5 Н"
    # an angle's degree sign stands against its number, a temperature's after a space
    assert particulars_text(Messages("en"), {"limb_step_deg": 10}) == "step of the limb: 10°"
    assert with_unit("23", "°C") == "23 °C" and with_unit("0.5", "") == "0.5"


def test_russian_numbers_take_a_decimal_comma() -> None:
    with number_locale("ru"):
        assert fmt(0.3985) == "0,3985"
        assert fmt(3.833e-8) == "3,833·10⁻⁸"
    assert fmt(0.3985) == "0.3985"  # the block ends, the default comes back


def test_results_in_their_display_units_and_digits() -> None:
    # 8e-7 m is 0.8 µm (the Ra = 8·10⁻⁷ m), three significant digits declared
    assert shown(PROFILOMETER["ra"], 8.123456e-7, "m") == "0.812"
    assert shown(PROFILOMETER["base_length"], 0.0008, "m") == "0.8"  # mm, as the channel
    assert shown(MTOS["steps[].h_min"], 2.725e-6, "m") == "2.725"


def test_rounding_noise_is_zero() -> None:
    # the e_x = 2.711·10⁻²⁰ m and Π0 = −1.388·10⁻¹⁷ at φ = 180°
    assert shown(SLIDE_BEARING["table[].e_x"], 2.711e-20, "m") == "0"
    assert shown(SLIDE_BEARING["table[].pi_short"], -1.388e-17, "1") == "0"
    assert shown(SLIDE_BEARING["table[].e_x"], -3.2e-6, "m") == "-3.2"


def test_plot_ticks_take_the_decimal_sign_of_the_language() -> None:
    from matplotlib.figure import Figure

    from rigserver.reports.plots import decorate

    for lang, expected in (("en", "0.2"), ("ru", "0,2")):
        with number_locale(lang):
            ax = Figure().subplots()
            ax.plot([0.0, 1.0], [0.0, 1.0])
            decorate(ax, xlabel="x", ylabel="y")
        ax.figure.canvas.draw()  # type: ignore[union-attr]
        ticks = [label.get_text() for label in ax.get_xticklabels()]
        assert expected in ticks, ticks


@given(
    value=st.floats(min_value=-1e3, max_value=1e3, allow_nan=False),
    digits=st.integers(min_value=1, max_value=6),
    resolution=st.sampled_from([0.0, 1e-4, 1e-2]),
)
def test_round_to_keeps_digits_and_drops_noise(
    value: float, digits: int, resolution: float
) -> None:
    got = round_to(value, digits, resolution)
    if abs(value) < resolution:
        assert got == 0.0  # below the resolution: rounding noise, printed 0
    else:  # within half a unit of the last significant digit
        last = 10.0 ** (math.floor(math.log10(abs(value))) - digits + 1) if value else 0.0
        assert abs(got - value) <= 0.5 * last * (1 + 1e-9)
        assert round_to(got, digits, resolution) == got  # rounding again changes nothing
