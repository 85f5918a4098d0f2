"""How numbers and symbols are printed in the reports and pages.

Numbers carry four significant figures (``fmt``), or the digits a result is declared with
(:class:`schemas.labels.Label`, :func:`shown`), by the rule of :mod:`schemas.digits` (GUM
7.2.6: a value to its uncertainty; counts whole, percentages to 0.1, one number of decimals
a column: :func:`shown_column`, :func:`column`); a power of ten is printed as ``·10ⁿ``; the
decimal sign is the language's (Babel: a comma in Russian), set for the work at hand by
:func:`number_locale`.
Symbols are written once in a small TeX-like syntax (``"Π_э"``, ``"t_{pэ}"``, ``"S_1^{-1}"``)
and printed as HTML (``<sub>``/``<sup>``) in tables and as mathtext in the plots.
Message texts use the same syntax, so a caption or a legend prints its symbols alike.
Text from users (a series' levels, an operator) is never read in that syntax or as
mathtext: :func:`plot_text` draws it as it is, :func:`spreadsheet_text` keeps a CSV cell
of it from being evaluated as a formula.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from decimal import Decimal
from typing import Any

from babel.numbers import get_decimal_symbol
from markupsafe import Markup, escape

from schemas.digits import (
    PERCENT_PLACES,
    column_places,
    count,
    is_stated,
    result_places,
    round_to_uncertainty,
    uncertainty_places,
)
from schemas.labels import Label, plain_symbol

DASH = "—"
_SUPERSCRIPT = str.maketrans("0123456789-+", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺")
_SCRIPT = re.compile(r"([_^])(\{[^}]*\}|[\w∞]+)")
_SCRIPTED = re.compile(r"([^\s_^{}$(),=·…/+-]*)((?:[_^](?:\{[^}]*\}|[\w∞]+))+)")


_LOCALE: ContextVar[str] = ContextVar("number_locale", default="en")


@contextmanager
def number_locale(lang: str) -> Iterator[None]:
    """Numbers printed by :func:`fmt` inside the block use ``lang``'s decimal sign."""
    token = _LOCALE.set(lang)
    try:
        yield
    finally:
        _LOCALE.reset(token)


def decimal_sign() -> str:
    """The decimal sign of the numbers printed now (``.`` or ``,``)."""
    return get_decimal_symbol(_LOCALE.get())


def fmt(value: float | int | None, digits: int = 4) -> str:
    """``value`` with ``digits`` significant figures: ``0.3985``, ``3.833·10⁻⁸``; ``—`` for
    none; ``0,3985`` in Russian (:func:`number_locale`).

    Fixed notation for decimal exponents -4..digits-1 (as Python's ``g``), otherwise a
    mantissa and a power of ten. Booleans are not numbers here (a verdict is printed in
    words).
    """
    if value is None or isinstance(value, bool):
        return DASH
    if not math.isfinite(value):
        return DASH
    if value == 0:
        return "0"
    text = f"{value:.{digits}g}".replace(".", decimal_sign())
    if "e" not in text:
        return text
    mantissa, exponent = text.split("e")
    return f"{mantissa}·10{str(int(exponent)).translate(_SUPERSCRIPT)}"


def fixed(value: float | None, places: int) -> str:
    """``value`` rounded to ``places`` decimals (:mod:`schemas.digits`; negative: tens,
    hundreds) in the language's decimal sign, with a power of ten below 10⁻⁴ or from 10⁶
    up (``7.7·10⁻⁵``); ``—`` for none."""
    if value is None or isinstance(value, bool) or not math.isfinite(value):
        return DASH
    return column_numbers([value], places)[0]


