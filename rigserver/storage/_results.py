"""The stored form of a run's analysis results.

The results are any JSON-able mapping; the analysis sends ``schemas.results``' wire form::

    {"stand": ..., "values": {...nested values...}, "units": {path: unit}}

where a path names a quantity of ``values``: dots for nested objects, ``[]`` for a list of
objects (``"experimental.intensity"``, ``"rows[].chi"``). The stores keep the mapping as
JSON text, and the run file also gets one float64 dataset per path of ``units`` that
resolves to a number or a rectangular array of numbers (a ``[]`` path gives the column of
that field over the list, None as NaN), at ``values/<path with "/" for "." and no "[]">``
with that ``@units``; anything else (text, flags, quantities without a unit) is in the
JSON only. So every numeric dataset of the results carries its unit.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True, slots=True)
class ResultArray:
    """One numeric quantity of the results: values, unit symbol, and its path in ``units``."""

    values: NDArray[np.float64]
    unit: str
    path: str


@dataclass(frozen=True, slots=True)
class CheckedResults:
    """Results ready to store.

    Attributes
    ----------
    text : str
        The results as JSON.
    key_results : dict of str to float
        The headline figures, all finite.
    arrays : dict of str to ResultArray
        Dataset path under ``/entry/results`` -> the quantity.
    """

    text: str
    key_results: dict[str, float]
    arrays: dict[str, ResultArray]


def check_results(results: Mapping[str, Any], key_results: Mapping[str, float]) -> CheckedResults:
    """The results as stored; ``ValueError`` if not JSON-able or a key result not finite."""
    try:
        text = json.dumps(results, ensure_ascii=False, sort_keys=True)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"the results must be JSON-able: {exc}") from exc
    keys: dict[str, float] = {}
    for name, value in key_results.items():
        number = float(value)
        if not math.isfinite(number):
            raise ValueError(f"key result {name!r} = {number} is not a finite number")
        keys[str(name)] = number
    return CheckedResults(text=text, key_results=keys, arrays=_arrays(json.loads(text)))


def _arrays(results: Any) -> dict[str, ResultArray]:
    values = results.get("values") if isinstance(results, dict) else None
    units = results.get("units") if isinstance(results, dict) else None
    if not isinstance(values, dict) or not isinstance(units, dict):
        return {}
    found: dict[str, ResultArray] = {}
    for path, unit in units.items():
        parts = str(path).split(".")
        names = [p.removesuffix("[]") for p in parts]
        if not isinstance(unit, str) or any(not n or "/" in n or n == "." for n in names):
            continue
        array = _numeric(_resolve(values, parts))
        if array is not None:
            found["values/" + "/".join(names)] = ResultArray(array, unit, str(path))
    return found


_MISSING = object()


def _resolve(node: Any, parts: list[str]) -> Any:
    if not parts:
        return node
    key = parts[0].removesuffix("[]")
    if not isinstance(node, dict) or key not in node:
        return _MISSING
    child = node[key]
    if parts[0].endswith("[]"):
        if not isinstance(child, list):
            return _MISSING
        return [_resolve(item, parts[1:]) for item in child]
    return _resolve(child, parts[1:])


def _numeric(value: Any) -> NDArray[np.float64] | None:
    """A number or rectangular numeric array (None inside as NaN); else ``None``."""
    if value is None or not _all_numbers(value):
        return None
    try:
        return np.asarray(value, dtype=np.float64)
    except ValueError:  # ragged
        return None


def _all_numbers(value: Any) -> bool:
    if isinstance(value, list):
        return all(v is None or _all_numbers(v) for v in value)
    return isinstance(value, int | float) and not isinstance(value, bool)
