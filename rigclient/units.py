"""The units that files write, turned into a channel's unit.

A unit is one of the wire's (:data:`schemas.units.UNITS`), one of :data:`FILE_UNITS` (the
spellings of vendors' and Russian exports), or a product and quotient of those
(``gf*mm``, ``mm/min``, ``kgf/mm^2``, ``N·cm``, ``rev/s``): each factor a known unit with an
optional power (``^2``, ``²``), joined by ``*``, ``·`` or ``/``. Two units convert when their
dimensions (in newtons, metres, seconds, kilograms, radians, degrees Celsius) are the same;
a revolution is 2π rad, a pascal N/m², a hertz 1/s.

An instrument that weighs its forces writes them in grams (CETR/Bruker UMT: ``g`` in its
units line): a unit of mass on a channel of force is read as the force of that mass
(gram-force, g0 = 9.80665 m/s², the standard acceleration of gravity, CGPM 1901).
"""

from __future__ import annotations

import math
import re
from collections import Counter

from rigclient.errors import InputError
from schemas.units import UNITS

#: The standard acceleration of gravity, m/s² (3rd CGPM, 1901): 1 gf = 9.80665e-3 N.
G0 = 9.80665

#: Units that files use and the wire does not: symbol -> (unit, factor to it).
FILE_UNITS: dict[str, tuple[str, float]] = {
    "kN": ("N", 1e3),
    "mN": ("N", 1e-3),
    "gf": ("N", G0 * 1e-3),
    "kgf": ("N", G0),
    "kN*m": ("N*m", 1e3),
    "kgf*m": ("N*m", G0),
    "N*mm": ("N*m", 1e-3),
    "kPa": ("Pa", 1e3),
    "bar": ("Pa", 1e5),
    "cm": ("m", 1e-2),
    "nm": ("m", 1e-9),
    "µm": ("um", 1.0),
    "μm": ("um", 1.0),
    "mkm": ("um", 1.0),
    "°C": ("degC", 1.0),
    "C": ("degC", 1.0),
    "°": ("deg", 1.0),
    "rev/min": ("rpm", 1.0),
    "r/min": ("rpm", 1.0),
    "min^-1": ("rpm", 1.0),
    "kg/cm^2": ("at", 1.0),
    "kgf/cm^2": ("at", 1.0),
    "ms": ("s", 1e-3),
    "sec": ("s", 1.0),
    "h": ("s", 3600.0),
    "GPa": ("Pa", 1e9),
    "N/mm^2": ("MPa", 1.0),
    "N·m": ("N*m", 1.0),
    "Nm": ("N*m", 1.0),
    "g/cm^3": ("kg/m^3", 1e3),
    # Russian exports (ГОСТ 8.417 symbols)
    "с": ("s", 1.0),
    "мин": ("min", 1.0),
    "ч": ("s", 3600.0),
    "Н": ("N", 1.0),
    "кН": ("N", 1e3),
    "Н·м": ("N*m", 1.0),
    "Н*м": ("N*m", 1.0),
    "м": ("m", 1.0),
    "см": ("m", 1e-2),
    "мм": ("mm", 1.0),
    "мкм": ("um", 1.0),
    "г": ("g", 1.0),
    "мг": ("mg", 1.0),
    "кг": ("kg", 1.0),
    "°С": ("degC", 1.0),  # with a Cyrillic С
    "об/мин": ("rpm", 1.0),
    "Па": ("Pa", 1.0),
    "МПа": ("MPa", 1.0),
    "ГПа": ("Pa", 1e9),
}

#: The units every other one is a multiple of, with the dimensions they stand for.
_BASE: dict[str, tuple[float, dict[str, int]]] = {
    "1": (1.0, {}),
    "N": (1.0, {"N": 1}),
    "m": (1.0, {"m": 1}),
    "s": (1.0, {"s": 1}),
    "kg": (1.0, {"kg": 1}),
    "rad": (1.0, {"rad": 1}),
    "rev": (2.0 * math.pi, {"rad": 1}),
    "Pa": (1.0, {"N": 1, "m": -2}),
    "Hz": (1.0, {"s": -1}),
    "degC": (1.0, {"degC": 1}),
}
_POWERS = str.maketrans({"²": "^2", "³": "^3", "⁻": "^-", "¹": "1"})
_TERM = re.compile(r"\s*([*·/])?\s*([^*·/^\s]+)(?:\^([+-]?\d+))?\s*")

