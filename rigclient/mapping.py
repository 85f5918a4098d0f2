"""The map of a stand's file: which column is which channel, in what unit; the constants;
the run's metadata. Written by the lab in TOML or JSON::

    stand = "smts2"            # optional: --stand wins
    group = "friction"         # optional: --group wins

    [run]
    operator = "Ivanova"
    title = "St3sp on R9, 300 N, 1000 rpm"
    specimen = { pin = "St3sp", disc = "R9" }
    test_plan = { mode = "wear" }

    [columns]                  # file column (its header, with or without the unit) -> channel
    "t" = "time"
    "F" = { channel = "load", unit = "kN" }             # converted to the channel's N
    "M" = { channel = "friction_moment", factor = 0.01 } # scale divisions -> N*m
    "comment" = ""                                      # a column left out on purpose

    [measurements]             # constants, posted once when the run opens
    pin_mass_before = 12.3456                       # in the channel's unit (g)
    disc_ra = { value = 0.32, unit = "um" }

A unit is one of the wire's units (``schemas.units``) or one of :data:`FILE_UNITS`; a factor
multiplies the file's value into the channel's unit.
"""

from __future__ import annotations

import json
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rigclient.errors import InputError
from schemas.units import UNITS

#: Units that files use and the wire does not: symbol -> (wire unit, factor to it).
FILE_UNITS: dict[str, tuple[str, float]] = {
    "kN": ("N", 1e3),
    "kgf": ("N", 9.80665),
    "kN*m": ("N*m", 1e3),
    "kgf*m": ("N*m", 9.80665),
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
    "min^-1": ("rpm", 1.0),
    "kg/cm^2": ("at", 1.0),
    "kgf/cm^2": ("at", 1.0),
    "ms": ("s", 1e-3),
    "h": ("s", 3600.0),
}


def unit_factor(source: str, target: str, *, where: str = "") -> float:
    """The factor that turns a value in ``source`` into ``target`` (same SI unit)."""
    symbol, scale = FILE_UNITS.get(source, (source, 1.0))
    if symbol not in UNITS:
        known = ", ".join([*UNITS, *FILE_UNITS])
        raise InputError(f"unknown unit {source!r}; known: {known}", column=where)
    a, b = UNITS[symbol], UNITS[target]
    if a.si != b.si:
        raise InputError(
            f"a value in {source!r} cannot be a {target!r} channel ({a.si} vs {b.si})",
            column=where,
        )
    return scale * a.factor / b.factor


@dataclass(frozen=True, slots=True)
class ColumnMap:
    """One file column: its channel ("" to leave it out), and a unit or a factor."""

    channel: str
    unit: str | None = None
    factor: float | None = None


@dataclass(frozen=True, slots=True)
class StandMap:
    """A file's map (see the module's docstring)."""

    stand: str | None = None
    group: str | None = None
    run: dict[str, Any] = field(default_factory=dict)
    columns: dict[str, ColumnMap] = field(default_factory=dict)
    measurements: dict[str, tuple[float, str | None]] = field(default_factory=dict)
    source: str = ""

    def column(self, header: str, name: str) -> ColumnMap | None:
        """The map of a header cell, by its whole text or by its name without the unit."""
        return self.columns.get(header) or self.columns.get(name)


_RUN_FIELDS = ("operator", "title", "specimen", "test_plan", "configuration", "notes")


def load_map(path: str | Path) -> StandMap:
    """Read a map from TOML (``.toml``) or JSON; :class:`InputError` names what is wrong."""
    path = Path(path)
    where = str(path)
    try:
        text = path.read_text(encoding="utf-8")
        data: Any = tomllib.loads(text) if path.suffix == ".toml" else json.loads(text)
    except OSError as exc:
        raise InputError(f"cannot read the map: {exc.strerror}", file=where) from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"not TOML: {exc}", file=where) from None
    except json.JSONDecodeError as exc:
        raise InputError(f"not JSON: {exc.msg}", file=where, line=exc.lineno) from None
    if not isinstance(data, dict):
        raise InputError("the map must be a table (an object)", file=where)
    unknown = sorted(set(data) - {"stand", "group", "run", "columns", "measurements"})
    if unknown:
        raise InputError(
            f"unknown keys {', '.join(unknown)}; a map has stand, group, run, columns, "
            "measurements",
            file=where,
        )
    run = dict(data.get("run", {}))
    extra = sorted(set(run) - set(_RUN_FIELDS))
    if extra:
        raise InputError(
            f"[run] has {', '.join(extra)}; it takes {', '.join(_RUN_FIELDS)}", file=where
        )
    columns = {str(k): _column(v, where, str(k)) for k, v in data.get("columns", {}).items()}
    measurements = {
        str(k): _constant(v, where, str(k)) for k, v in data.get("measurements", {}).items()
    }
    return StandMap(
        stand=data.get("stand"),
        group=data.get("group"),
        run=run,
        columns=columns,
        measurements=measurements,
        source=where,
    )


def _column(value: Any, where: str, name: str) -> ColumnMap:
    if isinstance(value, str):
        return ColumnMap(value)
    if not isinstance(value, dict) or not isinstance(value.get("channel"), str):
        raise InputError(
            'a column maps to a channel name or {channel = "...", unit = "..."} or '
            '{channel = "...", factor = ...}',
            file=where,
            column=name,
        )
    extra = sorted(set(value) - {"channel", "unit", "factor"})
    if extra or ("unit" in value and "factor" in value):
        raise InputError(
            "a column takes channel and either unit or factor", file=where, column=name
        )
    factor = value.get("factor")
    if factor is not None and not isinstance(factor, int | float):
        raise InputError(f"factor must be a number, got {factor!r}", file=where, column=name)
    return ColumnMap(value["channel"], value.get("unit"), None if factor is None else float(factor))


def _constant(value: Any, where: str, name: str) -> tuple[float, str | None]:
    if isinstance(value, int | float) and not isinstance(value, bool):
        return float(value), None
    if isinstance(value, dict) and isinstance(value.get("value"), int | float):
        unit = value.get("unit")
        return float(value["value"]), None if unit is None else str(unit)
    raise InputError(
        'a measurement is a number or {value = ..., unit = "..."}', file=where, column=name
    )
