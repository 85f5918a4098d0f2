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
    "Fz" = { channel = "normal_load", unit = "gf", factor = -1 }  # -value gf -> N
    "T" = { channel = "temperature", offset = -273.15, unit = "degC" }  # K -> °C
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
    continue_time = true       # a time that restarts (each step, block, file) goes on

    [profile]                  # a profilometer's export: the profile it holds
    kind = "roughness"         # "primary" (filtered by rig) or "roughness" (the instrument's)
    lambda_c = { value = 0.8, unit = "mm" }         # the instrument's λc, λs as it states
    lambda_s = { value = 2.5, unit = "um" }
    sections = 5               # sampling lengths of the evaluation length

A column's value is the file's value × ``factor`` + ``offset`` (1 and 0 unless given), in
its ``unit``: the map's, else the header's or the units line's, else the channel's; then
converted to the channel's unit (:mod:`rigclient.units`). A header cell is found in
``[columns]`` by its whole text, by its name without the unit, or by either with case,
blanks and the micro sign's spelling set aside (:func:`name_key`).

The map is read through :class:`MapModel`: every mistake is one line naming its key
(``columns.Fz.factor: Input should be a valid number, got 'x'``); JSON and TOML nested
deeper than :data:`rigclient.jsontext.MAX_DEPTH` levels are refused.
"""

from __future__ import annotations

import json
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    StringConstraints,
    ValidationError,
)

from rigclient.dialect import FileSettings, delimiter_of, encoding_of, name_key
from rigclient.errors import InputError
from rigclient.jsontext import DuplicateKey, TooDeep, loads_json, loads_toml
from rigclient.units import unit_factor
from schemas.quantity import unit_paths
from schemas.stands import DECLARATIONS, StandKind, default_stands, with_overrides
from schemas.wire import PlanValue, Scalar

#: The start of the line of a run's notes that says how its map read the file.
MAP_NOTE = "Read with the map: "


@dataclass(frozen=True, slots=True)
class ColumnMap:
    """One file column: its channel ("" to leave it out); its value is the file's × factor +
    offset, in ``unit`` (None: the header's, else the channel's)."""

    channel: str
    unit: str | None = None
    factor: float = 1.0
    offset: float = 0.0


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

    def describe(self) -> str:
        """How the map reads a file, in a line of the run's notes (its columns, constants
        and time; not its file name): a corrected map for a file imported before is told
        from the map of that import by it."""
        parts = []
        for name, c in sorted(self.columns.items()):
            how = c.channel or "left out"
            if c.unit is not None:
                how += f" in {c.unit}"
            if c.factor != 1.0:
                how += f" × {c.factor:g}"
            if c.offset != 0.0:
                how += f" + {c.offset:g}"
            parts.append(f"{name} → {how}")
        for name, (value, unit) in sorted(self.constants.items()):
            parts.append(f"{name} = {value:g}{f' {unit}' if unit else ''}")
        if self.file.continue_time:
            parts.append("time continued at each restart")
        return f"{MAP_NOTE}{'; '.join(parts)}" if parts else ""

    def column(self, header: str, name: str) -> ColumnMap | None:
        """The map of a header cell, by its whole text or by its name without the unit
        (as written, else by :func:`name_key`)."""
        found = self.columns.get(header) or self.columns.get(name)
        if found is not None:
            return found
        keys = {name_key(k): v for k, v in self.columns.items()}
        return keys.get(name_key(header)) or keys.get(name_key(name))


# --- the map's model: what each key takes ----------------------------------------------

_Finite = Annotated[float, Field(strict=True, allow_inf_nan=False)]
_Name = Annotated[str, StringConstraints(max_length=200)]


def _table_of(key: str) -> Any:
    """A plain value where a table may be: ``"time"`` is ``{channel = "time"}``, ``5`` is
    ``{value = 5}``."""

    def lift(value: Any) -> Any:
        if isinstance(value, str) and key == "channel":
            return {"channel": value}
        if isinstance(value, int | float) and not isinstance(value, bool) and key == "value":
            return {"value": value}
        return value

    return BeforeValidator(lift)


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, frozen=True)


class ColumnModel(_Strict):
    """A column: ``"channel"`` or ``{channel, unit, factor, offset}``."""

    channel: _Name
    unit: _Name | None = None
    factor: _Finite = 1.0
    offset: _Finite = 0.0


class ConstantModel(_Strict):
    """A constant: a finite number, or ``{value, unit}``."""

    value: _Finite
    unit: _Name | None = None


class FileModel(_Strict):
    """The ``[file]`` table: the file's dialect where detection is not enough."""

    encoding: _Name | None = None
    delimiter: _Name | None = None
    decimal: Literal[".", ","] | None = None
    header: Annotated[int, Field(ge=1)] | None = None
    continue_time: bool = False


