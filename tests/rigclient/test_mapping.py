"""Issue 39, item 8 (and item 3 for maps): a map with a mistake at any key is one line
naming the key, never a Python traceback; JSON and TOML maps nested deeper than 64 levels
are refused. Issue 37, item 3: a column's ``unit``, ``factor`` and ``offset`` together."""

from __future__ import annotations

import contextlib
import copy
import io
import json
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rigclient.cli import main
from rigclient.errors import InputError
from rigclient.jsontext import MAX_DEPTH
from rigclient.mapping import load_map
from rigclient.spool import Spool
from rigclient.table import Table
from schemas.stands import StandKind, default_stands
from tests.rigclient.importing import import_file

#: A valid map of every key, and the kinds of value each key takes.
VALID: dict[str, Any] = {
    "stand": "pin_on_disc",
    "group": "friction",
    "run": {
        "operator": "Ivanova",
        "title": "100Cr6 / Al2O3",
        "notes": "dry",
        "specimen": {"pin": "Al2O3"},
        "test_plan": {"loads": [5.0, 10.0]},
        "configuration": {"track_radius": {"value": 10, "unit": "mm"}},
    },
    "columns": {
        "t": "time",
        "mu": "friction_coefficient",
        "Fz": {"channel": "normal_load", "unit": "gf", "factor": -1, "offset": 0.0},
    },
    "measurements": {"pin_mass_before": {"value": 1.5, "unit": "g"}},
    "constants": {"temperature": 22.0},
    "file": {
        "encoding": "utf-8",
        "delimiter": "comma",
        "decimal": ".",
        "header": 1,
        "continue_time": True,
    },
}
TEXT, NUMBER, FLAG, TABLE, ARRAY = "text", "number", "flag", "table", "array"
TAKES: dict[tuple[str, ...], set[str]] = {
    ("stand",): {TEXT},
    ("group",): {TEXT},
    ("run",): {TABLE},
    ("run", "operator"): {TEXT},
    ("run", "title"): {TEXT},
    ("run", "notes"): {TEXT},
    ("run", "specimen"): {TABLE},
    ("run", "specimen", "pin"): {TEXT, NUMBER, FLAG},
    ("run", "test_plan"): {TABLE},
    ("run", "test_plan", "loads"): {TEXT, NUMBER, FLAG},  # and a list of numbers
    ("run", "configuration"): {TABLE},
    ("run", "configuration", "track_radius"): {NUMBER, TABLE},
    ("run", "configuration", "track_radius", "value"): {NUMBER},
    ("run", "configuration", "track_radius", "unit"): {TEXT},
    ("columns",): {TABLE},
    ("columns", "t"): {TEXT, TABLE},
    ("columns", "Fz"): {TEXT, TABLE},
    ("columns", "Fz", "channel"): {TEXT},
    ("columns", "Fz", "unit"): {TEXT},
    ("columns", "Fz", "factor"): {NUMBER},
    ("columns", "Fz", "offset"): {NUMBER},
    ("measurements",): {TABLE},
    ("measurements", "pin_mass_before"): {NUMBER, TABLE},
    ("measurements", "pin_mass_before", "value"): {NUMBER},
    ("measurements", "pin_mass_before", "unit"): {TEXT},
    ("constants",): {TABLE},
    ("constants", "temperature"): {NUMBER, TABLE},
    ("file",): {TABLE},
    ("file", "encoding"): {TEXT},
    ("file", "delimiter"): {TEXT},
    ("file", "decimal"): {TEXT},
    ("file", "header"): {NUMBER},
    ("file", "continue_time"): {FLAG},
}
VALUES = {
    TEXT: st.text(min_size=1, max_size=8),
    NUMBER: st.one_of(st.integers(-5, 5), st.floats(-10, 10)),
    FLAG: st.booleans(),
    TABLE: st.dictionaries(st.sampled_from(["x", "value", "y"]), st.integers(), max_size=2),
    ARRAY: st.lists(st.text(max_size=3), min_size=1, max_size=3),  # not even a plan's list
}


def _kind(value: Any) -> str:
    if isinstance(value, bool):
        return FLAG
    if isinstance(value, int | float):
        return NUMBER
    if isinstance(value, str):
        return TEXT
    return TABLE if isinstance(value, dict) else ARRAY


