"""Property: whatever a generated file holds (headers changed mid-file, poison lines, any
of the dialects), every good row is delivered once, in order, by the header above it, and
every bad line is recorded with its place and reason (issue 22, items 2 and 3)."""

from __future__ import annotations

import codecs
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.rigclient.importing import import_file

CHANNELS = ("time", "load", "speed", "friction_moment", "revolutions")
UNITS = {
    "time": "s",
    "load": "N",
    "speed": "rpm",
    "friction_moment": "N*m",
    "revolutions": "100 rev",
}
#: The poison lines (cells of a row that is otherwise good): the cell's channel, its text
#: and the reason the reject gives.
POISON = {
    "nan": ("load", "nan", "is not a number"),
    "inf": ("speed", "-inf", "is not a number"),
    "1e400": ("friction_moment", "1e400", "beyond the range"),
    "3_05": ("load", "3_05", "is not a number"),
    "Arabic-Indic": ("speed", "١٠٠٠", "is not a number"),
    "full-width": ("time", "１２", "is not a number"),
    "empty": ("friction_moment", "", "an empty cell"),
    "over the load's limit": ("load", "9999", "outside the limit of load"),
}


def good(k: int) -> dict[str, float]:
    """Good row k: each channel's value tells the row and the channel apart."""
    return {
        "time": 0.5 * k,
        "load": 300.0 + k,
        "speed": 1000.0,
        "friction_moment": 2.0 + 0.001 * k,
        "revolutions": float(k // 10),
    }


@dataclass(frozen=True)
class Dialect:
    delimiter: str
    decimal: str
    end: str
    encoding: str
    bom: bool

    def number(self, value: float) -> str:
        text = f"{value:.6g}"
        return text.replace(".", ",") if self.decimal == "," else text


dialects = st.builds(
    Dialect,
    delimiter=st.sampled_from([";", "\t", ","]),
    decimal=st.sampled_from([".", ","]),
    end=st.sampled_from(["\n", "\r\n", "\r"]),
    encoding=st.sampled_from(["utf-8", "utf-16-le", "cp1251"]),
    bom=st.booleans(),
).filter(lambda d: not (d.delimiter == "," and d.decimal == ","))

segment = st.tuples(
    st.permutations(CHANNELS),
    st.booleans(),  # the load in kN (else N)
    st.lists(
        st.one_of(st.just("row"), st.sampled_from(sorted(POISON)), st.just("long")), max_size=12
    ),
)


@dataclass
class Expected:
    rows: list[dict[str, float]]
    rejects: list[tuple[int, str, str]]  # line, column, reason


def build(dialect: Dialect, preamble: int, segments: list[Any], path: Path) -> Expected:
    """Write the file; what an import must deliver and refuse."""
    lines: list[str] = [f"Образец {p}: сталь 45 / value {p}" for p in range(preamble)]
    if preamble:
        lines.append("")
    k = 0
    expected = Expected([], [])
    for order, kilo, body in segments:
        heads = {c: f"{c} [{'kN' if c == 'load' and kilo else UNITS[c]}]" for c in order}
        lines.append(dialect.delimiter.join(heads[c] for c in order))
        for what in body:
            values = good(k)
            cells = {
                c: dialect.number(values[c] / (1000.0 if c == "load" and kilo else 1))
                for c in order
            }
            if what == "row":
                expected.rows.append(values)
                k += 1
            elif what == "long":
                cells["speed"] = "1" * (70 << 10)
                expected.rejects.append((len(lines) + 1, "", "over 64 KiB"))
            else:
                channel, text, why = POISON[what]
                cells[channel] = text
                if what == "over the load's limit" and kilo:
                    cells[channel] = "9,999" if dialect.decimal == "," else "9.999"
                expected.rejects.append((len(lines) + 1, heads[channel], why))
            lines.append(dialect.delimiter.join(cells[c] for c in order))
    data = dialect.end.join(lines) + dialect.end
    raw = data.encode(dialect.encoding, errors="replace")  # cp1251 has no Arabic digits: ?
    if dialect.bom:
        raw = {"utf-8": codecs.BOM_UTF8, "utf-16-le": codecs.BOM_UTF16_LE}.get(
            dialect.encoding, b""
        ) + raw
    path.write_bytes(raw)
    return expected


@pytest.mark.slow
@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    dialect=dialects,
    preamble=st.integers(0, 3),
    segments=st.lists(segment, min_size=1, max_size=4).filter(
        lambda s: any("row" in body for _, _, body in s[:1])
    ),
)
def test_every_good_row_once_in_order_and_every_bad_line_recorded(
    dialect: Dialect, preamble: int, segments: list[Any]
) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "run.txt"
        expected = build(dialect, preamble, segments, path)
        got = import_file(path, Path(tmp) / "spool")
    for channel in CHANNELS:
        assert got.columns.get(channel, []) == pytest.approx([r[channel] for r in expected.rows]), (
            channel
        )
    assert [(r.line, r.column) for r in got.rejects] == [(n, c) for n, c, _ in expected.rejects]
    for reject, (_, _, why) in zip(got.rejects, expected.rejects, strict=True):
        assert why in reject.message and reject.file == str(path)