class RunModel(_Strict):
    """The ``[run]`` table: the run's opening (:class:`schemas.runs.RunCreate`)."""

    operator: _Name | None = None
    title: _Name | None = None
    specimen: dict[_Name, Scalar] = Field(default_factory=dict)
    test_plan: dict[_Name, PlanValue] = Field(default_factory=dict)
    configuration: dict[_Name, Any] = Field(default_factory=dict)
    notes: Annotated[str, StringConstraints(max_length=5000)] | None = None


class ProfileModel(_Strict):
    """The ``[profile]`` table: the profile a profilometer's export holds."""

    kind: Literal["primary", "roughness"] = "primary"
    lambda_c: _Finite | dict[_Name, _Finite | _Name] | None = None
    lambda_s: _Finite | dict[_Name, _Finite | _Name] | None = None
    sections: Annotated[int, Field(ge=1, le=1000)] | None = None


class MapModel(_Strict):
    """A map (see the module's docstring)."""

    stand: _Name | None = None
    group: _Name | None = None
    run: RunModel = Field(default_factory=RunModel)
    columns: dict[str, Annotated[ColumnModel, _table_of("channel")]] = Field(default_factory=dict)
    measurements: dict[str, Annotated[ConstantModel, _table_of("value")]] = Field(
        default_factory=dict
    )
    constants: dict[str, Annotated[ConstantModel, _table_of("value")]] = Field(default_factory=dict)
    file: FileModel = Field(default_factory=FileModel)
    profile: ProfileModel | None = None


#: What a table of the map takes, for the message about a key it does not.
_TAKES: dict[str, type[BaseModel]] = {
    "": MapModel,
    "run": RunModel,
    "file": FileModel,
    "profile": ProfileModel,
    "columns": ColumnModel,
    "measurements": ConstantModel,
    "constants": ConstantModel,
}
_EXPECTED = {
    "columns": 'a channel name or {channel = "...", unit = "...", factor = ..., offset = ...}',
    "measurements": 'a finite number or {value = ..., unit = "..."}',
    "constants": 'a finite number or {value = ..., unit = "..."}',
}


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _mistake(error: Any) -> str:
    """One pydantic error as ``key.path: what is wrong``."""
    loc = [str(p) for p in error["loc"]]
    path = ".".join(loc) or "(the map)"
    if error["type"] == "extra_forbidden":
        parent = loc[:-1]
        model = _TAKES.get(parent[0] if parent else "")
        if len(parent) > (2 if parent and parent[0] in _EXPECTED else 1):
            model = None
        if model is None:
            return f"{path}: not a key there"
        table = f"the map's [{parent[0]}]" if parent else "the map"
        return f"{path}: not a key of {table}; it takes {', '.join(model.model_fields)}"
    if len(loc) == 2 and loc[0] in _EXPECTED and error["type"] in ("model_type", "dict_type"):
        return f"{path}: must be {_EXPECTED[loc[0]]}, got {_shown(error['input'])}"
    if error["type"] in ("model_type", "dict_type"):
        return f"{path}: must be a table, got {_shown(error['input'])}"
    text = f"{path}: {error['msg']}"
    if error["type"].endswith("_type") or error["type"] in ("literal_error", "finite_number"):
        text += f", got {_shown(error['input'])}"
    return text


#: The ``[profile]`` table's keys -> the profilometer's configuration fields.
PROFILE_FIELDS = {
    "kind": "profile_kind",
    "lambda_c": "lambda_c",
    "lambda_s": "lambda_s",
    "sections": "sections",
}


