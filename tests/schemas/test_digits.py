"""The digits of a printed number (issue 37, item 6): GUM 7.2.6 for a result with an
uncertainty, whole counts, percentages to 0.1, one number of decimals in a column."""

from __future__ import annotations

import math

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from rigserver.reports.formatting import (
    column,
    number_locale,
    shown,
    to_uncertainty,
    with_uncertainty,
)
from schemas import digits
from schemas.labels import Label

uncertainties = st.floats(min_value=1e-12, max_value=1e12, allow_nan=False, allow_infinity=False)
values = st.floats(min_value=-1e12, max_value=1e12, allow_nan=False, allow_infinity=False)


@given(value=values, u=uncertainties)
def test_the_uncertainty_has_two_significant_digits_and_the_value_its_place(
    value: float, u: float
) -> None:
    got, got_u, places = digits.round_to_uncertainty(value, u)
    # U in units of its last place is a two-digit whole number (10..99)
    assert 10 <= round(got_u * 10.0**places) <= 99
    assert math.isclose(got_u * 10.0**places, round(got_u * 10.0**places), abs_tol=1e-6)
    # the value rounded to the same place: within half a unit of it of the original
    unit = 10.0**-places
    assert abs(got - value) <= 0.5 * unit * (1 + 1e-9) + 1e-12 * abs(value)
    # ...and the uncertainty likewise (rounding, not truncating)
    assert abs(got_u - u) <= 0.5 * unit * (1 + 1e-9)


def test_the_gum_example() -> None:
    # GUM (JCGM 100:2008) 7.2.6 and 7.2.2: m_s = 100,021 47 g with u_c = 0,35 mg
    assert digits.round_to_uncertainty(100.02147, 0.00035) == (100.02147, 0.00035, 5)
    assert with_uncertainty(100.02147, 0.00035) == "100.02147 ± 0.00035 (k = 2)"
    with number_locale("ru"):
        assert with_uncertainty(100.02147, 0.00035) == "100,02147 ± 0,00035 (k = 2)"
    # GUM 7.2.6: an uncertainty is stated to at most two significant digits, so 0.3481 mg
    # is 0.35 mg, and the value follows it
    assert digits.round_to_uncertainty(100.0214734, 0.0003481) == (100.02147, 0.00035, 5)


def test_a_rounding_that_carries_keeps_two_digits() -> None:
    # U = 0.0996 rounds to 0.10 (two digits), not 0.100: the value goes to 0.01 too
    assert digits.uncertainty_places(0.0996) == 2
    assert with_uncertainty(0.5, 0.0996) == "0.50 ± 0.10 (k = 2)"
    assert with_uncertainty(1234.5, 99.7) == "1230 ± 100 (k = 2)"


def test_a_value_alone_to_its_uncertainty() -> None:
    # the report's k of the disc: 7.683·10⁻⁵ mm³/(N·m) with U = 1.0·10⁻⁵ is 7.7·10⁻⁵
    assert to_uncertainty(7.683e-5, 1.03e-5) == "7.7·10⁻⁵"
    assert to_uncertainty(0.55134, 0.0093) == "0.5513"
    assert to_uncertainty(0.55134, None) == "0.5513"  # no uncertainty: four digits


def test_counts_are_whole() -> None:
    # the "999.987 cycles"
    cycles = Label("laps (cycles) run", "n_L", digits=6, count=True)
    assert shown(cycles, 999.987, "1") == "1000"
    assert digits.count(2.5) == 3 and digits.count(-2.5) == -3 and digits.count(0.4) == 0


def test_percentages_to_a_tenth() -> None:
    # the issue's −0.0662 %
    share = Label("relative difference", "δ", unit="%", digits=3)
    assert shown(share, -0.0662, "%") == "-0.1"
    assert shown(share, 0.04, "%") == "0.0"
    assert shown(share, 12.345, "%") == "12.3"
    with number_locale("ru"):
        assert shown(share, 12.345, "%") == "12,3"


@pytest.mark.parametrize(
    ("numbers", "printed"),
    [
        # the strokes' μ: 0.549 and 0.55 were printed with three and two decimals
        ([0.7454, 0.549, 0.55], ["0.7454", "0.5490", "0.5500"]),
        ([12.5, 987.5], ["12.5", "987.5"]),
        ([80000.0, 12.0], ["80000", "12"]),
        ([1.234e-6, 5.6e-7, None], ["1.234·10⁻⁶", "0.560·10⁻⁶", "—"]),
    ],
)
def test_a_column_has_one_number_of_decimals(
    numbers: list[float | None], printed: list[str]
) -> None:
    assert column(numbers) == printed


@given(st.lists(st.floats(min_value=-1e6, max_value=1e6, allow_nan=False), min_size=1))
@example(numbers=[5e-324])  # 10^324 is past a double: the scaling divided by zero
def test_every_column_has_one_number_of_decimals(numbers: list[float]) -> None:
    cells = column(numbers)
    decimals = {len(c.split("·")[0].partition(".")[2]) for c in cells}
    assert len(decimals) == 1, cells


def test_an_uncertainty_sets_the_digits_of_its_value() -> None:
    results = {"k": 7.683e-5, "k_uncertainty": 5.1e-6, "k_expanded": 1.03e-5, "x": 1.0}
    assert digits.stated_uncertainty("k", results) == 1.03e-5  # the expanded one first
    assert digits.stated_uncertainty("k_uncertainty", results) == 5.1e-6  # itself
    assert digits.stated_uncertainty("x", results) is None
    assert digits.stated_uncertainty("x", {"x": 1.0, "x_expanded": float("nan")}) is None


def test_an_uncertainty_of_rounding_noise_sets_no_digits() -> None:
    # three runs with the same readings: s = 1.7·10⁻¹⁷ of a mean 0.1097 (the series report
    # printed 0,1097156587905486341); and a spread below the label's resolution
    friction = Label("friction coefficient", "f")
    assert shown(friction, 0.10971565879054863, "1", 1.7e-17) == "0.1097"
    chi = Label("relative eccentricity", "χ", resolution=1e-4)
    assert shown(chi, 0.638016, "1", 4e-7) == "0.638"  # digits=4 by its label
    assert shown(chi, 0.638016, "1", 0.0002) == "0.63802"
