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

    [run.configuration]        # the stand's configuration for this run, units allowed
    disc_radius = { value = 22.5, unit = "mm" }     # -> 0.0225 m, the field's unit

    [measurements]             # constants, posted once when the run opens
    pin_mass_before = 12.3456                       # in the channel's unit (g)
    disc_ra = { value = 0.32, unit = "um" }

    [constants]                # a channel the file lacks: this value in every row
    load = { value = 0.3, unit = "kN" }

    [file]                     # the file's dialect, where detection is not enough
    encoding = "cp1251"        # utf-8 (with or without a BOM), cp1251, utf-16 (by its BOM)
    delimiter = "tab"          # tab, semicolon, comma, spaces
    decimal = ","              # "," or "."
    header = 12                # the header's line number; the lines before it: the preamble

    [profile]                  # a profilometer's export: the profile it holds
    kind = "roughness"         # "primary" (filtered by rig) or "roughness" (the instrument's)
    lambda_c = { value = 0.8, unit = "mm" }         # the instrument's λc, λs as it states
    lambda_s = { value = 2.5, unit = "um" }
    sections = 5               # sampling lengths of the evaluation length

A unit is one of the wire's units (``schemas.units``) or one of :data:`FILE_UNITS`; a factor
multiplies the file's value into the channel's unit. A header cell is found in
``[columns]`` by its whole text, by its name without the unit, or by either with case,
blanks and the micro sign's spelling set aside (:func:`name_key`).
"""

from __future__ import annotations

import json
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rigclient.dialect import FileSettings, delimiter_of, encoding_of, name_key
from rigclient.errors import InputError
from schemas.quantity import unit_paths
from schemas.stands import CONFIG_MODELS, StandKind
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


def unit_factor(source: str, target: str, *, where: str = "") -> float:
    """The factor that turns a value in ``source`` into ``target`` (same SI unit)."""
    source = source.strip()
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
    constants: dict[str, tuple[float, str | None]] = field(default_factory=dict)
    file: FileSettings = field(default_factory=FileSettings)
    source: str = ""

    def column(self, header: str, name: str) -> ColumnMap | None:
        """The map of a header cell, by its whole text or by its name without the unit
        (as written, else by :func:`name_key`)."""
        found = self.columns.get(header) or self.columns.get(name)
        if found is not None:
            return found
        keys = {name_key(k): v for k, v in self.columns.items()}
        return keys.get(name_key(header)) or keys.get(name_key(name))


_RUN_FIELDS = ("operator", "title", "specimen", "test_plan", "configuration", "notes")
_KEYS = ("stand", "group", "run", "columns", "measurements", "constants", "file", "profile")
#: The ``[profile]`` table's keys -> the profilometer's configuration fields.
PROFILE_FIELDS = {
    "kind": "profile_kind",
    "lambda_c": "lambda_c",
    "lambda_s": "lambda_s",
    "sections": "sections",
}


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
    unknown = sorted(set(data) - set(_KEYS))
    if unknown:
        raise InputError(
            f"unknown keys {', '.join(unknown)}; a map has {', '.join(_KEYS)}", file=where
        )
    run = dict(data.get("run", {}))
    extra = sorted(set(run) - set(_RUN_FIELDS))
    if extra:
        raise InputError(
            f"[run] has {', '.join(extra)}; it takes {', '.join(_RUN_FIELDS)}", file=where
        )
    if "profile" in data:
        run["configuration"] = _profile(data["profile"], dict(run.get("configuration", {})), where)
    columns = {str(k): _column(v, where, str(k)) for k, v in data.get("columns", {}).items()}
    measurements = {
        str(k): _constant(v, where, str(k)) for k, v in data.get("measurements", {}).items()
    }
    constants = {str(k): _constant(v, where, str(k)) for k, v in data.get("constants", {}).items()}
    return StandMap(
        stand=data.get("stand"),
        group=data.get("group"),
        run=run,
        columns=columns,
        measurements=measurements,
        constants=constants,
        file=_file(data.get("file", {}), where),
        source=where,
    )


def _file(value: Any, where: str) -> FileSettings:
    if not isinstance(value, dict):
        raise InputError("[file] must be a table", file=where)
    extra = sorted(set(value) - {"encoding", "delimiter", "decimal", "header"})
    if extra:
        raise InputError(
            f"[file] has {', '.join(extra)}; it takes encoding, delimiter, decimal, header",
            file=where,
        )
    encoding, delimiter = value.get("encoding"), value.get("delimiter")
    decimal, header = value.get("decimal"), value.get("header")
    try:
        if encoding is not None:
            encoding = encoding_of(b"", str(encoding)).codec
        if delimiter is not None:
            delimiter_of(str(delimiter))
    except InputError as exc:
        raise InputError(str(exc), file=where, column="file") from None
    if decimal not in (None, ".", ","):
        raise InputError(f'[file] decimal is "." or ",", not {decimal!r}', file=where)
    if header is not None and (isinstance(header, bool) or not isinstance(header, int)):
        raise InputError(f"[file] header is a line number, not {header!r}", file=where)
    if header is not None and header < 1:
        raise InputError(f"[file] header is a line number from 1, not {header}", file=where)
    return FileSettings(encoding, None if delimiter is None else str(delimiter), decimal, header)


def _profile(value: Any, into: dict[str, Any], where: str) -> dict[str, Any]:
    """``[profile]`` as the profilometer's configuration fields (:data:`PROFILE_FIELDS`),
    added to ``[run.configuration]``, which must not set them too."""
    if not isinstance(value, dict):
        raise InputError("[profile] must be a table", file=where)
    extra = sorted(set(value) - set(PROFILE_FIELDS))
    if extra:
        raise InputError(
            f"[profile] has {', '.join(extra)}; it takes {', '.join(PROFILE_FIELDS)}",
            file=where,
        )
    if value.get("kind", "primary") not in ("primary", "roughness"):
        raise InputError(
            f'[profile] kind is "primary" or "roughness", not {value["kind"]!r}', file=where
        )
    for key, name in PROFILE_FIELDS.items():
        if key not in value:
            continue
        if name in into:
            raise InputError(
                f"[profile] {key} and [run.configuration] {name} both set it: keep one",
                file=where,
                column=name,
            )
        into[name] = value[key]
    return into


def configuration(kind: str, given: dict[str, Any], *, where: str = "") -> dict[str, Any]:
    """The map's ``[run.configuration]`` with every ``{value, unit}`` converted to its
    field's unit (``schemas.stands``: ``disc_radius`` is in m)."""
    try:
        model = CONFIG_MODELS[StandKind(kind)]
    except (ValueError, KeyError):
        return given
    units = unit_paths(model)
    return _converted(given, units, "", where)


def _converted(
    given: dict[str, Any], units: dict[str, str], prefix: str, where: str
) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in given.items():
        path = f"{prefix}{key}"
        if isinstance(value, dict) and "value" in value and set(value) <= {"value", "unit"}:
            number, unit = _constant(value, where, path)
            if unit is not None:
                if path not in units:
                    raise InputError(
                        f"configuration {path!r} has no unit to convert {unit!r} to",
                        file=where,
                        column=path,
                    )
                number *= unit_factor(unit, units[path], where=f"configuration {path}")
            out[key] = number
        elif isinstance(value, dict):
            out[key] = _converted(value, units, f"{path}.", where)
        else:
            out[key] = value
    return out


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
    if isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value):
        return float(value), None
    number = value.get("value") if isinstance(value, dict) else None
    if (
        isinstance(number, int | float)
        and not isinstance(number, bool)
        and math.isfinite(number)
        and set(value) <= {"value", "unit"}
    ):
        unit = value.get("unit")
        return float(number), None if unit is None else str(unit)
    raise InputError(
        'a constant is a finite number or {value = ..., unit = "..."}', file=where, column=name
    )
