"""How many digits a printed number carries: the one rule of the pages, reports and consoles.

- A result with an uncertainty is printed to it (GUM, JCGM 100:2008, 7.2.6): the
  uncertainty to two significant digits, the value rounded to the same decimal place
  (the GUM's m_s = 100.021 47 g with u_c = 0.35 mg).
- A count (cycles, laps, profiles, rows) is a whole number: no "999.987 cycles".
- A percentage to 0.1.
- The numbers of a table's column share one number of decimals: as many as the one that
  shows the most at the column's significant digits.

The functions give decimal places (``places``: digits after the decimal sign, negative for
tens and hundreds); the printing (decimal sign of the language, powers of ten) is
:mod:`rigserver.reports.formatting`'s.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from decimal import Decimal
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from schemas.labels import Label

#: Significant digits of a stated uncertainty (GUM 7.2.6: "at most two").
UNCERTAINTY_DIGITS = 2
#: Decimals of a percentage.
PERCENT_PLACES = 1


def places_for(value: float, digits: int) -> int:
    """The decimal places at which ``value`` (non-zero, finite) shows ``digits``
    significant digits once rounded: 0.0996 to two is 0.10, two places, not 0.100."""
    exponent = math.floor(math.log10(abs(value)))
    places = digits - 1 - exponent
    if abs(round(value, places)) >= 10.0 ** (exponent + 1):
        places -= 1  # rounding carried into the next power of ten (0.0996 -> 0.10)
    return places


def uncertainty_places(uncertainty: float) -> int:
    """The decimal places of a value stated with ``uncertainty`` (GUM 7.2.6): those at
    which the uncertainty has two significant digits."""
    return places_for(uncertainty, UNCERTAINTY_DIGITS)


def round_to_uncertainty(value: float, uncertainty: float) -> tuple[float, float, int]:
    """``value`` and ``uncertainty`` rounded as GUM 7.2.6 states them, with the places:
    ``(100.021 47, 0.000 35, 5)`` for the GUM's 100.021 47 g and 0.35 mg."""
    places = uncertainty_places(uncertainty)
    return round(value, places), round(uncertainty, places), places


def is_stated(uncertainty: float | None) -> bool:
    """An uncertainty that can set a value's digits: finite and above zero."""
    return uncertainty is not None and math.isfinite(uncertainty) and uncertainty > 0


#: An uncertainty below this share of its value is the arithmetic's noise (the spread of
#: runs that hold the same readings, 1.7·10⁻¹⁷), not a measured one.
RELATIVE_NOISE = 1e-9


def result_places(
    label: Label, value: float, stored: str, uncertainty: float | None = None
) -> int | None:
    """The decimals a result (``value`` and its ``uncertainty`` stored in ``stored``) is
    printed with in ``label``'s display unit, in the rule's order: a count none (whole), a
    value with a stated uncertainty those of the uncertainty (GUM 7.2.6; one below the
    label's resolution or the arithmetic's noise is none), a percentage one; ``None``: the
    label's significant digits."""
    if label.count:
        return 0
    u = None if uncertainty is None else label.displayed(uncertainty, stored)
    if (
        u is not None
        and is_stated(u)  # finite, above zero
        and u >= label.resolution
        and u > RELATIVE_NOISE * abs(label.displayed(value, stored))
    ):
        return uncertainty_places(u)
    if label.unit == "%":
        return PERCENT_PLACES
    return None


def count(value: float) -> int:
    """A count as the whole number nearest to it (halves away from zero)."""
    return int(math.copysign(math.floor(abs(value) + 0.5), value))


def column_places(values: Iterable[float | None], digits: int) -> int | None:
    """The decimals shared by a table's column: as many as the one that shows the most
    once each is rounded to ``digits`` significant digits (0.179 and 1.07 print 0.179 and
    1.070), yet no more than two beyond the largest's own (a 0.001 beside 1000 is 0.00);
    ``None`` for a column without a finite non-zero number."""
    numbers = [abs(v) for v in values if v is not None and math.isfinite(v) and v != 0]
    if not numbers:
        return None
    shown = max(_decimals(float(f"{v:.{digits}g}")) for v in numbers)
    return min(shown, max(0, places_for(max(numbers), digits)) + 2)


def _decimals(value: float) -> int:
    """The decimals ``value`` shows written without trailing zeros (12.5: 1, 1200: 0)."""
    exponent = Decimal(repr(value)).normalize().as_tuple().exponent
    assert isinstance(exponent, int)
    return max(0, -exponent)


#: The endings of a result's uncertainties: expanded (k = 2) and standard.
UNCERTAINTY_SUFFIXES = ("_expanded", "_uncertainty")


def stated_uncertainty(name: str, results: Mapping[str, Any]) -> float | None:
    """The uncertainty that sets the digits of the result ``name`` among ``results`` (one
    level of a results payload): its expanded one, else its standard one; an uncertainty
    is printed to itself (two significant digits); ``None`` when none is stated."""
    if name.endswith(UNCERTAINTY_SUFFIXES):
        return _number(results.get(name))
    for suffix in UNCERTAINTY_SUFFIXES:
        found = _number(results.get(name + suffix))
        if found is not None:
            return found
    return None


def _number(value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value) if is_stated(value) else None
