"""``rigclient import`` against a real ``rigserver serve``: a tribometer-like export with a
map of a few lines, its run id first and its headline results once finished; the same file
imported again opens no second run, from the same spool or a fresh one."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest

from rigsim.cli import settings_for
from rigsim.export import export_text
from rigsim.simulators import SIMULATORS
from schemas.stands import StandKind
from tests.api.conftest import WRITER, Server, read_columns
from tests.rigclient.conftest import AgentProcess
from tests.rigclient.test_tribometer_exports import doc_map

pytestmark = pytest.mark.slow


def _import(
    agents: list[AgentProcess], server: Server, path: Path, map_path: Path, spool: Path, *more: str
) -> tuple[int, list[str], str]:
    log = spool.parent / f"{spool.name}.log"
    args = ["import", str(path), "--map", str(map_path), "--url", server.url, "--key", WRITER]
    args += ["--spool", str(spool), "--drain", "60", *more]
    agents.append(AgentProcess(args, log))
    lines = agents[-1].output(120)
    return agents[-1].proc.returncode, lines, log.read_text()


def test_an_export_imported_twice_is_one_run(
    server: Server, agents: list[AgentProcess], tmp_path: Path
) -> None:
    kind = StandKind.PIN_ON_DISC
    settings = replace(settings_for(kind, noise=True), laps=12, running_in_laps=3)
    sim = SIMULATORS[kind].simulate(settings, 3)
    path, map_path = tmp_path / "export.txt", tmp_path / "map.json"
    path.write_bytes(export_text(kind, sim, "tab-comma"))
    data = doc_map(kind, "tab-comma")  # the map of docs/tribometers.md, as the lab types it
    data["constants"]["normal_load"]["value"] = sim.truth.load
    data["run"]["configuration"]["track_radius"] = sim.run_create.configuration["track_radius"]
    data["run"]["title"] = "pin-on-disc export"
    map_path.write_text(json.dumps(data), "utf-8")
    code, lines, log = _import(agents, server, path, map_path, tmp_path / "spool")
    assert code == 0, log
    run_id = lines[0]
    assert run_id.count("-") == 1 and "T" in run_id  # the server's id, first
    summary = "\n".join(lines[1:])  # the headline results, once finished
    assert "results (pin_on_disc)" in summary and "friction" in summary.lower()
    columns = read_columns(server.url, run_id, "friction")
    assert columns["time"] == pytest.approx(sim.columns("friction")["time"].tolist())
    assert columns["normal_load"] == pytest.approx([sim.truth.load] * len(columns["time"]))
    # again, from the same spool, then from a fresh one: the same run, no second one
    for spool in ("spool", "fresh-spool"):
        code, lines, log = _import(agents, server, path, map_path, tmp_path / spool)
        assert code == 0, log
        assert lines[0] == run_id and f"run {run_id}" in log and "imported before" in log
    # a corrected map (another normal load), from the same spool and a fresh one: the run
    # that holds the file is named with what differs, never its results with exit 0
    data["constants"]["normal_load"]["value"] = sim.truth.load + 1
    map_path.write_text(json.dumps(data), "utf-8")
    for spool in ("spool", "map-spool"):
        code, lines, log = _import(agents, server, path, map_path, tmp_path / spool)
        assert code == 1 and lines == [run_id], log
        assert f"normal_load = {sim.truth.load + 1:g} N" in log and "--again" in log, log
    data["constants"]["normal_load"]["value"] = sim.truth.load
    # another map (another title): the server names the run that holds the content
    data["run"]["title"] = "another title"
    map_path.write_text(json.dumps(data), "utf-8")
    code, lines, log = _import(agents, server, path, map_path, tmp_path / "third-spool")
    assert code == 1 and lines[0] == run_id and "read with other values: title" in log
    assert "--again" in log and "results (" not in "\n".join(lines)
    code, lines, log = _import(agents, server, path, map_path, tmp_path / "third-spool", "--again")
    assert code == 0, log
    assert lines[0] != run_id
