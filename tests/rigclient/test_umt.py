"""Issue 37, item 3: what instruments write. A CETR/Bruker UMT linear-module test is one CSV
per reciprocation, two step blocks in each, each block with its own ``key = value``
preamble, header and units line (``s,g,g,``), the forces in gram-force with the normal
force negative and the time restarting at each block; the files are named ``..._1.csv`` to
``..._12.csv``, which a shell's ``*.csv`` lists as 1, 10, 11, 12, 2, ... These files are
written here from that description (no real export is kept in the repository)."""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import httpx
import pytest
from hypothesis import given
from hypothesis import strategies as st

from rigclient import Api, Client
from rigclient.agent import Agent, Batching, run_metadata
from rigclient.cli import main
from rigclient.imported import digest_key, import_files, imported_before
from rigclient.mapping import load_map
from rigclient.spool import Spool
from rigclient.table import Clock
from tests.rigclient.fake import FakeServer
from tests.rigclient.importing import import_file

G0 = 9.80665e-3  # N per gram-force (CGPM 1901)
FILES, BLOCKS, ROWS, STEP = 12, 2, 5, 0.1
LOAD_G, FRICTION_G = 500.0, 60.0

MAP = """\
stand = "reciprocating"
group = "friction"
[file]
continue_time = true
[columns]
"Fx" = "friction_force"
"Fz" = { channel = "normal_load", factor = -1 }
"COF" = "friction_coefficient"
"""


def umt_file(path: Path, number: int) -> None:
    """Reciprocation ``number``: two step blocks, each its preamble, header, units line,
    and ``ROWS`` rows whose time starts at 0."""
    blocks = []
    for step in range(1, BLOCKS + 1):
        rows = "".join(
            f"{STEP * k:.1f},{FRICTION_G:g},{-LOAD_G:g},{FRICTION_G / LOAD_G:.3f}\n"
            for k in range(ROWS)
        )
        blocks.append(
            f"Test = UMT linear\nReciprocation = {number}\nStep = {step}\nLoad = {LOAD_G:g} g\n"
            f"\nTime,Fx,Fz,COF\ns,g,g,\n{rows}"
        )
    path.write_text("\n".join(blocks), "utf-8")


def test_a_umt_test_of_many_files_is_one_run_in_natural_order(tmp_path: Path) -> None:
    folder = tmp_path / "umt"
    folder.mkdir()
    for n in range(1, FILES + 1):
        umt_file(folder / f"recip_{n}.csv", n)
    (tmp_path / "umt.toml").write_text(MAP, "utf-8")
    files = import_files([folder])
    assert [p.name for p in files[:3]] == ["recip_1.csv", "recip_2.csv", "recip_3.csv"]
    assert files == import_files(sorted(folder.glob("*.csv")))  # the shell's order mended
    done = import_file(
        files[0],
        tmp_path / "spool",
        stand="reciprocating",
        mapping=load_map(tmp_path / "umt.toml"),
        more=tuple(files[1:]),
    )
    total = FILES * BLOCKS * ROWS
    assert done.rejects == [] and done.outcome.rejected == 0
    # the time restarts at each block: continued, one step after the last row each time
    assert done.columns["time"] == pytest.approx([STEP * k for k in range(total)])
    assert done.columns["normal_load"] == pytest.approx([LOAD_G * G0] * total)
    assert done.columns["friction_force"] == pytest.approx([FRICTION_G * G0] * total)
    assert "Reciprocation = 1" in done.opening["notes"]  # the first file's preamble
    assert any("a block's preamble, left out" in s for s in done.said)


def test_without_continue_time_a_restarting_time_is_refused_naming_the_line(
    tmp_path: Path,
) -> None:
    """The map's choice, not a guess: without ``continue_time`` the second block's rows go
    back in time and are refused by file, line and column."""
    umt_file(tmp_path / "recip_1.csv", 1)
    (tmp_path / "umt.toml").write_text(MAP.replace("continue_time = true", ""), "utf-8")
    done = import_file(
        tmp_path / "recip_1.csv",
        tmp_path / "spool",
        stand="reciprocating",
        mapping=load_map(tmp_path / "umt.toml"),
    )
    assert len(done.columns["time"]) == ROWS  # block 2's 0.0-0.4 s are not after 0.4 s
    assert len(done.rejects) == ROWS
    first = done.rejects[0]
    assert first.column == "Time" and "after 0.4" in first.message


