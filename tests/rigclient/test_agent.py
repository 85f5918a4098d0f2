"""The agent on a file being written, against a fake server: batches, rotation, truncation,
partial lines, refused lines."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest

from rigclient import Client, InputError, RetryPolicy, RunHandle
from rigclient.agent import Agent, Batching, HeaderChanged, Outcome
from rigclient.mapping import ColumnMap, StandMap
from rigclient.spool import Spool
from tests.rigclient.fake import FakeServer
from tests.rigclient.importing import import_file

HEADER = "time [s];load [kN];speed [rpm];friction_moment [N*m];revolutions [100 rev]\n"
TIMEOUT = 20.0


def row(k: int) -> str:
    """Row k of an SMTs-2 friction record with decimal commas (load 0.3 kN = 300 N)."""
    return f"{k * 0.5:.1f};0,3;1000;{2.9 + 0.001 * k:.3f};{k // 10}\n".replace(".", ",")


def stored_times(server: FakeServer) -> list[float]:
    return [t for seq in sorted(server.stored) for t in server.stored[seq].get("time", [])]


def wait_for(condition: Callable[[], bool], timeout: float = TIMEOUT) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.02)


class Running:
    """An agent in a thread, on the file ``path``, posting to ``server`` through ``spool``."""

    def __init__(
        self,
        server: FakeServer,
        path: Path,
        spool: Path,
        idle: float = 0.8,
        mapping: StandMap | None = None,
    ) -> None:
        self.client = Client(
            "http://rig.test",
            "key",
            spool=spool,
            transport=httpx.MockTransport(server),
            retry=RetryPolicy(base_delay=0.01, max_delay=0.05),
        )
        self.said: list[str] = []
        self.agent = Agent(
            self.client,
            path,
            stand="smts2",
            group="friction",
            mapping=mapping,
            metadata={"stand": "smts2", "operator": "Ivanova", "title": path.name},
            batching=Batching(rows=4, seconds=0.1, finish_after_idle=idle, poll=0.02),
            say=self.said.append,
        )
        self.stop = threading.Event()
        self.outcome: Outcome | None = None
        self.error: BaseException | None = None
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        try:
            self.outcome = self.agent.run(self.stop)
        except (InputError, Crash) as exc:
            self.error = exc

    def join(self) -> Outcome:
        self.thread.join(TIMEOUT)
        assert not self.thread.is_alive(), "the agent did not finish"
        assert self.client.wait(TIMEOUT)
        self.client.close()
        assert self.outcome is not None
        return self.outcome


class Crash(Exception):
    """The agent's process ends here (as a kill would end it)."""


@pytest.fixture
def server() -> Iterator[FakeServer]:
    yield FakeServer()


def write(path: Path, text: str, mode: str = "a") -> None:
    with path.open(mode, encoding="utf-8") as f:
        f.write(text)
        f.flush()


@pytest.mark.parametrize("how", ["renamed", "truncated"])
def test_a_rotated_file_is_followed(server: FakeServer, tmp_path: Path, how: str) -> None:
    path = tmp_path / "smts2.csv"
    write(path, HEADER + "".join(row(k) for k in range(10)), "w")
    agent = Running(server, path, tmp_path / "spool")
    wait_for(lambda: agent.agent.follower.is_open)  # a file renamed before is another file
    if how == "renamed":
        path.rename(tmp_path / "smts2.csv.1")  # rows not read yet are read from the old file
    else:  # copytruncate: what was not read before the truncation is gone, so wait for it
        wait_for(lambda: len(stored_times(server)) == 10)
    write(path, HEADER + "".join(row(k) for k in range(10, 20)), "w")
    outcome = agent.join()
    assert stored_times(server) == [k * 0.5 for k in range(20)]
    assert server.stored[0]["load"][0] == pytest.approx(300.0)  # kN -> N
    assert (outcome.rows, outcome.rejected, server.state) == (20, 0, "finished")
    change = "rotated" if how == "renamed" else "truncated"
    assert any(f"the file was {change}" in s for s in agent.said)