def load_map(path: str | Path) -> StandMap:
    """Read a map from TOML (``.toml``) or JSON; :class:`InputError` names what is wrong
    (the key, on one line)."""
    path = Path(path)
    where = str(path)
    try:
        text = path.read_text(encoding="utf-8")
        data: Any = loads_toml(text) if path.suffix == ".toml" else loads_json(text)
    except OSError as exc:
        raise InputError(f"cannot read the map: {exc.strerror}", file=where) from None
    except UnicodeDecodeError as exc:
        raise InputError(f"not UTF-8 text ({exc.reason} at byte {exc.start})", file=where) from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"not TOML: {exc}", file=where) from None
    except json.JSONDecodeError as exc:
        raise InputError(f"not JSON: {exc.msg}", file=where, line=exc.lineno) from None
    except (TooDeep, DuplicateKey) as exc:
        raise InputError(str(exc), file=where) from None
    if not isinstance(data, dict):
        raise InputError("the map must be a table (an object)", file=where)
    try:
        model = MapModel.model_validate(data)
    except ValidationError as exc:
        errors = exc.errors(include_url=False)
        more = f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""
        raise InputError(_mistake(errors[0]) + more, file=where) from None
    run = {k: getattr(model.run, k) for k in model.run.model_fields_set}
    if model.profile is not None:
        run["configuration"] = _profile(model.profile, dict(run.get("configuration", {})), where)
    return StandMap(
        stand=model.stand,
        group=model.group,
        run=run,
        columns={
            k: ColumnMap(c.channel, c.unit, c.factor, c.offset) for k, c in model.columns.items()
        },
        measurements={k: (c.value, c.unit) for k, c in model.measurements.items()},
        constants={k: (c.value, c.unit) for k, c in model.constants.items()},
        file=_file(model.file, where),
        source=where,
    )


def _file(value: FileModel, where: str) -> FileSettings:
    try:
        encoding = None if value.encoding is None else encoding_of(b"", value.encoding).codec
        if value.delimiter is not None:
            delimiter_of(value.delimiter)
    except InputError as exc:
        raise InputError(f"file: {exc}", file=where) from None
    return FileSettings(encoding, value.delimiter, value.decimal, value.header, value.continue_time)


def _profile(given: ProfileModel, into: dict[str, Any], where: str) -> dict[str, Any]:
    """``[profile]`` as the profilometer's configuration fields (:data:`PROFILE_FIELDS`),
    added to ``[run.configuration]``, which must not set them too."""
    for key in sorted(given.model_fields_set, key=list(PROFILE_FIELDS).index):
        name = PROFILE_FIELDS[key]
        if name in into:
            raise InputError(
                f"[profile] {key} and [run.configuration] {name} both set it: keep one",
                file=where,
                column=name,
            )
        into[name] = getattr(given, key)
    return into


def configuration(kind: str, given: dict[str, Any], *, where: str = "") -> dict[str, Any]:
    """The map's ``[run.configuration]`` with every ``{value, unit}`` converted to its
    field's unit (``schemas.stands``: ``disc_radius`` is in m), checked by the stand's
    configuration schema over its defaults (the key named on one line)."""
    try:
        stand = StandKind(kind)
    except ValueError:
        return given
    units = unit_paths(DECLARATIONS[stand].configuration)
    converted = _converted(given, units, "", where)
    try:
        with_overrides(default_stands()[stand].configuration, converted)
    except ValidationError as exc:
        error = exc.errors(include_url=False)[0]
        error["loc"] = ("run", "configuration", *error["loc"])
        raise InputError(_mistake(error), file=where) from None
    return converted


def _converted(
    given: dict[str, Any], units: dict[str, str], prefix: str, where: str
) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in given.items():
        path = f"{prefix}{key}"
        if isinstance(value, dict) and "value" in value and set(value) <= {"value", "unit"}:
            try:
                constant = ConstantModel.model_validate(value)
            except ValidationError as exc:
                error = exc.errors(include_url=False)[0]
                error["loc"] = ("run", "configuration", *path.split("."), *error["loc"])
                raise InputError(_mistake(error), file=where) from None
            number, unit = constant.value, constant.unit
            if unit is not None:
                if path not in units:
                    raise InputError(
                        f"run.configuration.{path}: has no unit to convert {unit!r} to",
                        file=where,
                    )
                try:
                    number *= unit_factor(unit, units[path])
                except InputError as exc:
                    raise InputError(f"run.configuration.{path}: {exc}", file=where) from None
            out[key] = number
        elif isinstance(value, dict):
            out[key] = _converted(value, units, f"{path}.", where)
        else:
            out[key] = value
    return out
