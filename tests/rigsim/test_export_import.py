"""Truth recovery through the import path (issue 26): ``rigsim export`` writes a vendor's
file, ``rigclient import`` with the map that docs/tribometers.md gives for its dialect
sends it to a real ``rigserver serve``, and the run's results are the simulator's truth:
to round-off without noise (the export writes every digit), within the bounds of
tests/analysis/test_tribometer_truth.py with it.

The maps are read from docs/tribometers.md, so the documented maps are the tested ones.
"""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path
from typing import Any

import httpx
import pytest

from rigserver.core.tribometer import STEADY_BAND
from rigsim.cli import main as rigsim
from tests.api.conftest import READER, WRITER, Server, auth
from tests.rigclient.conftest import AgentProcess

DOCS = Path(__file__).resolve().parents[2] / "docs" / "tribometers.md"
LABEL = {"pin_on_disc": "pin-on-disc", "reciprocating": "reciprocating"}
#: Laps (cycles) of the exported tests: a short record, its running-in a block multiple.
LAPS = 200


def documented_map(stand: str, dialect: str) -> str:
    """The map of docs/tribometers.md whose first line names the kind and the dialect."""
    blocks = re.findall(r"```toml\n(.*?)```", DOCS.read_text(encoding="utf-8"), flags=re.S)
    found = [b for b in blocks if b.startswith(f"# {LABEL[stand]}, {dialect}")]
    assert len(found) == 1, f"{len(found)} maps of {stand}, {dialect} in {DOCS.name}"
    tomllib.loads(found[0])  # valid TOML
    return found[0]


def _supports_constants() -> bool:
    from rigclient import mapping

    return "[constants]" in (mapping.__doc__ or "")


pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(
        not DOCS.exists() or not _supports_constants(),
        reason="rigclient's import map with [constants] and docs/tribometers.md (issue 26, "
        "items 3 and 5) are not here yet",
    ),
]


def imported(
    server: Server, agents: list[AgentProcess], tmp: Path, stand: str, dialect: str, noise: str
) -> tuple[dict[str, Any], dict[str, Any]]:
    """The run's results after the round trip, and the simulator's truth."""
    export, truth, map_path = tmp / "export.txt", tmp / "truth.json", tmp / "map.toml"
    args = ["export", "--stand", stand, "--dialect", dialect, "--out", str(export)]
    args += ["--truth-json", str(truth), "--noise", noise, "--laps", str(LAPS), "--seed", "3"]
    assert rigsim(args) == 0
    map_path.write_text(documented_map(stand, dialect), encoding="utf-8")
    command = ["import", str(export), "--map", str(map_path), "--url", server.url]
    command += ["--key", WRITER, "--spool", str(tmp / "spool"), "--drain", "120"]
    agents.append(AgentProcess(command, tmp / "rigclient.log"))
    lines = agents[-1].output(300)
    assert agents[-1].proc.returncode == 0, (tmp / "rigclient.log").read_text()
    run_id = lines[0]
    answer = httpx.get(
        f"{server.url}/api/v1/runs/{run_id}/results", headers=auth(READER), timeout=120
    )
    answer.raise_for_status()
    return answer.json()["values"], json.loads(truth.read_text(encoding="utf-8"))["truth"]


CASES = [
    (stand, dialect)
    for stand in ("pin_on_disc", "reciprocating")
    for dialect in ("tab-comma", "csv-units", "utf16-tab")
]


@pytest.mark.parametrize(("stand", "dialect"), CASES)
def test_without_noise_the_import_gives_the_truth(
    server: Server, agents: list[AgentProcess], tmp_path: Path, stand: str, dialect: str
) -> None:
    v, t = imported(server, agents, tmp_path, stand, dialect, "off")
    assert v["stand"] == stand
    for name in ("friction_mean", "friction_static"):
        assert v[name] == pytest.approx(t[name], rel=1e-12), name
    # the running-in ends in the block of laps (here one) where the true excess enters the
    # band (issue 37), or earlier where the tail's mean excess ē ≤ δ·μ_ss widens the band:
    # by λ·ln(1 + (1 + δ)ē/(δμ_ss)) < λ = L_r/3 at most; the steady mean holds only the
    # transient's tail, within the band
    lap = t["sliding_distance"] / t["laps"]
    assert v["running_in_distance"] <= t["running_in_distance"] + lap + 1e-9
    assert v["running_in_distance"] >= t["running_in_distance"] - t["transient_distance"] / 3
    mu = t["friction_steady"]
    assert mu <= v["friction_steady"] <= mu * (1.0 + STEADY_BAND)
    assert v["sliding_distance"] == pytest.approx(t["sliding_distance"], rel=1e-12)
    assert v["laps"] == pytest.approx(t["laps"], rel=1e-12)
    assert v["mean_load"] == pytest.approx(t["load"], rel=1e-12)
    if stand == "pin_on_disc":
        # the fit over the steady part takes up a little of the transient's tail (its exact
        # value: tests/analysis/test_tribometer_truth.py), within 1 % here
        assert v["lap_amplitude"] == pytest.approx(t["lap_amplitude"], rel=0.01)


@pytest.mark.parametrize("stand", ["pin_on_disc", "reciprocating"])
def test_with_noise_the_import_stays_within_the_bounds(
    server: Server, agents: list[AgentProcess], tmp_path: Path, stand: str
) -> None:
    # tab-comma: the load is the preamble's setting, every row's constant
    v, t = imported(server, agents, tmp_path, stand, "tab-comma", "on")
    # the steady mean of n ≥ 40 laps of 64 (80) readings: AR(1) of 2 % (ρ = 0.9) and the
    # force's noise give σ ≤ 0.55·√(19·0.02²)/√2560 = 9.6e-4 (test_tribometer_truth's
    # bound), plus the running-in's excess where the steady part starts early, below
    # 2z√2·σ_b ≈ 0.02 at the start and falling: 5σ + that excess's mean over the part
    assert v["friction_steady"] == pytest.approx(t["friction_steady"], abs=5 * 9.6e-4 + 0.02)
    assert v["mean_load"] == t["load"]  # the preamble's 5 N, a constant of the map
    # the record's distance and laps are written as measured: to round-off
    assert v["sliding_distance"] == pytest.approx(t["sliding_distance"], rel=1e-12)
