"""``rigsim export`` writes a tribometer's test as a vendor's program does, in the three
agreed dialects of issue 26, and every number reads back to the simulated record."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from rigsim.cli import main, settings_for
from rigsim.export import DIALECTS, export_text
from rigsim.simulators import SIMULATORS
from schemas.stands import StandKind

KINDS = [StandKind.PIN_ON_DISC, StandKind.RECIPROCATING]


def _sim(kind: StandKind, noise: bool = True):  # type: ignore[no-untyped-def]
    from dataclasses import replace

    s = replace(settings_for(kind, noise=noise), laps=40, running_in_laps=8)
    return SIMULATORS[kind].simulate(s, 5)


def _read(text: str, dialect: str) -> tuple[list[str], list[str], list[list[float]]]:
    """The preamble, the header and the rows of an export, read as the dialect says."""
    d = DIALECTS[dialect]
    lines = text.split(d.newline)
    assert lines[-1] == "" and all("\r" not in line for line in lines)
    lines = lines[:-1]
    start = next(
        i
        for i, line in enumerate(lines)
        if d.delimiter in line and ":" not in line.split(d.delimiter)[0]
    )
    header = [h.strip().strip('"') for h in lines[start].split(d.delimiter)]
    rows = [
        [float(c.strip('"').replace(d.decimal, ".")) for c in line.split(d.delimiter)]
        for line in lines[start + 1 :]
    ]
    return lines[:start], header, rows


@pytest.mark.parametrize("kind", KINDS)
def test_tab_comma(kind: StandKind) -> None:
    sim = _sim(kind)
    raw = export_text(kind, sim, "tab-comma")
    assert raw.startswith(b"\xef\xbb\xbf") and b"\r\n" in raw  # UTF-8 with a BOM, CRLF
    preamble, header, rows = _read(raw.decode("utf-8-sig"), "tab-comma")
    assert preamble[0] == "Sample:\tSteel 100Cr6 / Al2O3 ball"
    assert "Normal load:\t5 N" in preamble and preamble[-1] == ""
    assert ("Radius:\t10 mm" in preamble) is (kind is StandKind.PIN_ON_DISC)
    head = raw.decode("utf-8-sig").split("\r\n")[len(preamble)]
    assert head.startswith(" Time [s]\tDistance [m]\t Laps \tµ\tFriction Force [N] ")
    assert "," in raw.decode("utf-8-sig").split("\r\n")[len(preamble) + 2]  # decimal comma
    expected = ["Time [s]", "Distance [m]", "Laps", "µ", "Friction Force [N]"]
    names = ["time", "distance", "laps", "friction_coefficient", "friction_force"]
    if kind is StandKind.RECIPROCATING:
        expected += ["Position [mm]", "Stroke"]
        names += ["position", "stroke"]
    assert header == expected
    _same(sim, rows, names)


@pytest.mark.parametrize("kind", KINDS)
def test_csv_units(kind: StandKind) -> None:
    sim = _sim(kind)
    raw = export_text(kind, sim, "csv-units")
    text = raw.decode("utf-8")
    assert not raw.startswith(b"\xef\xbb\xbf") and "\r" not in text
    first, second = text.split("\n")[:2]
    assert first.startswith('"Time (s)","Cycles","Distance (m)","Normal Load (N)","Friction')
    assert second.split(",")[5].startswith('"')  # the COF quoted as text
    preamble, header, rows = _read(text, "csv-units")
    assert preamble == []
    names = ["time", "laps", "distance", "normal_load", "friction_force", "friction_coefficient"]
    if kind is StandKind.RECIPROCATING:
        assert header[-2:] == ["Position (mm)", "Stroke"]
        names += ["position", "stroke"]
    _same(sim, rows, names)


@pytest.mark.parametrize("kind", KINDS)
def test_utf16_tab(kind: StandKind) -> None:
    sim = _sim(kind)
    raw = export_text(kind, sim, "utf16-tab")
    assert raw.startswith(b"\xff\xfe")  # UTF-16 LE with its BOM
    text = raw.decode("utf-16")
    preamble, header, rows = _read(text, "utf16-tab")
    assert preamble[0].startswith("Test: ") and preamble[1].startswith("Instrument: ")
    assert header[:3] == ["Время, с", "Путь, м", "Круги"]
    assert "Температура, °C" in header
    names = [
        "time",
        "distance",
        "laps",
        "friction_coefficient",
        "friction_force",
        "normal_load",
        "temperature",
    ]
    if kind is StandKind.RECIPROCATING:
        assert header[-2:] == ["Положение, мм", "Ход"]
        names += ["position", "stroke"]
    _same(sim, rows, names)


def _same(sim, rows: list[list[float]], names: list[str]) -> None:  # type: ignore[no-untyped-def]
    record = sim.columns("friction")
    columns = np.array(rows).T
    for name, column in zip(names, columns, strict=True):
        assert np.array_equal(column, record[name]), name  # every digit: shortest round trip


def test_the_cli_writes_the_file_and_the_truth(tmp_path: Path) -> None:
    out, truth = tmp_path / "test.txt", tmp_path / "truth.json"
    status = main(
        [
            "export",
            "--stand",
            "reciprocating",
            "--dialect",
            "utf16-tab",
            "--out",
            str(out),
            "--truth-json",
            str(truth),
            "--noise",
            "off",
            "--laps",
            "40",
        ]
    )
    assert status == 0 and out.read_bytes().startswith(b"\xff\xfe")
    document = json.loads(truth.read_text(encoding="utf-8"))
    assert document["stand"] == "reciprocating" and document["noise"] == "off"
    assert document["truth"]["friction_steady"] == 0.55
    assert document["configuration"]["stroke_length"] == 0.01
    rows = out.read_bytes().decode("utf-16").count("\r\n") - 3  # two preamble lines, the header
    assert rows == 40 * 80