def _put(data: dict[str, Any], path: tuple[str, ...], value: Any) -> dict[str, Any]:
    out = copy.deepcopy(data)
    node = out
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return out


@st.composite
def malformed(draw: st.DrawFn) -> tuple[tuple[str, ...], dict[str, Any]]:
    """The valid map with one key given a value of a kind it does not take."""
    path = draw(st.sampled_from(sorted(TAKES)))
    kind = draw(st.sampled_from(sorted(set(VALUES) - TAKES[path])))
    return path, _put(VALID, path, draw(VALUES[kind]))


def _rigclient(*argv: str) -> tuple[int, str]:
    """``rigclient ARGV`` in this process: its exit status and what it wrote to stderr
    (an exception escaping main, a traceback to the user, fails the test)."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(list(argv))
    return code, err.getvalue()


def _import(tmp: Path, data: Any, *, suffix: str = ".json") -> tuple[int, str]:
    export, path = tmp / "export.csv", tmp / f"map{suffix}"
    export.write_text("t,Fz,mu\n0,-500,0.1\n1,-500,0.1\n", "utf-8")
    path.write_text(data if isinstance(data, str) else json.dumps(data), "utf-8")
    spool = ["--spool", str(tmp / "spool"), "--url", "http://127.0.0.1:9", "--drain", "0"]
    return _rigclient("import", str(export), "--map", str(path), "--again", *spool)


def test_the_valid_map_is_valid(tmp_path: Path) -> None:
    """The template the mistakes are made in reads (else every mistake would be refused for
    the template's own)."""
    (tmp_path / "m.json").write_text(json.dumps(VALID), "utf-8")
    mapping = load_map(tmp_path / "m.json")
    assert mapping.columns["Fz"].factor == -1 and mapping.file.header == 1
    assert {_kind(v) for v in [VALID["stand"], VALID["columns"]["Fz"]["factor"]]} == {
        TEXT,
        NUMBER,
    }


def test_columns_given_as_a_number_is_one_line_naming_the_key(tmp_path: Path) -> None:
    """The adversary's map (``columns = 5``) ended rigclient with an AttributeError."""
    code, said = _import(
        tmp_path, 'stand = "pin_on_disc"\ngroup = "friction"\ncolumns = 5\n', suffix=".toml"
    )
    assert code == 1
    assert said.count("\n") == 1 and "Traceback" not in said
    assert said.startswith("rigclient: ") and "columns: must be a table" in said, said


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(malformed())
def test_a_map_with_a_wrong_kind_of_value_at_any_key_is_one_line_naming_it(
    tmp_path_factory: pytest.TempPathFactory, case: tuple[tuple[str, ...], dict[str, Any]]
) -> None:
    path, data = case
    code, said = _import(tmp_path_factory.mktemp("map"), data)
    assert code == 1 and "Traceback" not in said
    assert said.count("\n") == 1, said
    # the key, or (a table given where a plain value was) the first key within it
    named = ".".join(path)
    assert f"{named}: " in said or f"{named}." in said, (named, said)


@pytest.mark.parametrize("suffix", [".json", ".toml"])
def test_a_map_nested_deeper_than_the_limit_is_refused_naming_it(
    tmp_path: Path, suffix: str
) -> None:
    """Issue 39, item 3 on the lab PC: the server's limit (64 levels) on the maps; 1 000
    levels were a RecursionError in the parser."""
    for levels, refused in ((MAX_DEPTH - 3, False), (MAX_DEPTH - 2, True), (1000, True)):
        if suffix == ".json":
            text = json.dumps({"run": {"specimen": {"pin": 0}}})
            text = text.replace("0", "[" * levels + "]" * levels)
        else:
            text = "[run]\nspecimen = { pin = " + "[" * levels + "]" * levels + " }\n"
        code, said = _import(tmp_path, text, suffix=suffix)
        assert code == 1 and said.count("\n") == 1, said
        assert (f"nested deeper than {MAX_DEPTH} levels" in said) is refused, said


def test_a_column_takes_unit_factor_and_offset_together(tmp_path: Path) -> None:
    """UMT writes the normal force in gram-force, negative: ``factor = -1`` in gf; a
    thermocouple in kelvin: ``offset = -273.15`` in °C. 500 gf = 4.903325 N (g0 = 9.80665
    m/s², CGPM 1901)."""
    path = tmp_path / "m.toml"
    path.write_text(
        "[columns]\n"
        '"Fz" = { channel = "normal_load", unit = "gf", factor = -1 }\n'
        '"Fx" = "friction_force"\n'
        '"T" = { channel = "temperature", factor = 1, offset = -273.15, unit = "degC" }\n',
        "utf-8",
    )
    group = default_stands()[StandKind.PIN_ON_DISC].group("friction")
    assert group is not None
    table = Table.from_header(
        "Time (s),Fz,Fx (mN),T", file="f", group=group, mapping=load_map(path)
    )
    row = dict(zip(table.channels, table.parse("2.0,-500,980.665,300.15", 2), strict=True))
    assert row["normal_load"] == pytest.approx(4.903325)
    assert row["friction_force"] == pytest.approx(0.980665)
    assert row["temperature"] == pytest.approx(27.0)


def test_a_units_mistake_names_the_column(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text('[columns]\n"Fz" = { channel = "normal_load", unit = "mm" }\n', "utf-8")
    group = default_stands()[StandKind.PIN_ON_DISC].group("friction")
    assert group is not None
    with pytest.raises(InputError, match=r"column 'Fz': a value in 'mm' cannot be"):
        Table.from_header("time,Fz,mu", file="f", group=group, mapping=load_map(path))


@pytest.mark.parametrize("again", [False, True])
def test_an_import_whose_every_line_is_refused_opens_no_run(tmp_path: Path, again: bool) -> None:
    """Issue 39, item 8: a file whose every line was refused (its time as hh:mm:ss) finished
    an empty run and exited 0. Now: exit 1, a line saying why, and nothing in the spool (nor
    on the server: a file imported once is looked up there with its opening, which would
    open the run; that lookup is not made for a file without a row)."""
    export = tmp_path / "export.csv"
    export.write_text("time,friction_coefficient\n00:00:01,0.1\n00:00:02,0.1\n00:00:03,0.1\n")
    spool = tmp_path / "spool"
    code, said = _rigclient(
        "import", str(export), "--stand", "pin_on_disc", "--group", "friction",
        "--spool", str(spool), "--url", "http://127.0.0.1:9", "--drain", "0",
        *(["--again"] if again else []),
    )  # fmt: skip
    assert code == 1, said
    last = said.strip().splitlines()[-1]
    assert last.startswith("rigclient: ") and "no run opened" in last, said
    assert "3 lines refused" in last and "'00:00:01' is not a number" in last, said
    assert "connection refused" not in said  # the server was never asked
    if spool.exists():
        with Spool(spool, create=False) as s:
            assert s.runs() == []


def test_a_umt_block_with_its_units_line_in_gram_force(tmp_path: Path) -> None:
    """Issue 37, item 3: a CETR/Bruker UMT block (a ``key = value`` preamble, a header, a
    units line ``s,g,g,``; forces in gram-force, the normal force negative) read with a map
    whose only arithmetic is ``factor = -1``: 500 gf = 4.903325 N, 50 gf = 0.4903325 N
    (g0 = 9.80665 m/s², CGPM 1901)."""
    export = tmp_path / "umt.csv"
    rows = "".join(f"{0.1 * k:.1f},50,-500,0.1\n" for k in range(6))
    export.write_text(
        "Test = linear reciprocating\nStep = 1\nLoad = 500 g\n\nTime,Fx,Fz,COF\ns,g,g,\n" + rows,
        "utf-8",
    )
    path = tmp_path / "umt.toml"
    path.write_text(
        'stand = "reciprocating"\ngroup = "friction"\n[columns]\n'
        '"Fx" = "friction_force"\n"Fz" = { channel = "normal_load", factor = -1 }\n'
        '"COF" = "friction_coefficient"\n',
        "utf-8",
    )
    done = import_file(export, tmp_path / "spool", stand="reciprocating", mapping=load_map(path))
    assert done.rejects == [] and len(done.columns["time"]) == 6
    assert done.columns["normal_load"] == pytest.approx([4.903325] * 6)
    assert done.columns["friction_force"] == pytest.approx([0.4903325] * 6)
    assert "Load = 500 g" in done.opening["notes"]  # the preamble, not the units line
    assert "s,g,g," not in done.opening["notes"]