Dimension = tuple[float, Counter[str]]


def dimension(symbol: str, *, depth: int = 0) -> Dimension | None:
    """A unit as its factor and dimensions (None if it is not known)."""
    if depth > 8:
        return None
    if symbol in _BASE:
        factor, dims = _BASE[symbol]
        return factor, Counter(dims)
    if symbol in FILE_UNITS:
        wire, scale = FILE_UNITS[symbol]
        found = dimension(wire, depth=depth + 1)
        return None if found is None else (scale * found[0], found[1])
    if symbol in UNITS and UNITS[symbol].si != symbol:
        unit = UNITS[symbol]
        found = dimension(unit.si, depth=depth + 1)
        return None if found is None else (unit.factor * found[0], found[1])
    return _product(symbol, depth)


def _product(text: str, depth: int) -> Dimension | None:
    """``a*b/c^2``: each term a known unit (none of them a product again)."""
    text = text.translate(_POWERS)
    if "(" in text:
        return None
    factor, dims, at = 1.0, Counter[str](), 0
    terms = 0
    while at < len(text):
        found = _TERM.match(text, at)
        if found is None or found.end() == at or (terms and found[1] is None):
            return None
        op, name, power = found[1], found[2], int(found[3] or 1)
        if terms == 0 and op is not None:
            return None
        if op == "/":
            power = -power
        if name in ("*", "·", "/") or (name == text and power == 1):
            return None  # a single unknown name: not a product
        part = dimension(name, depth=depth + 1)
        if part is None:
            return None
        factor *= part[0] ** power
        for key, n in part[1].items():
            dims[key] += n * power
        at, terms = found.end(), terms + 1
    return (factor, _nonzero(dims)) if terms else None


def known_units() -> str:
    """The units a map may name, for a message."""
    return ", ".join([*UNITS, *FILE_UNITS]) + " and their products and quotients (gf*mm, mm/min)"


def unit_factor(source: str, target: str, *, where: str = "") -> float:
    """The factor that turns a value in ``source`` into ``target``; :class:`InputError`
    names an unknown unit, or one of another quantity."""
    source = source.strip()
    found, wanted = dimension(source), dimension(target)
    if found is None or wanted is None:  # a unit of its own kind (div, code, drops/min)
        symbol, scale = FILE_UNITS.get(source, (source, 1.0))
        if symbol not in UNITS:
            raise InputError(f"unknown unit {source!r}; known: {known_units()}", column=where)
        a, b = UNITS[symbol], UNITS[target]
        if a.si != b.si:
            raise InputError(
                f"a value in {source!r} cannot be a {target!r} channel ({a.si} vs {b.si})",
                column=where,
            )
        return scale * a.factor / b.factor
    factor, dims = found
    if dims != wanted[1] and _as_force(dims) == wanted[1]:
        factor, dims = factor * G0, wanted[1]  # grams on a force channel: gram-force
    if dims != wanted[1]:
        si = UNITS[target].si if target in UNITS else target
        raise InputError(
            f"a value in {source!r} cannot be a {target!r} channel ({_text(dims)} vs {si})",
            column=where,
        )
    return factor / wanted[0]


def _as_force(dims: Counter[str]) -> Counter[str]:
    """The dimensions of a mass's weight (kg -> N), else none."""
    if dims.get("kg") != 1:
        return Counter()
    out = Counter(dims)
    del out["kg"]
    out["N"] += 1
    return _nonzero(out)


def _nonzero(dims: Counter[str]) -> Counter[str]:
    return Counter({k: n for k, n in dims.items() if n})


def _text(dims: Counter[str]) -> str:
    return "*".join(k if n == 1 else f"{k}^{n}" for k, n in sorted(dims.items())) or "1"
