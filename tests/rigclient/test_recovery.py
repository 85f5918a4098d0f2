"""The agent against a real ``rigserver serve``: the server killed for a while, the agent
killed -9 twice, the file rotated, and every row stored exactly once, in order, in a finished
run.

The issue asks for a 30 s outage; CI runs it scaled down (RIG_OUTAGE_SECONDS, default 3).
"""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path

import httpx
import pytest

from tests.api.conftest import READER, WRITER, Server, auth, read_columns
from tests.rigclient.conftest import AgentProcess

pytestmark = pytest.mark.slow

HEADER = "time [s];load [kN];speed [rpm];friction_moment [N*m];revolutions [100 rev]\n"
OUTAGE = float(os.environ.get("RIG_OUTAGE_SECONDS", "3"))


def row(k: int) -> str:
    """Row k of an SMTs-2 record, decimal commas (0.3 kN = 300 N, in the load's limits)."""
    return f"{k * 0.5:.1f};0,3;1000;{2.9 + 0.001 * k:.3f};{k // 10}\n".replace(".", ",")


class Stand:
    """The stand's software: appends rows to its CSV file, a few at a time."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.rows = 0
        path.write_text(HEADER, encoding="utf-8")

    def write(self, rows: int, pause: float = 0.01) -> None:
        for _ in range(rows):
            with self.path.open("a", encoding="utf-8") as f:
                f.write(row(self.rows))
            self.rows += 1
            time.sleep(pause)

    def rotate(self) -> None:
        """The file renamed aside and a new one started with the header."""
        self.path.rename(self.path.with_suffix(".csv.1"))
        self.path.write_text(HEADER, encoding="utf-8")

    def write_split(self) -> None:
        """One row written in two pieces, a while apart (a partial last line)."""
        text = row(self.rows)
        with self.path.open("a", encoding="utf-8") as f:
            f.write(text[:7])
        time.sleep(0.5)
        with self.path.open("a", encoding="utf-8") as f:
            f.write(text[7:])
        self.rows += 1


def run_state(url: str, run_id: str) -> dict[str, object]:
    r = httpx.get(f"{url}/api/v1/runs/{run_id}", headers=auth(READER), timeout=30)
    r.raise_for_status()
    found: dict[str, object] = r.json()
    return found


def friction_rows(state: dict[str, object]) -> object:
    rows = state["rows"]
    assert isinstance(rows, dict)
    return rows.get("friction")


@pytest.mark.parametrize("outage", [OUTAGE])
def test_outage_and_two_kills_store_every_row_once_in_order(
    server: Server, agents: list[AgentProcess], tmp_path: Path, outage: float
) -> None:
    stand = Stand(tmp_path / "smts2.csv")
    spool, log = tmp_path / "spool", tmp_path / "agent.log"
    args = ["tail", str(stand.path), "--stand", "smts2", "--group", "friction"]
    args += ["--url", server.url, "--key", WRITER, "--spool", str(spool)]
    args += ["--rows", "7", "--seconds", "0.2", "--poll", "0.05", "--drain", "60"]

    def start() -> AgentProcess:
        agents.append(AgentProcess(args, log))
        return agents[-1]

    first = start()
    run_id = first.first_line()
    assert run_id.count("-") == 1 and "T" in run_id  # the server's id
    stand.write(40)
    time.sleep(0.5)
    first.kill9()  # 1st kill: rows read but not spooled are read again
    stand.write(20)
    second = start()
    assert second.first_line() == run_id  # the same run goes on
    stand.write(20)
    time.sleep(0.3)
    server.kill()  # the server goes away; the agent spools on
    stand.write(15)
    stand.write_split()
    stand.write(15)
    time.sleep(outage / 2)
    second.kill9()  # 2nd kill, while the server is down
    third = start()
    assert third.first_line() == run_id  # known from the spool, without the server
    stand.write(20)
    time.sleep(outage / 2)
    server.start()
    stand.write(10)
    stand.rotate()  # the stand's software starts a new file mid-run
    stand.write(10)
    deadline = time.monotonic() + 60
    while friction_rows(state := run_state(server.url, run_id)) != stand.rows:
        assert time.monotonic() < deadline, f"{state}: {log.read_text()[-2000:]}"
        time.sleep(0.2)
    third.signal(signal.SIGTERM)  # the operator stops the agent: the run is finished
    assert third.wait(60) == 0, log.read_text()[-2000:]
    columns = read_columns(server.url, run_id, "friction")
    assert columns["time"] == [k * 0.5 for k in range(stand.rows)]  # once each, in order
    assert columns["load"] == pytest.approx([300.0] * stand.rows)
    state = run_state(server.url, run_id)
    assert state["state"] == "finished" and friction_rows(state) == stand.rows


def test_import_refuses_a_malformed_line_and_delivers_the_rest(
    server: Server, agents: list[AgentProcess], tmp_path: Path
) -> None:
    path = tmp_path / "mtos.tsv"
    lines = ["load\tindicator [mm]\tx\ty\tt1\tt2\tt3\tt4\tt5\tregime\n"]
    for k in range(12):
        load = "abc" if k == 6 else f"{500 + 100 * k}"
        lines.append(f"{load}\t0,{k + 1:02d}\t1,5\t-2,0\t40\t45\t50\t51\t52\t1\n")
    path.write_text("".join(lines), encoding="utf-8")
    spool, log = tmp_path / "spool", tmp_path / "agent.log"
    args = ["import", str(path), "--stand", "mtos", "--group", "steps", "--rows", "5"]
    args += ["--url", server.url, "--key", WRITER, "--spool", str(spool), "--operator", "Kim"]
    agents.append(AgentProcess(args, log))
    run_id = agents[-1].first_line()
    assert agents[-1].wait(60) == 0, log.read_text()
    assert f"{path}:8, column 'load': 'abc' is not a number" in log.read_text()
    columns = read_columns(server.url, run_id, "steps")
    assert columns["load"] == [500.0 + 100 * k for k in range(12) if k != 6]
    assert columns["indicator"] == pytest.approx([(k + 1) / 100 for k in range(12) if k != 6])
    assert run_state(server.url, run_id)["state"] == "finished"
    status = AgentProcess(["status", "--spool", str(spool), "--json"], log)
    agents.append(status)
    report = "\n".join(status.output())
    assert status.proc.returncode == 0, log.read_text()
    assert '"line": 8' in report and '"column": "load"' in report


def test_a_key_refused_at_the_start_stops_the_agent_and_the_right_key_goes_on(
    server: Server, agents: list[AgentProcess], tmp_path: Path
) -> None:
    """A key without the scope: the agent says so at once, with the URL, instead of
    spooling rows for nobody; the same command with the right key goes on with the run the
    spool kept, and delivers it (the key is not frozen into the spool)."""
    path = tmp_path / "smts2.csv"
    path.write_text(HEADER + "".join(row(k) for k in range(30)), encoding="utf-8")
    log = tmp_path / "agent.log"
    args = ["tail", str(path), "--stand", "smts2", "--group", "friction", "--url", server.url]
    args += ["--spool", str(tmp_path / "spool"), "--finish-after-idle", "1"]
    agents.append(AgentProcess([*args, "--key", READER], log))
    assert agents[-1].output(60) == []
    assert agents[-1].proc.returncode == 1
    said = log.read_text()
    assert f"POST {server.url}/api/v1/runs: 403" in said, said
    assert "the server refused the key (403, see above); stopped" in said, said
    agents.append(AgentProcess([*args, "--key", WRITER], log))
    run_id = agents[-1].first_line()
    assert agents[-1].wait(60) == 0, log.read_text()[-2000:]
    assert "going on with run local-" in log.read_text()
    columns = read_columns(server.url, run_id, "friction")
    assert columns["time"] == [k * 0.5 for k in range(30)]
    assert run_state(server.url, run_id)["state"] == "finished"