def column_numbers(values: Sequence[float | None], places: int) -> list[str]:
    """Numbers printed to ``places`` decimals, with one power of ten for them all when the
    largest is outside 10⁻⁴..10⁶; ``—`` for none."""
    finite = [abs(v) for v in values if v is not None and math.isfinite(v) and v != 0]
    power = 0
    if finite and not 1e-4 <= max(finite) < 1e6:
        power = math.floor(math.log10(max(finite)))
    shift = places + power  # decimals of the mantissa v/10^power
    out = []
    for v in values:
        if v is None or isinstance(v, bool) or not math.isfinite(v):
            out.append(DASH)
            continue
        scaled = float(Decimal(v).scaleb(-power))  # 10^-power overflows past 1e308
        mantissa = round(scaled, shift) if shift < 0 else scaled
        text = f"{mantissa:.{max(shift, 0)}f}"
        if float(text) == 0:
            text = text.lstrip("-")  # -0.00 is 0.00
        text = text.replace(".", decimal_sign())
        if power:
            text += f"·10{str(power).translate(_SUPERSCRIPT)}"
        out.append(text)
    return out


def percent(value: float | None) -> str:
    """A percentage to 0.1 (``-0.1`` for the issue's −0.0662 %)."""
    return fixed(value, PERCENT_PLACES)


def column(values: Sequence[float | None], digits: int = 4) -> list[str]:
    """A table column's numbers with one number of decimals (:func:`schemas.digits.
    column_places` at ``digits`` significant digits)."""
    places = column_places(values, digits)
    if places is None:
        return [fmt(v) for v in values]
    return column_numbers(values, places)


def to_uncertainty(value: float | None, uncertainty: float | None) -> str:
    """``value`` alone, rounded to the place of its ``uncertainty`` (GUM 7.2.6, the value of
    a table whose uncertainty is stated elsewhere); four significant digits without one."""
    if value is None or not is_stated(uncertainty):
        return fmt(value)
    assert uncertainty is not None
    return fixed(value, uncertainty_places(uncertainty))


def with_uncertainty(value: float | None, expanded: float | None) -> str:
    """``0.401 ± 0.012 (k = 2)``: a result and its expanded uncertainty (GUM 7.2.6: U to two
    significant digits, the value to the same place); the value alone without one."""
    if value is None or not is_stated(expanded):
        return fmt(value)
    assert expanded is not None
    *rounded, places = round_to_uncertainty(value, expanded)
    both = column_numbers(rounded, places)
    if "·10" not in both[0] and "·10" not in both[1]:
        return f"{both[0]} ± {both[1]} (k = 2)"
    mantissas = [b.split("·10")[0] for b in both]
    power = both[0].split("·10")[1] if "·10" in both[0] else both[1].split("·10")[1]
    return f"({mantissas[0]} ± {mantissas[1]})·10{power} (k = 2)"


def shown(label: Label, value: float | None, stored: str, uncertainty: float | None = None) -> str:
    """A result as its label declares it: in the display unit, 0 below its resolution
    (``e_x = 2.7·10⁻²⁰ m`` is printed ``0``); a count whole, a percentage to 0.1, a value
    with an ``uncertainty`` (stored in ``stored`` too) to its place (GUM 7.2.6), any other
    to the label's digits."""
    if value is None or isinstance(value, bool) or not math.isfinite(value):
        return fmt(value)
    places = result_places(label, value, stored, uncertainty)
    if places is None:
        return fmt(label.shown(value, stored), label.digits)
    if label.count:
        return str(count(label.displayed(value, stored)))
    return fixed(_noiseless(label, value, stored), places)


def shown_column(label: Label, values: Sequence[float | None], stored: str) -> list[str]:
    """A table column of one result (stored in ``stored``) as :func:`shown` prints it, with
    one number of decimals (:func:`schemas.digits.column_places` at the label's digits),
    0.1 for a percentage; a count whole."""
    if label.count:
        return [shown(label, v, stored) for v in values]
    numbers = [
        None
        if v is None or isinstance(v, bool) or not math.isfinite(v)
        else _noiseless(label, v, stored)
        for v in values
    ]
    places = PERCENT_PLACES if label.unit == "%" else column_places(numbers, label.digits)
    if places is None:
        return [fmt(v) for v in numbers]
    return column_numbers(numbers, places)


