"""Argument checks shared by the model library; messages name the argument, value and limit."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rigserver.core.errors import ModelInputError


def finite(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """Return ``value`` as a float array, refusing NaN and infinities."""
    arr = np.asarray(value, dtype=np.float64)
    if not np.all(np.isfinite(arr)):
        bad = arr[~np.isfinite(arr)].flat[0]
        raise ModelInputError(f"{name} must be finite, got {bad}")
    return arr


def positive(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """Return ``value`` as a float array, refusing values <= 0."""
    arr = finite(name, value)
    if np.any(arr <= 0):
        raise ModelInputError(f"{name} must be > 0, got {arr[arr <= 0].flat[0]}")
    return arr


def non_negative(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """Return ``value`` as a float array, refusing values < 0."""
    arr = finite(name, value)
    if np.any(arr < 0):
        raise ModelInputError(f"{name} must be >= 0, got {arr[arr < 0].flat[0]}")
    return arr


def within(
    name: str,
    value: ArrayLike,
    low: float,
    high: float,
    *,
    closed: tuple[bool, bool] = (True, True),
) -> NDArray[np.float64]:
    """Return ``value`` as a float array, refusing values outside ``low .. high``.

    ``closed`` says whether each end is allowed; the message prints the interval.
    """
    arr = finite(name, value)
    lo_ok = arr >= low if closed[0] else arr > low
    hi_ok = arr <= high if closed[1] else arr < high
    ok = lo_ok & hi_ok
    if not np.all(ok):
        left = "[" if closed[0] else "("
        right = "]" if closed[1] else ")"
        raise ModelInputError(
            f"{name} must lie in {left}{low}, {high}{right}, got {arr[~ok].flat[0]}"
        )
    return arr


def one_of(name: str, value: str, allowed: Iterable[str]) -> str:
    """Return ``value`` if it is one of ``allowed``, else raise naming the choices."""
    choices = tuple(allowed)
    if value not in choices:
        listed = ", ".join(map(repr, choices))
        raise ModelInputError(f"{name} must be one of {listed}, got {value!r}")
    return value
