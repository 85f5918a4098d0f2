"""``rigsim export``: a simulated tribometer's record as a vendor's software writes it.

Three dialects, as commercial tribometers' programs export a test (the agreed forms of
issue 26; ``rigclient import`` reads them with the maps of docs/tribometers.md):

- ``tab-comma``: UTF-8 with a byte-order mark, CRLF; a preamble of ``Key:<TAB>value``
  lines (sample, operator, date, the normal load, the radius or the stroke, the speed, the
  stop condition), an empty line, a header with stray spaces and units in brackets
  (`` Time [s]``, `` Laps ``, ``µ``), tab-separated rows with a decimal comma. The normal
  load is a setting of the preamble, not a column.
- ``csv-units``: comma-separated, decimal point, UTF-8 without a BOM, LF; quoted header
  names with units in parentheses (``"Time (s)"``, ``"COF"``); the friction coefficient
  quoted as text (``"0.512"``); no preamble.
- ``utf16-tab``: UTF-16 LE with a BOM, CRLF, tab-separated, decimal point; two preamble
  lines (``Test: ...``, ``Instrument: ...``); the header in Russian (``Время, с``).

Numbers are written in full (the shortest text that reads back to the same float), so an
export of a noiseless run reads back to the truth.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rigsim.batches import SimulatedRun
from rigsim.errors import SettingsError
from rigsim.simulators import SIMULATORS
from rigsim.simulators.tribometer import TribometerTruth
from schemas.stands import PinOnDiscConfig, ReciprocatingConfig, StandKind

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Column:
    """A column of the file: its header as written and the record's channel it holds."""

    header: str
    channel: str
    quoted: bool = False


@dataclass(frozen=True, slots=True)
class Dialect:
    """How a vendor's program writes a test."""

    columns: tuple[Column, ...]
    stroke_columns: tuple[Column, ...]
    delimiter: str
    decimal: str
    encoding: str
    newline: str
    quote_headers: bool = False


DIALECTS: dict[str, Dialect] = {
    "tab-comma": Dialect(
        columns=(
            Column(" Time [s]", "time"),
            Column("Distance [m]", "distance"),
            Column(" Laps ", "laps"),
            Column("µ", "friction_coefficient"),
            Column("Friction Force [N] ", "friction_force"),
        ),
        stroke_columns=(Column("Position [mm]", "position"), Column("Stroke", "stroke")),
        delimiter="\t",
        decimal=",",
        encoding="utf-8-sig",
        newline="\r\n",
    ),
    "csv-units": Dialect(
        columns=(
            Column("Time (s)", "time"),
            Column("Cycles", "laps"),
            Column("Distance (m)", "distance"),
            Column("Normal Load (N)", "normal_load"),
            Column("Friction Force (N)", "friction_force"),
            Column("COF", "friction_coefficient", quoted=True),
        ),
        stroke_columns=(Column("Position (mm)", "position"), Column("Stroke", "stroke")),
        delimiter=",",
        decimal=".",
        encoding="utf-8",
        newline="\n",
        quote_headers=True,
    ),
    "utf16-tab": Dialect(
        columns=(
            Column("Время, с", "time"),
            Column("Путь, м", "distance"),
            Column("Круги", "laps"),
            Column("Коэффициент трения", "friction_coefficient"),
            Column("Сила трения, Н", "friction_force"),
            Column("Нормальная нагрузка, Н", "normal_load"),
            Column("Температура, °C", "temperature"),
        ),
        stroke_columns=(Column("Положение, мм", "position"), Column("Ход", "stroke")),
        delimiter="\t",
        decimal=".",
        encoding="utf-16-le",  # with its byte-order mark, written by export_text
        newline="\r\n",
    ),
}


def number(value: float, decimal: str) -> str:
    """The shortest positional text that reads back to ``value`` (``12,5`` with a comma)."""
    text = np.format_float_positional(value, unique=True, trim="-")
    return text.replace(".", decimal)


def _preamble(name: str, kind: StandKind, sim: SimulatedRun[TribometerTruth]) -> list[str]:
    body = sim.run_create
    model = PinOnDiscConfig if kind is StandKind.PIN_ON_DISC else ReciprocatingConfig
    config = model.model_validate(body.configuration)
    t = sim.truth
    if name == "utf16-tab":
        return [f"Test: {body.title}", "Instrument: rigsim TRB-sim"]
    if name != "tab-comma":
        return []
    lines = [
        f"Sample:\tSteel {config.disc.name} / {config.pin.name} ball",
        f"Operator:\t{body.operator}",
        "Date:\t2026-11-26 10:00",
        f"Normal load:\t{number(t.load, ',')} N",
    ]
    if isinstance(config, ReciprocatingConfig):
        lines += [
            f"Stroke length:\t{number(config.stroke_length * 1e3, ',')} mm",
            f"Frequency:\t{number(config.frequency, ',')} Hz",
        ]
    elif isinstance(config, PinOnDiscConfig):
        lines += [
            f"Radius:\t{number(config.track_radius * 1e3, ',')} mm",
            f"Linear speed:\t{number(config.plan.speed * 1e2, ',')} cm/s",
        ]
    lines.append(f"Stop condition:\t{number(t.laps, ',')} laps")
    return [*lines, ""]


def export_text(kind: StandKind, sim: SimulatedRun[TribometerTruth], dialect: str) -> bytes:
    """The run's friction record as the vendor's ``dialect`` writes it, encoded."""
    found = DIALECTS.get(dialect)
    if found is None:
        raise SettingsError(f"dialect must be one of {', '.join(DIALECTS)}, got {dialect!r}")
    if not SIMULATORS[kind].vendor_export:
        raise SettingsError(f"rigsim exports the tribometers only, not {kind.value!r}")
    columns = found.columns + (found.stroke_columns if kind is StandKind.RECIPROCATING else ())
    record = sim.columns("friction")
    lines = _preamble(dialect, kind, sim)

    def head(c: Column) -> str:
        return f'"{c.header}"' if found.quote_headers else c.header

    lines.append(found.delimiter.join(head(c) for c in columns))
    cells: list[Sequence[str]] = []
    for c in columns:
        write: Callable[[float], str] = _writer(c, found.decimal)
        cells.append([write(float(v)) for v in record[c.channel]])
    lines.extend(found.delimiter.join(row) for row in zip(*cells, strict=True))
    text = (found.newline.join(lines) + found.newline).encode(found.encoding)
    return "\ufeff".encode(found.encoding) + text if found.encoding == "utf-16-le" else text


def _writer(column: Column, decimal: str) -> Callable[[float], str]:
    if column.quoted:
        return lambda v: f'"{number(v, decimal)}"'
    return lambda v: number(v, decimal)