def _noiseless(label: Label, value: float, stored: str) -> float:
    """``value`` in the label's display unit, 0 below its resolution (rounding noise)."""
    shown_as = label.displayed(value, stored)
    return 0.0 if abs(shown_as) < label.resolution else shown_as


#: Units written against their number (an angle: ``320°``), not after a space (``23 °C``).
CLOSED_UNITS = ("°", "′", "″")


def with_unit(number: str, unit: str) -> str:
    """A number and its printed unit: ``7.1 at``, ``320°``; the number alone without one."""
    if not unit:
        return number
    return f"{number}{unit}" if unit in CLOSED_UNITS else f"{number} {unit}"


def value_text(value: Any) -> str:
    """A free-form value (specimen, test plan, configuration): numbers by :func:`fmt`,
    lists joined by commas, words as they are."""
    if isinstance(value, bool | str):
        return str(value)
    if isinstance(value, int | float):
        return fmt(value)
    if isinstance(value, Sequence):
        return ", ".join(value_text(v) for v in value)
    return str(value)


def html_symbol(symbol: str) -> Markup:
    """``"e_x"`` -> ``e<sub>x</sub>``, ``"S_1^{-1}"`` -> ``S<sub>1</sub><sup>-1</sup>``;
    ``<=`` and ``>=`` as ``≤`` and ``≥``."""
    symbol = symbol.replace("<=", "≤").replace(">=", "≥")
    out: list[str] = []
    pos = 0
    for match in _SCRIPT.finditer(symbol):
        out.append(str(escape(symbol[pos : match.start()])))
        tag = "sub" if match.group(1) == "_" else "sup"
        out.append(f"<{tag}>{escape(match.group(2).strip('{}'))}</{tag}>")
        pos = match.end()
    out.append(str(escape(symbol[pos:])))
    return Markup("".join(out))


def plain_text(text: str) -> str:
    """Text for a place that cannot hold markup (a ``<select>`` option, a canvas axis): the
    scripts in Unicode where it has them (``e_x`` -> ``eₓ``), else run on (``M_тр`` ->
    ``Mтр``), never the raw ``_`` or ``^``."""
    return re.sub(r"[_^{}]", "", plain_symbol(text))


def plot_text(text: str) -> str:
    """Text from a user, for matplotlib, drawn as written: each ``$`` escaped, so no part
    of it is parsed as mathtext (``$\\foo$`` would make the plot fail) and a label made of
    it and of :func:`tex` text shows it literally (outside a ``$...$`` pair mathtext takes
    text as it is, ``\\$`` as ``$``)."""
    return text.replace("$", r"\$")


#: What a spreadsheet takes for the start of a formula (OWASP, CSV injection).
_FORMULA_START = ("=", "+", "-", "@")
_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:[.,][0-9]*)?|[.,][0-9]+)(?:[eE][+-]?[0-9]+)?")


def spreadsheet_text(cell: str) -> str:
    """A text cell of a CSV that Excel or LibreOffice shows as text, never evaluates: one
    that starts like a formula (``=``, ``+``, ``-``, ``@``, after blanks or not) or with a
    tab or a carriage return gets a leading ``'`` (OWASP's advice against CSV injection);
    a number (``-1.5``, ``+3e-4``) and any other text are left as they are."""
    if not cell:
        return cell
    if cell[0] in "\t\r" or (
        cell.lstrip(" \t\r\n").startswith(_FORMULA_START) and not _NUMBER.fullmatch(cell)
    ):
        return "'" + cell
    return cell


def tex(text: str) -> str:
    """Text for matplotlib with each scripted symbol in mathtext: ``"f_э, fluid"`` ->
    ``"$f_{э}$, fluid"``; text without scripts is left alone."""

    def math(match: re.Match[str]) -> str:
        scripts = _SCRIPT.sub(lambda m: f"{m.group(1)}{{{m.group(2).strip('{}')}}}", match[2])
        return f"${match[1]}{scripts}$"

    return _SCRIPTED.sub(math, text)