def test_a_partial_last_line_waits_for_its_end(server: FakeServer, tmp_path: Path) -> None:
    path = tmp_path / "smts2.csv"
    write(path, HEADER + row(0) + row(1), "w")
    agent = Running(server, path, tmp_path / "spool", idle=1.0)
    wait_for(lambda: len(stored_times(server)) == 2)
    half = len(row(2)) // 2
    write(path, row(2)[:half])
    time.sleep(0.4)  # longer than a batch's seconds: the half line is not taken
    assert len(stored_times(server)) == 2
    write(path, row(2)[half:] + row(3))
    agent.join()
    assert stored_times(server) == [0.0, 0.5, 1.0, 1.5]


def test_a_malformed_line_is_refused_by_file_line_column_and_the_rest_delivered(
    server: FakeServer, tmp_path: Path
) -> None:
    path = tmp_path / "smts2.csv"
    lines = [row(k) for k in range(8)]
    lines[4] = lines[4].replace("0,3", "0,3x", 1)  # file line 6 (the header is line 1)
    write(path, HEADER + "".join(lines), "w")
    agent = Running(server, path, tmp_path / "spool")
    outcome = agent.join()
    assert stored_times(server) == [k * 0.5 for k in range(8) if k != 4]
    assert outcome.rejected == 1
    message = f"{path}:6, column 'load [kN]': '0,3x' is not a number"
    assert any(message in s for s in agent.said)
    with Spool(tmp_path / "spool") as spool:
        (reject,) = spool.rejects(outcome.run.local_id)
    assert (reject.line, reject.column) == (6, "load [kN]") and message in reject.message


def test_rows_are_batched_by_count_and_by_time(server: FakeServer, tmp_path: Path) -> None:
    path = tmp_path / "smts2.csv"
    write(path, HEADER + "".join(row(k) for k in range(9)), "w")
    agent = Running(server, path, tmp_path / "spool")
    wait_for(lambda: len(stored_times(server)) == 9)  # 4 + 4 at once, the 9th after 0.1 s
    agent.join()
    sizes = [len(server.stored[s]["time"]) for s in sorted(server.stored)]
    assert sizes == [4, 4, 1]
    np.testing.assert_allclose(stored_times(server), np.arange(9) * 0.5)


SWAPPED = "time [s];speed [rpm];load [kN];revolutions [100 rev];friction_moment [N*m]\n"


def swapped_row(k: int) -> str:
    """Row k under :data:`SWAPPED`: the same values, the columns in another order."""
    return f"{k * 0.5:.1f};1000;0,3;{k // 10};{2.9 + 0.001 * k:.3f}\n".replace(".", ",")


def test_a_header_changed_mid_file_is_read_by_its_names(server: FakeServer, tmp_path: Path) -> None:
    """Issue 22, item 2: load and speed swap places mid-file; neither is stored swapped."""
    path = tmp_path / "smts2.csv"
    text = HEADER + "".join(row(k) for k in range(6)) + SWAPPED
    write(path, text + "".join(swapped_row(k) for k in range(6, 12)), "w")
    agent = Running(server, path, tmp_path / "spool")
    outcome = agent.join()
    assert stored_times(server) == [k * 0.5 for k in range(12)]
    loads = [v for s in sorted(server.stored) for v in server.stored[s]["load"]]
    speeds = [v for s in sorted(server.stored) for v in server.stored[s]["speed"]]
    assert loads == pytest.approx([300.0] * 12) and speeds == [1000.0] * 12
    assert outcome.rejected == 0
    assert any(f"{path}:8: a new header" in s for s in agent.said)


