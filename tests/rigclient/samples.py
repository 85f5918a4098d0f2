"""Small hand-made files of the three tribometer export dialects (docs/tribometers.md),
for the SMTs-2's friction group (time, load, speed, friction_moment, revolutions) until
the tribometer stands are there: the same shapes, with the SMTs-2's channels."""

from __future__ import annotations

import codecs
from pathlib import Path

#: Row k of every sample: time s, moment N*m, speed rpm, revolutions (100 rev); the load is
#: a constant of 300 N in the first dialect, a column in the others.
ROWS = [(0.5 * k, 2.9 + 0.01 * k, 1000.0, float(k // 4)) for k in range(10)]

TAB_COMMA_MAP = """
stand = "smts2"
group = "friction"
[columns]
"Time" = "time"
"M" = "friction_moment"
"Speed" = "speed"
"Counter" = "revolutions"
[constants]
load = { value = 0.3, unit = "kN" }
"""

CSV_UNITS_MAP = """
stand = "smts2"
group = "friction"
[columns]
"Moment" = "friction_moment"
"Counter" = "revolutions"
"""

UTF16_TAB_MAP = """
stand = "smts2"
group = "friction"
[columns]
"Время" = "time"
"Нагрузка" = "load"
"Частота вращения" = "speed"
"Момент трения" = "friction_moment"
"Обороты" = "revolutions"
"Температура" = ""
"""


def tab_comma(path: Path) -> None:
    """UTF-8 with a BOM, CRLF, a ``Key:<TAB>value`` preamble, an empty line, a header with
    stray spaces and units in brackets, decimal commas; the load is not a column."""
    lines = [
        "Sample:\tSteel 100Cr6 / Al2O3 ball",
        "Operator:\tIvanova",
        "Date:\t2026-11-26 10:00",
        "Normal load:\t300 N",
        "",
        " Time [s]\tM [N*m]\t Speed [rpm] \tCounter [100 rev] ",
    ]
    lines += [f"{t:.1f}\t{m:.2f}\t{n:.0f}\t{c:.0f}".replace(".", ",") for t, m, n, c in ROWS]
    path.write_bytes(codecs.BOM_UTF8 + "\r\n".join(lines).encode("utf-8") + b"\r\n")


def csv_units(path: Path) -> None:
    """Comma-separated, decimal points, LF, quoted names with units in parentheses, some
    numbers quoted, no preamble."""
    lines = ['"Time (s)","Load (N)","Speed (rpm)","Moment (N*m)","Counter (100 rev)"']
    lines += [f'{t:.1f},300,"{n:.0f}","{m:.3f}",{c:.0f}' for t, m, n, c in ROWS]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def utf16_tab(path: Path) -> None:
    """UTF-16 LE with a BOM, CRLF, tabs, decimal points, two preamble lines, Russian names
    with units after a comma (the load in kN), and a column the map leaves out."""
    lines = [
        "Test: SMTs-2 sample",
        "Instrument: SMTs-2",
        "Время, с\tНагрузка, кН\tЧастота вращения, об/мин\tМомент трения, Н*м\tОбороты"
        "\tТемпература, °C",
    ]
    lines += [f"{t:.1f}\t0.3\t{n:.0f}\t{m:.2f}\t{c:.0f}\t21.5" for t, m, n, c in ROWS]
    path.write_bytes(
        codecs.BOM_UTF16_LE + "\r\n".join(lines).encode("utf-16-le") + "\r\n".encode("utf-16-le")
    )


SAMPLES = {
    "tab-comma": (tab_comma, TAB_COMMA_MAP),
    "csv-units": (csv_units, CSV_UNITS_MAP),
    "utf16-tab": (utf16_tab, UTF16_TAB_MAP),
}
