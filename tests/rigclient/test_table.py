"""The map and the rows of a stand's file: units, decimal commas, errors that say where."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from rigclient.agent import constants, run_metadata
from rigclient.dialect import FileSettings
from rigclient.errors import InputError
from rigclient.mapping import load_map
from rigclient.table import Table, split_header
from rigclient.units import unit_factor
from schemas.channels import ChannelGroup
from schemas.stands import StandKind, default_stands, with_overrides


def _friction() -> ChannelGroup:
    group = default_stands()[StandKind.SMTS2].group("friction")
    assert group is not None
    return group


FRICTION = _friction()

MAP = """
stand = "smts2"
group = "friction"

[run]
operator = "Ivanova"
specimen = { pin = "St3sp", disc = "R9" }

[columns]
"t" = "time"
"F" = { channel = "load", unit = "kN" }
"n" = "speed"
"M" = { channel = "friction_moment", factor = 0.01 }
"counter" = "revolutions"
"comment" = ""

[measurements]
pin_mass_before = 12.3456
disc_ra = { value = 320, unit = "nm" }
"""


def test_header_units_in_brackets_parentheses_or_after_a_comma() -> None:
    assert split_header("load [kN]", ";") == ("load", "kN")
    assert split_header("load (N*m)", ",") == ("load", "N*m")
    assert split_header("load, kN", ";") == ("load", "kN")
    assert split_header("load", ";") == ("load", None)


def test_unit_factors() -> None:
    assert unit_factor("kN", "N") == 1000.0
    assert unit_factor("nm", "um") == pytest.approx(1e-3)
    assert unit_factor("kgf/cm^2", "at") == 1.0  # the technical atmosphere is 1 kgf/cm²
    with pytest.raises(InputError, match="cannot be a 'N' channel"):
        unit_factor("mm", "N")
    with pytest.raises(InputError, match="unknown unit 'furlong'"):
        unit_factor("furlong", "m")


def test_a_header_naming_the_channels_needs_no_map() -> None:
    header = "time [s];load [kN];speed [rpm];friction_moment [N*m];revolutions [100 rev]\n"
    table = Table.from_header(header, file="f.csv", group=FRICTION, mapping=None)
    assert table.delimiter == ";"
    row = table.parse("0,5;0,3;1000;2,95;0\n", line=2)
    assert row == pytest.approx([0.5, 300.0, 1000.0, 2.95, 0.0])


def test_the_map_names_columns_converts_them_and_leaves_some_out(tmp_path: Path) -> None:
    path = tmp_path / "smts2.toml"
    path.write_text(MAP, encoding="utf-8")
    mapping = load_map(path)
    assert mapping.run["operator"] == "Ivanova" and mapping.stand == "smts2"
    table = Table.from_header(
        "t\tF\tn\tM\tcounter\tcomment", file="f.tsv", group=FRICTION, mapping=mapping
    )
    assert table.ignored == ("comment",)
    columns = table.columns([table.parse("1,0\t0,3\t1000\t295\t2\tok", line=2)])
    assert columns["load"][0] == pytest.approx(300.0)  # kN -> N
    assert columns["friction_moment"][0] == pytest.approx(2.95)  # divisions x 0.01
    # the same map as JSON
    as_json = tmp_path / "smts2.json"
    as_json.write_text(
        json.dumps({"columns": {"t": "time", "F": {"channel": "load", "unit": "kN"}}}),
        encoding="utf-8",
    )
    assert load_map(as_json).columns["F"].unit == "kN"


def test_a_bad_cell_names_file_line_and_column() -> None:
    header = "time,load [N],speed,friction_moment,revolutions"
    table = Table.from_header(header, file="run.csv", group=FRICTION, mapping=None)
    with pytest.raises(InputError, match=r"^run\.csv:7, column 'load \[N\]': 'abc' is not a"):
        table.parse("1.0,abc,1000,2.9,0", line=7)
    with pytest.raises(InputError, match=r"^run\.csv:8.*: 3 cells where the header has 5"):
        table.parse("1.0,300,1000", line=8)


def test_a_header_that_misses_a_channel_or_names_a_stranger() -> None:
    with pytest.raises(InputError, match=r"f\.csv:1: no column for revolutions"):
        Table.from_header(
            "time,load,speed,friction_moment", file="f.csv", group=FRICTION, mapping=None
        )
    with pytest.raises(InputError, match=r"column 'torque': 'torque' is not a channel"):
        Table.from_header(
            "time,load,speed,torque,revolutions", file="f.csv", group=FRICTION, mapping=None
        )


def test_map_errors_name_the_file_and_the_key(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text('[columns]\n"F" = { channel = "load", unit = "kN", factor = "2" }\n')
    with pytest.raises(InputError, match=r"bad\.toml: columns\.F\.factor: .* number, got '2'"):
        load_map(path)
    path.write_text("[colums]\n")
    with pytest.raises(InputError, match=r"bad\.toml: colums: not a key of the map; it takes"):
        load_map(path)
    path.write_text("[columns\n")
    with pytest.raises(InputError, match=r"bad\.toml: not TOML"):
        load_map(path)


def test_columns_keep_the_rows_in_order() -> None:
    header = "time,load,speed,friction_moment,revolutions"
    table = Table.from_header(header, file="f.csv", group=FRICTION, mapping=None)
    rows = [table.parse(f"{k},300,1000,3,{k}", line=k + 2) for k in range(5)]
    np.testing.assert_array_equal(table.columns(rows)["time"], np.arange(5.0))


def test_the_readmes_maps_read_a_file_of_their_stand(tmp_path: Path) -> None:
    """Each map in the README's "Connect a real stand" section and in docs/tribometers.md
    is a valid map: a header of its columns (and the channels it leaves to the header or
    gives as constants) reads, its constants and configuration convert."""
    root = Path(__file__).parents[2]
    blocks = []
    for page, count in (("README.md", 4), ("docs/tribometers.md", 8)):
        text = (root / page).read_text(encoding="utf-8")
        found = re.findall(r"```toml\n(.*?)```", text, flags=re.S)
        found = [b for b in found if "group = " in b or page == "README.md"]  # whole maps
        assert len(found) == count, page
        blocks += found
    seen = set()
    for k, block in enumerate(blocks):
        path = tmp_path / f"map{k}.toml"
        path.write_text(block, encoding="utf-8")
        mapping = load_map(path)
        stand = default_stands()[StandKind(mapping.stand or "profilometer")]
        group = stand.group(mapping.group or "profile")
        assert group is not None
        given = {c.channel for c in mapping.columns.values()} | set(mapping.constants)
        header = [*mapping.columns, *(c.name for c in group.channels if c.name not in given)]
        table = Table.from_header(";".join(header), file=str(path), group=group, mapping=mapping)
        assert sorted([*table.channels, *table.constants]) == sorted(c.name for c in group.channels)
        constants(stand, mapping)
        meta = run_metadata(path, stand.kind.value, mapping, operator="Kim")
        with_overrides(stand.configuration, meta.get("configuration", {}))
        seen.add(stand.kind)
    assert seen == set(StandKind)


def test_constants_fill_a_channel_the_file_lacks_in_its_unit(tmp_path: Path) -> None:
    """Issue 26: a test setting (the normal load) is not a column; the map gives it."""
    path = tmp_path / "m.toml"
    path.write_text('[constants]\nload = { value = 30.591, unit = "kgf" }\n', encoding="utf-8")
    table = Table.from_header(
        "time;speed;friction_moment;revolutions", file="f", group=FRICTION, mapping=load_map(path)
    )
    columns = table.columns([table.parse("0,5;1000;2,9;0", 2), table.parse("1;1000;3;0", 3)])
    assert columns["load"] == pytest.approx([30.591 * 9.80665] * 2)  # kgf -> N, CGPM 1901


@pytest.mark.parametrize(
    ("constant", "why"),
    [
        ('load = { value = 3, unit = "furlong" }', "unknown unit 'furlong'"),
        ('load = { value = 3, unit = "mm" }', "a value in 'mm' cannot be a 'N' channel"),
        ('torque = { value = 3, unit = "N" }', "'torque' of \\[constants\\] is not a channel"),
        ('time = { value = 3, unit = "s" }', "time: both a column and a constant"),
    ],
)
def test_constants_that_cannot_be_are_named(tmp_path: Path, constant: str, why: str) -> None:
    path = tmp_path / "m.toml"
    path.write_text(f"[constants]\n{constant}\n", encoding="utf-8")
    with pytest.raises(InputError, match=why):
        Table.from_header(
            "time;speed;friction_moment;revolutions",
            file="f",
            group=FRICTION,
            mapping=load_map(path),
        )


def test_the_runs_configuration_takes_units(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text(
        "[run.configuration]\n"
        'disc_radius = { value = 22.5, unit = "mm" }\n'
        'pin = { youngs_modulus = { value = 210, unit = "GPa" }, name = "45" }\n'
        "steady_fraction = 0.4\n",
        encoding="utf-8",
    )
    meta = run_metadata(Path("f.csv"), "smts2", load_map(path), operator="Kim")
    assert meta["configuration"] == {
        "disc_radius": pytest.approx(0.0225),
        "pin": {"youngs_modulus": pytest.approx(2.1e11), "name": "45"},
        "steady_fraction": 0.4,
    }
    path.write_text('[run.configuration]\ndisc_radius = { value = 2, unit = "N" }\n', "utf-8")
    with pytest.raises(
        InputError, match=r"run\.configuration\.disc_radius: a value in 'N' cannot be a 'm'"
    ):
        run_metadata(Path("f.csv"), "smts2", load_map(path))


def test_the_files_dialect_in_the_map(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text(
        '[file]\nencoding = "windows-1251"\ndelimiter = "spaces"\ndecimal = ","\nheader = 3\n',
        encoding="utf-8",
    )
    assert load_map(path).file == FileSettings("cp1251", "spaces", ",", 3)
    for bad, why in [
        ('encoding = "latin-9"', "unknown encoding 'latin-9'"),
        ('encoding = "koi8-r"', "encoding 'koi8-r' is not one of"),
        ('delimiter = "pipe"', "unknown delimiter 'pipe'"),
        ('decimal = ";"', r"file\.decimal: Input should be '\.' or ',', got ';'"),
        ("header = 0", r"file\.header: Input should be greater than or equal to 1"),
        ('header = "3"', r"file\.header: Input should be a valid integer, got '3'"),
        ("quote = true", r"file\.quote: not a key of the map's \[file\]; it takes encoding"),
    ]:
        path.write_text(f"[file]\n{bad}\n", encoding="utf-8")
        with pytest.raises(InputError, match=why):
            load_map(path)


def test_header_names_are_found_whatever_their_spelling() -> None:
    """Stray blanks, case, the micro sign and Russian units: ``Friction Moment [N*m]``
    finds ``friction_moment``; ``Время, с`` is in s."""
    header = " Time [s] \tLoad, кН\tSPEED (rpm)\tFriction Moment [Н*м]\tRevolutions [100 rev]"
    table = Table.from_header(header, file="f", group=FRICTION, mapping=None)
    assert table.channels == ("time", "load", "speed", "friction_moment", "revolutions")
    assert table.parse("1,5\t0,3\t1000\t2,9\t0", 2) == pytest.approx([1.5, 300, 1000, 2.9, 0])
