"""A file's dialect: encodings, line ends, delimiters, decimal marks, preambles; numbers
that are numbers; lines bounded."""

from __future__ import annotations

import codecs
from pathlib import Path

import pytest

from rigclient.dialect import FileSettings, encoding_of, find_header, number
from rigclient.follow import MAX_LINE, Follower
from rigclient.mapping import MAP_NOTE, load_map
from tests.rigclient.importing import import_file
from tests.rigclient.samples import ROWS, SAMPLES


@pytest.mark.parametrize(
    ("cell", "value"),
    [("12,5", 12.5), ("12.5", 12.5), ("-1e-3", -1e-3), (" 7 ", 7.0), (".5", 0.5), ("+3.", 3.0)],
)
def test_numbers(cell: str, value: float) -> None:
    assert number(cell) == value


@pytest.mark.parametrize(
    ("cell", "why"),
    [
        ("nan", "is not a number"),
        ("inf", "is not a number"),
        ("-Infinity", "is not a number"),
        ("1e400", "beyond the range"),
        ("3_05", "is not a number"),
        ("٣٠٥", "is not a number"),  # Arabic-Indic digits: float() takes them
        ("３０５", "is not a number"),  # full-width digits: float() takes them too
        ("1.234,5", "both a decimal point and a comma"),
        ("1,2,3", "is not a number"),
        ("", "an empty cell"),
        ("0x10", "is not a number"),
    ],
)
def test_what_is_not_a_number(cell: str, why: str) -> None:
    with pytest.raises(ValueError, match=why):
        number(cell)


def test_a_decimal_mark_set_refuses_the_other() -> None:
    assert number("2,5", ",") == 2.5
    with pytest.raises(ValueError, match="has a point"):
        number("2.5", ",")
    with pytest.raises(ValueError, match="is not a number"):
        number("2,5", ".")


def test_encodings_by_their_marks_or_their_bytes() -> None:
    text = "Время, с\tСила трения, Н\n"
    assert encoding_of(codecs.BOM_UTF8 + text.encode()).codec == "utf-8"
    assert encoding_of(codecs.BOM_UTF8 + text.encode()).bom == 3
    assert encoding_of(codecs.BOM_UTF16_LE + text.encode("utf-16-le")).codec == "utf-16-le"
    assert encoding_of(codecs.BOM_UTF16_BE + text.encode("utf-16-be")).codec == "utf-16-be"
    assert encoding_of(text.encode()).codec == "utf-8"
    assert encoding_of(text.encode("cp1251")).codec == "cp1251"
    # the map wins; a BOM of its encoding is skipped all the same
    assert encoding_of(codecs.BOM_UTF8 + b"a", "utf-8-sig").bom == 3
    assert encoding_of(b"abc", "windows-1251").codec == "cp1251"


def test_the_header_is_the_line_before_the_first_row() -> None:
    lines = ["Sample:\tSteel", "Radius:\t10 mm", "", "Time [s]\tFriction [N]", "0,0\t1,5"]
    found = find_header(lines, FileSettings(), final=False)
    assert found is not None and (found.index, found.delimiter) == (3, "\t")
    assert find_header(lines[:4], FileSettings(), final=False) is None  # no row yet
    spaces = ["time   load  speed", "0.5 300 1000"]
    found = find_header(spaces, FileSettings(), final=False)
    assert found is not None and found.delimiter == " "
    given = find_header(lines, FileSettings(header=4, delimiter="tab"), final=False)
    assert given is not None and given.index == 3


def test_a_header_repeated_after_unreadable_rows_is_found_at_its_first() -> None:
    # found by hypothesis (tests/rigclient/test_file_properties.py): the header, a row that
    # cannot be read, the header again (its columns in another order and unit), a row. The
    # first is the header: the bad row is a reject, not part of the run's notes.
    lines = ["Sample;Steel", "time [s];load [N]", "0;nan", "load (kN);Time [s]", "0,3;0"]
    found = find_header(lines, FileSettings(), final=False)
    assert found is not None and (found.index, found.delimiter) == (1, ";")
    # another header (other names) above the row's is a preamble line, as before
    other = ["time [s];speed [rpm]", "0;nan", "time [s];load [N]", "0;300"]
    found = find_header(other, FileSettings(), final=False)
    assert found is not None and found.index == 2


