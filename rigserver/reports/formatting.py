"""How numbers and symbols are printed in the reports and pages.

Numbers carry four significant figures (``fmt``), or the digits a result is declared with
(:class:`schemas.labels.Label`, :func:`shown`); a power of ten is printed as ``·10ⁿ``; the
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
from typing import Any

from babel.numbers import get_decimal_symbol
from markupsafe import Markup, escape

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


def with_uncertainty(value: float | None, expanded: float | None) -> str:
    """``0.401 ± 0.012 (k = 2)``: a result and its expanded uncertainty (GUM), the value
    rounded to the uncertainty's second significant figure; the value alone without one."""
    if value is None or expanded is None or not math.isfinite(expanded) or expanded <= 0:
        return fmt(value)
    places = 1 - math.floor(math.log10(expanded))
    if -4 <= math.floor(math.log10(abs(value) or expanded)) <= 3 and places >= 0:
        text = f"{value:.{places}f} ± {expanded:.{places}f} (k = 2)"
    else:
        scale = 10.0 ** math.floor(math.log10(abs(value) or expanded))
        digits = max(0, places + math.floor(math.log10(scale)))
        power = str(int(math.log10(scale))).translate(_SUPERSCRIPT)
        text = f"({value / scale:.{digits}f} ± {expanded / scale:.{digits}f})·10{power} (k = 2)"
    return text.replace(".", decimal_sign())


def shown(label: Label, value: float | None, stored: str) -> str:
    """A result as its label declares it: in the display unit, to its digits, 0 below its
    resolution (``e_x = 2.7·10⁻²⁰ m`` is printed ``0``)."""
    if value is None or isinstance(value, bool) or not math.isfinite(value):
        return fmt(value)
    return fmt(label.shown(value, stored), label.digits)


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