def test_a_corrected_map_for_a_file_imported_before_says_what_differs(tmp_path: Path) -> None:
    """Issue 37, item 3: the same file with a corrected map (the friction force read in mN,
    not in the units line's gram-force) was
    answered with the old run and its results, exit 0. Now the run that holds it is named
    with what differs and how to import again; the spool's run is not taken for it."""
    umt_file(tmp_path / "recip_1.csv", 1)
    path = tmp_path / "recip_1.csv"
    wrong, right = tmp_path / "wrong.toml", tmp_path / "right.toml"
    wrong.write_text(
        MAP.replace(
            '"Fx" = "friction_force"', '"Fx" = { channel = "friction_force", unit = "mN" }'
        ),
        "utf-8",
    )
    right.write_text(MAP, "utf-8")
    key = digest_key(path)
    server = FakeServer()
    import_file(path, tmp_path / "spool", stand="reciprocating", mapping=load_map(wrong),
                server=server, key=key)  # fmt: skip
    api = Api("http://rig.test", "k", transport=httpx.MockTransport(server))
    with Client("http://rig.test", "k", spool=tmp_path / "spool",
                transport=httpx.MockTransport(server)) as client:  # fmt: skip
        for mapping, other in ((load_map(wrong), False), (load_map(right), True)):
            agent = Agent(
                client, path, stand="reciprocating", group="friction", mapping=mapping,
                metadata=run_metadata(path, "reciprocating", mapping, operator="Ivanova"),
                batching=Batching(), say=print, kind="import", idempotency_key=key,
            )  # fmt: skip
            held = imported_before(client, agent, api, key)
            assert held is not None and held.other_values is other
        said = held.describe()
    assert "Fx → friction_force in mN" in said and "--again" in said, said
    assert said.index("Fx → friction_force;") < said.index("(was ") < said.index("in mN"), said


def test_rigclient_import_of_a_folder_spools_one_run_of_all_its_files(tmp_path: Path) -> None:
    """``rigclient import FOLDER``: every file's rows in one run (the server out of reach:
    they wait in the spool, and the command says so with exit 1)."""
    folder = tmp_path / "umt"
    folder.mkdir()
    for n in (1, 2, 10):
        umt_file(folder / f"recip_{n}.csv", n)
    (tmp_path / "umt.toml").write_text(MAP, "utf-8")
    spool = tmp_path / "spool"
    err = io.StringIO()
    argv = ["import", str(folder), "--map", str(tmp_path / "umt.toml"), "--again"]
    argv += ["--spool", str(spool), "--url", "http://127.0.0.1:9", "--drain", "0"]
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(argv)
    assert code == 1 and "not delivered yet" in err.getvalue()
    with Spool(spool, create=False) as s:
        (run,) = s.runs()
    assert run.rows_pending == 3 * BLOCKS * ROWS and run.rejects == 0


@given(
    st.lists(
        st.tuples(
            st.floats(-100, 100),  # where a block's time starts
            st.lists(st.floats(1e-3, 10), min_size=1, max_size=8),  # its steps
        ),
        min_size=1,
        max_size=6,
    )
)
def test_a_continued_time_increases_and_keeps_each_blocks_steps(
    blocks: list[tuple[float, list[float]]],
) -> None:
    """Whatever each block's time starts at, the continued time increases (a block after
    one of a single row aside: no step is known there, and its first row repeats the last
    time, refused as not after it) and every step within a block is kept."""
    clock, last, step = Clock(), None, 0.0
    for start, steps in blocks:
        times = [start + sum(steps[:k]) for k in range(len(steps) + 1)]
        shown = []
        for t in times:
            value = clock.time(t, last)
            clock.taken()
            if last is not None:
                assert value > last or (value == last and step == 0.0)
            step = value - last if last is not None else 0.0
            shown.append(value)
            last = value
        for k in range(1, len(times)):
            assert shown[k] - shown[k - 1] == pytest.approx(times[k] - times[k - 1], abs=1e-9)