@pytest.mark.parametrize("end", ["\n", "\r\n", "\r"])
@pytest.mark.parametrize("encoding", ["utf-8", "utf-16-le", "cp1251"])
def test_lines_end_in_lf_crlf_or_cr_alone(tmp_path: Path, end: str, encoding: str) -> None:
    texts = ["Время;Нагрузка", "1;2", "", "3;4"]
    path = tmp_path / "f.csv"
    path.write_bytes(end.join(texts).encode(encoding) + end.encode(encoding))
    follower = Follower(path, encoding)
    assert follower.open()
    lines = follower.lines(final=True)
    assert [line.text for line in lines] == texts
    assert lines[-1].end == path.stat().st_size
    assert [line.number for line in lines] == [1, 2, 3, 4]
    follower.close()


def test_a_cr_at_the_end_waits_for_a_possible_lf(tmp_path: Path) -> None:
    path = tmp_path / "f.csv"
    path.write_bytes(b"a;b\r\n1;2\r")
    follower = Follower(path)
    assert follower.open()
    assert [line.text for line in follower.lines()] == ["a;b"]
    with path.open("ab") as f:
        f.write(b"\n3;4\r\n")
    assert [(line.text, line.end) for line in follower.lines()] == [("1;2", 10), ("3;4", 15)]
    follower.close()


def test_an_overlong_line_is_given_short_and_the_next_where_it_starts(tmp_path: Path) -> None:
    """A cell of 200 KiB (more than the csv module's field limit): the line is named, not
    kept; the next line starts where the file says."""
    path = tmp_path / "f.csv"
    long = "1;" + "9" * (200 << 10)
    path.write_text(f"a;b\n{long}\n5;6\n", encoding="utf-8")
    follower = Follower(path)
    assert follower.open()
    lines = []
    while chunk := follower.lines():  # read in chunks of 1 MiB at most
        lines += chunk
    assert [line.overlong for line in lines] == [0, len(long), 0]
    assert len(lines[1].text) < 100 and lines[1].text.startswith("1;999")
    assert lines[2].text == "5;6" and lines[2].end == path.stat().st_size
    assert len(follower._buffer) <= MAX_LINE
    follower.close()


@pytest.mark.parametrize("dialect", sorted(SAMPLES))
def test_each_dialect_is_read_by_a_map_of_a_few_lines(tmp_path: Path, dialect: str) -> None:
    write, text = SAMPLES[dialect]
    path, map_path = tmp_path / f"{dialect}.txt", tmp_path / "map.toml"
    write(path)
    map_path.write_text(text, encoding="utf-8")
    got = import_file(path, tmp_path / "spool", mapping=load_map(map_path))
    assert got.rejects == []
    assert got.columns["time"] == pytest.approx([r[0] for r in ROWS])
    assert got.columns["friction_moment"] == pytest.approx([r[1] for r in ROWS])
    assert got.columns["speed"] == pytest.approx([r[2] for r in ROWS])
    assert got.columns["revolutions"] == pytest.approx([r[3] for r in ROWS])
    assert got.columns["load"] == pytest.approx([300.0] * len(ROWS))  # kN -> N, or a constant
    preamble = {
        "tab-comma": "Sample: Steel 100Cr6 / Al2O3 ball\nOperator: Ivanova\nDate: 2026-11-26 "
        "10:00\nNormal load: 300 N",
        "csv-units": "",
        "utf16-tab": "Test: SMTs-2 sample\nInstrument: SMTs-2",
    }
    notes = got.opening["notes"].split("\n\n")  # how the map reads it, then the preamble
    assert notes[0] == load_map(map_path).describe() and notes[0].startswith(MAP_NOTE)
    assert "\n\n".join(notes[1:]) == preamble[dialect]
