"""``rigclient import`` against a real ``rigserver serve``: a tribometer-like export with a
map of a few lines, its run id first and its headline results once finished; the same file
imported again opens no second run, from the same spool or a fresh one."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.api.conftest import WRITER, Server, read_columns
from tests.rigclient.conftest import AgentProcess
from tests.rigclient.samples import ROWS, TAB_COMMA_MAP, tab_comma

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
    path, map_path = tmp_path / "export.txt", tmp_path / "map.toml"
    tab_comma(path)
    map_path.write_text(TAB_COMMA_MAP + '[run]\ntitle = "pin-on-disc export"\n', "utf-8")
    code, lines, log = _import(agents, server, path, map_path, tmp_path / "spool")
    assert code == 0, log
    run_id = lines[0]
    assert run_id.count("-") == 1 and "T" in run_id  # the server's id, first
    assert "results (smts2)" in "\n".join(lines[1:])  # the headline results, once finished
    columns = read_columns(server.url, run_id, "friction")
    assert columns["time"] == pytest.approx([r[0] for r in ROWS])
    assert columns["load"] == pytest.approx([300.0] * len(ROWS))
    # again, from the same spool, then from a fresh one: the same run, no second one
    for spool in ("spool", "fresh-spool"):
        code, lines, log = _import(agents, server, path, map_path, tmp_path / spool)
        assert code == 0, log
        assert lines[0] == run_id and f"run {run_id}" in log and "imported before" in log
    # another map (another title): the server names the run that holds the content
    map_path.write_text(TAB_COMMA_MAP, "utf-8")
    code, lines, log = _import(agents, server, path, map_path, tmp_path / "third-spool")
    assert code == 1 and lines[0] == run_id and "opened with other values" in log
    code, lines, log = _import(agents, server, path, map_path, tmp_path / "third-spool", "--again")
    assert code == 0, log
    assert lines[0] != run_id