def test_a_header_the_map_cannot_place_stops_the_agent_there(
    server: FakeServer, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The rows before it are delivered, the agent stops naming the line; started again
    with a map that places it, it goes on from that line, and a restart after a crash reads
    the rows after the cursor by the header in effect there (kept in the spool)."""
    path = tmp_path / "smts2.csv"
    other = "time [s];speed [rpm];Last [kN];revolutions [100 rev];friction_moment [N*m]\n"
    write(path, HEADER + "".join(row(k) for k in range(5)) + other, "w")
    write(path, "".join(swapped_row(k) for k in range(5, 9)))
    stopped = Running(server, path, tmp_path / "spool")
    stopped.thread.join(TIMEOUT)
    assert stopped.outcome is None and isinstance(stopped.error, HeaderChanged)
    assert str(stopped.error).startswith(f"{path}:7, column 'Last [kN]': a new header line")
    assert stopped.client.wait(TIMEOUT)
    stopped.client.close()
    assert stored_times(server) == [k * 0.5 for k in range(5)] and server.state == "open"
    # the map places "Last" now; a crash (the finish never queued) after the file's end
    mapping = StandMap(columns={"Last": ColumnMap("load", "kN")})
    monkeypatch.setattr(RunHandle, "finish", lambda self: (_ for _ in ()).throw(Crash()))
    crashed = Running(server, path, tmp_path / "spool", mapping=mapping)
    crashed.thread.join(TIMEOUT)
    assert isinstance(crashed.error, Crash)
    assert crashed.client.wait(TIMEOUT)
    crashed.client.close()
    monkeypatch.undo()
    write(path, "".join(swapped_row(k) for k in range(9, 12)))
    again = Running(server, path, tmp_path / "spool", mapping=mapping)
    again.join()
    assert stored_times(server) == [k * 0.5 for k in range(12)]
    loads = [v for s in sorted(server.stored) for v in server.stored[s]["load"]]
    assert loads == pytest.approx([300.0] * 12) and server.state == "finished"
    assert any("going on with run" in s for s in again.said)


POISON = {
    "a cell of 200 KiB": "1,0;" + "9" * (200 << 10) + ";1000;2,9;0\n",
    "nan": "1,0;nan;1000;2,9;0\n",
    "inf": "1,0;0,3;inf;2,9;0\n",
    "1e400": "1,0;0,3;1000;1e400;0\n",
    "3_05": "1,0;3_05;1000;2,9;0\n",
    "Arabic-Indic digits": "1,0;0,3;١٠٠٠;2,9;0\n",
    "full-width digits": "1,0;0,3;１０００;2,9;0\n",
    "outside the load's limits": "1,0;-0,3;1000;2,9;0\n",
    "a time that goes back": "0,1;0,3;1000;2,9;0\n",
}


def test_poison_lines_are_kept_as_rejects_and_the_run_goes_on(
    server: FakeServer, tmp_path: Path
) -> None:
    """Issue 22, item 3: each poison line is refused by file, line and column, kept in the
    spool with its reason; every good row around them is delivered once, in order."""
    path = tmp_path / "smts2.csv"
    lines = [HEADER, row(0), row(1)] + list(POISON.values()) + [row(k) for k in range(2, 6)]
    write(path, "".join(lines), "w")
    agent = Running(server, path, tmp_path / "spool")
    outcome = agent.join()
    assert stored_times(server) == [k * 0.5 for k in range(6)]
    assert outcome.rejected == len(POISON) and server.state == "finished"
    with Spool(tmp_path / "spool") as spool:
        rejects = spool.rejects(outcome.run.local_id)
    assert [r.line for r in rejects] == list(range(4, 4 + len(POISON)))
    columns = [r.column for r in rejects]
    load, speed, moment = "load [kN]", "speed [rpm]", "friction_moment [N*m]"
    assert columns == ["", load, speed, moment, load, speed, speed, load, "time [s]"]
    assert "over 64 KiB" in rejects[0].message and "beyond the range" in rejects[3].message
    assert "outside the limit of load" in rejects[7].message
    assert "must be increasing" in rejects[8].message


@pytest.mark.parametrize("how", ["CR alone", "a header over 64 KiB", "an empty file"])
def test_import_ends_whatever_the_file_holds(tmp_path: Path, how: str) -> None:
    """CR-only line ends are lines; a header past the bound, or no header, is an error at
    once (the import used to wait for ever)."""
    path = tmp_path / "f.csv"
    if how == "CR alone":
        path.write_bytes((HEADER + "".join(row(k) for k in range(5))).replace("\n", "\r").encode())
        got = import_file(path, tmp_path / "spool")
        assert got.columns["time"] == [k * 0.5 for k in range(5)]
        return
    text = "" if how == "an empty file" else "time;" + "x" * (70 << 10) + "\n" + row(0)
    path.write_text(text, encoding="utf-8")
    why = "an empty file" if how == "an empty file" else "line 1 is over 64 KiB"
    with pytest.raises(InputError, match=why):
        import_file(path, tmp_path / "spool")
