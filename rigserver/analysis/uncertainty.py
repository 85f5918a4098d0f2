"""Measurement uncertainty of the headline results (GUM, JCGM 100:2008), first order.

Each input is a :class:`uncertainties.UFloat`: type B from a stand's declared limit of error a
(a rectangular distribution, u = a/√3, GUM 4.3.7) or resolution q (u = q/(2√3)), type A from
the scatter of a record. The ``uncertainties`` package carries the first-order propagation
(GUM 5.1.2, with the correlations of shared inputs such as the zero readings); the expanded
uncertainty is U = k·u with k = 2 (GUM 6.2). The tests check the partial derivatives by hand
and the first-order figure by Monte Carlo where the model is nonlinear (χ = |e|/h0).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from uncertainties import UFloat, ufloat, umath

__all__ = [
    "COVERAGE",
    "Estimate",
    "batch_mean",
    "estimate",
    "first_order",
    "from_limit",
    "from_resolution",
    "mtos_chi",
    "slide_bearing_chi_mean",
]

#: Coverage factor of the expanded uncertainty (about 95 % for a normal output).
COVERAGE = 2.0
_ROOT3 = math.sqrt(3.0)


@dataclass(frozen=True, slots=True)
class Estimate:
    """A result with its standard uncertainty u and expanded uncertainty U = k·u."""

    value: float
    standard: float
    expanded: float


def estimate(x: UFloat | float) -> Estimate:
    if isinstance(x, float | int):
        return Estimate(value=float(x), standard=0.0, expanded=0.0)
    return Estimate(value=x.nominal_value, standard=x.std_dev, expanded=COVERAGE * x.std_dev)


def first_order(make: Callable[[], UFloat | float]) -> Estimate | None:
    """The estimate of ``make()``; None where first-order propagation (GUM 5.1.2) is
    undefined: a derivative that divides by zero or overflows, or a u that is not finite
    (hypot's at the origin: χ of a centred journal)."""
    try:
        found = estimate(make())
    except ArithmeticError:
        return None
    return found if math.isfinite(found.standard) else None


def _uncertain(value: float, std: float, tag: str | None) -> UFloat:
    """A UFloat, or the exact value itself when it has no uncertainty (a declared limit of
    zero, an ideal instrument)."""
    return ufloat(value, std, tag) if std > 0 else value


def from_limit(value: float, limit: float, tag: str | None = None) -> UFloat:
    """A reading whose error lies within ±limit, uniformly: u = limit/√3 (GUM 4.3.7)."""
    return _uncertain(value, abs(limit) / _ROOT3, tag)


def from_resolution(value: float, step: float, tag: str | None = None) -> UFloat:
    """A reading rounded to ``step``: u = step/(2√3) (GUM F.2.2.1)."""
    return _uncertain(value, abs(step) / (2.0 * _ROOT3), tag)


def _magnitude(x: UFloat) -> UFloat:
    """|x| to first order (the sign of its value; ``abs`` of a UFloat is deprecated)."""
    value = x if isinstance(x, float | int) else x.nominal_value
    return x if value >= 0 else -x


def batch_mean(values: Sequence[float], batches: int = 20) -> UFloat:
    """The mean of a correlated record with its type A uncertainty by batch means: the
    standard deviation of ``batches`` consecutive batch means over √batches (a record's
    neighbouring rows are correlated, so s/√n would understate it)."""
    v = np.asarray(values, dtype=np.float64)
    n = max(2, min(batches, v.size))
    means = np.array([part.mean() for part in np.array_split(v, n)])
    return _uncertain(float(v.mean()), float(means.std(ddof=1) / math.sqrt(n)), "record")


def slide_bearing_chi_mean(
    *,
    x: Sequence[float],
    y: Sequence[float],
    x_zero: float,
    y_zero: float,
    per_division: float,
    limit_divisions: float,
    clearance: float,
    clearance_limit: float,
) -> UFloat:
    """χ_ср (3.16)-(3.17), (3.23) with each gauge reading and h0 uncertain; the zero readings
    are shared by every row, so their errors do not average out."""
    x0 = from_limit(x_zero, limit_divisions, "X_zero")
    y0 = from_limit(y_zero, limit_divisions, "Y_zero")
    h0 = from_limit(clearance, clearance_limit, "h0")
    chis = []
    for xi, yi in zip(x, y, strict=True):
        e_x = h0 - _magnitude(x0 - from_limit(xi, limit_divisions)) * per_division
        e_y = h0 - _magnitude(y0 - from_limit(yi, limit_divisions)) * per_division
        chis.append(umath.hypot(e_x, e_y) / h0)
    return sum(chis) / len(chis)


def mtos_chi(
    *,
    x: float,
    y: float,
    x_zero: UFloat,
    y_zero: UFloat,
    limit: float,
    clearance: UFloat,
    signed: bool,
) -> UFloat:
    """χ of one MTOS step (4.11); pass the same zero readings and h0 to every step."""
    offset = clearance * math.cos(math.pi / 4.0)
    dx, dy = from_limit(x, limit) - x_zero, from_limit(y, limit) - y_zero
    e_x = offset - (dx if signed else _magnitude(dx))
    e_y = offset - (dy if signed else _magnitude(dy))
    return umath.hypot(e_x, e_y) / clearance
