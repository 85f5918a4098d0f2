"""How numbers and symbols are printed in the reports and pages.

Numbers carry four significant figures (``fmt``); a power of ten is printed as ``·10ⁿ``.
Symbols are written once in a small TeX-like syntax (``"Π_э"``, ``"t_{pэ}"``, ``"S_1^{-1}"``)
and printed as HTML (``<sub>``/``<sup>``) in tables and as mathtext in the plots.
Message texts use the same syntax, so a caption or a legend prints its symbols alike.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

from markupsafe import Markup, escape

DASH = "—"
_SUPERSCRIPT = str.maketrans("0123456789-+", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺")
_SCRIPT = re.compile(r"([_^])(\{[^}]*\}|[\w∞]+)")
_SCRIPTED = re.compile(r"([^\s_^{}$(),=·…/+-]*)((?:[_^](?:\{[^}]*\}|[\w∞]+))+)")


def fmt(value: float | int | None) -> str:
    """``value`` with four significant figures: ``0.3985``, ``3.833·10⁻⁸``; ``—`` for none.

    Fixed notation for decimal exponents -4..3 (as Python's ``.4g``), otherwise a mantissa
    and a power of ten. Booleans are not numbers here (a verdict is printed in words).
    """
    if value is None or isinstance(value, bool):
        return DASH
    if not math.isfinite(value):
        return DASH
    if value == 0:
        return "0"
    text = f"{value:.4g}"
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
        return f"{value:.{places}f} ± {expanded:.{places}f} (k = 2)"
    scale = 10.0 ** math.floor(math.log10(abs(value) or expanded))
    digits = max(0, places + math.floor(math.log10(scale)))
    power = str(int(math.log10(scale))).translate(_SUPERSCRIPT)
    return f"({value / scale:.{digits}f} ± {expanded / scale:.{digits}f})·10{power} (k = 2)"


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


def pairs(mapping: Mapping[str, Any]) -> str:
    """``pin: St3sp; disc: R9``."""
    return "; ".join(f"{k}: {value_text(v)}" for k, v in mapping.items())


def html_symbol(symbol: str) -> Markup:
    """``"e_x"`` -> ``e<sub>x</sub>``, ``"S_1^{-1}"`` -> ``S<sub>1</sub><sup>-1</sup>``."""
    out: list[str] = []
    pos = 0
    for match in _SCRIPT.finditer(symbol):
        out.append(str(escape(symbol[pos : match.start()])))
        tag = "sub" if match.group(1) == "_" else "sup"
        out.append(f"<{tag}>{escape(match.group(2).strip('{}'))}</{tag}>")
        pos = match.end()
    out.append(str(escape(symbol[pos:])))
    return Markup("".join(out))


def tex(text: str) -> str:
    """Text for matplotlib with each scripted symbol in mathtext: ``"f_э, fluid"`` ->
    ``"$f_{э}$, fluid"``; text without scripts is left alone."""

    def math(match: re.Match[str]) -> str:
        scripts = _SCRIPT.sub(lambda m: f"{m.group(1)}{{{m.group(2).strip('{}')}}}", match[2])
        return f"${match[1]}{scripts}$"

    return _SCRIPTED.sub(math, text)
