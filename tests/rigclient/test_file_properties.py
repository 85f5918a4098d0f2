"""Property: whatever a generated file holds (headers changed mid-file, poison lines, any
of the dialects), every good row is delivered once, in order, by the header above it, and
every bad line is recorded with its place and reason (issue 22, items 2 and 3)."""

from __future__ import annotations

import codecs
import tempfile
import threading
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from unittest.mock import patch

import httpx
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, rule

from rigclient import Client, RetryPolicy, RunHandle
from rigclient.agent import Agent, Batching
from rigclient.spool import Spool
from tests.rigclient.fake import FakeServer
from tests.rigclient.importing import import_file, stored

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


class Crash(Exception):
    """The agent's process ends before the run's finish (a kill after the last batch)."""


class TailedFile(RuleBasedStateMachine):
    """A file that the stand's software writes while the agent follows it and is killed and
    started again: rows, poison lines and new headers in any order. At the end every good
    row is stored once, in order, by the header above it, and every bad line is kept as a
    reject with its line and reason (the header in effect is found again after a restart)."""

    def __init__(self) -> None:
        super().__init__()
        self.tmp = tempfile.TemporaryDirectory()
        self.path = Path(self.tmp.name) / "run.csv"
        self.spool = Path(self.tmp.name) / "spool"
        self.server = FakeServer()
        self.dialect = Dialect(";", ",", "\n", "utf-8", False)
        self.lines: list[str] = []
        self.expected = Expected([], [])
        self.k = 0
        self.heads: dict[str, str] = {}
        self.order: tuple[str, ...] = CHANNELS
        self.kilo = False
        self._header(CHANNELS, False)
        self.local_id = ""

    def _write(self, text: str) -> None:
        self.lines.append(text)
        with self.path.open("a", encoding="utf-8") as f:
            f.write(text + "\n")

    def _header(self, order: tuple[str, ...], kilo: bool) -> None:
        self.order, self.kilo = order, kilo
        self.heads = {c: f"{c} [{'kN' if c == 'load' and kilo else UNITS[c]}]" for c in order}
        self._write(";".join(self.heads[c] for c in order))

    def _cells(self) -> dict[str, str]:
        values = good(self.k)
        return {
            c: self.dialect.number(values[c] / (1000.0 if c == "load" and self.kilo else 1))
            for c in self.order
        }

    @rule(n=st.integers(1, 6))
    def rows(self, n: int) -> None:
        for _ in range(n):
            self.expected.rows.append(good(self.k))
            self._write(";".join(self._cells()[c] for c in self.order))
            self.k += 1

    @rule(what=st.sampled_from(sorted(POISON)))
    def poison(self, what: str) -> None:
        channel, text, why = POISON[what]
        cells = self._cells()
        cells[channel] = text if not (what == "over the load's limit" and self.kilo) else "9,999"
        self.expected.rejects.append((len(self.lines) + 1, self.heads[channel], why))
        self._write(";".join(cells[c] for c in self.order))

    @rule(order=st.permutations(CHANNELS), kilo=st.booleans())
    def new_header(self, order: list[str], kilo: bool) -> None:
        self._header(tuple(order), kilo)

    def _agent(self, *, crash: bool) -> None:
        """An agent that reads what is written and stops: killed before the finish
        (``crash``), or finishing the run."""
        with Client(
            "http://rig.test",
            "key",
            spool=self.spool,
            transport=httpx.MockTransport(self.server),
            retry=RetryPolicy(base_delay=0.01, max_delay=0.05),
        ) as client:
            stop = threading.Event()  # set once the run is open: read what is there, stop
            agent = Agent(
                client,
                self.path,
                stand="smts2",
                group="friction",
                mapping=None,
                metadata={"stand": "smts2", "operator": "Ivanova", "title": "tailed"},
                batching=Batching(rows=3, seconds=60.0, poll=0.01),
                say=lambda text: None,
                on_run=lambda run: stop.set(),
            )
            with patch.object(RunHandle, "finish", _crash) if crash else nullcontext():
                try:
                    outcome = agent.run(stop)
                except Crash:
                    outcome = None
            if outcome is not None:
                self.local_id = outcome.run.local_id
            assert client.wait(20.0)

    @rule()
    def killed(self) -> None:
        self._agent(crash=True)

    def teardown(self) -> None:
        try:
            self._agent(crash=False)
            got = stored(self.server)
            for channel in CHANNELS:
                assert got.get(channel, []) == pytest.approx(
                    [r[channel] for r in self.expected.rows]
                ), channel
            with Spool(self.spool) as spool:
                rejects = spool.rejects(self.local_id)
            assert [(r.line, r.column) for r in rejects] == [
                (n, c) for n, c, _ in self.expected.rejects
            ]
            for reject, (_, _, why) in zip(rejects, self.expected.rejects, strict=True):
                assert why in reject.message
        finally:
            self.tmp.cleanup()


def _crash(self: RunHandle) -> None:
    raise Crash


TestTailedFile = pytest.mark.slow(TailedFile.TestCase)
TailedFile.TestCase.settings = settings(
    max_examples=10, stateful_step_count=6, deadline=None, suppress_health_check=list(HealthCheck)
)
