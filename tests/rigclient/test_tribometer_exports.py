"""Issue 26: each dialect ``rigsim export`` writes, for both tribometer kinds, read by the
map docs/tribometers.md gives for it: every value of the record comes back as simulated."""

from __future__ import annotations

import json
import re
import tomllib
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from rigclient.mapping import load_map
from rigsim.cli import settings_for
from rigsim.export import DIALECTS, export_text
from rigsim.simulators import SIMULATORS
from schemas.stands import StandKind
from tests.rigclient.importing import import_file

DOC = Path(__file__).parents[2] / "docs" / "tribometers.md"
KINDS = {"pin-on-disc": StandKind.PIN_ON_DISC, "reciprocating": StandKind.RECIPROCATING}


def doc_map(kind: StandKind, dialect: str) -> dict[str, Any]:
    """The map docs/tribometers.md gives for the kind and the dialect (its first line names
    them: ``# pin-on-disc, tab-comma``)."""
    for block in re.findall(r"```toml\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S):
        name, _, rest = block.partition("\n")[0].lstrip("# ").partition(", ")
        if KINDS.get(name) is kind and rest.split()[0].rstrip(":") == dialect:
            found: dict[str, Any] = tomllib.loads(block)
            return found
    raise AssertionError(f"no map for {kind.value}, {dialect} in {DOC}")


@pytest.mark.parametrize("dialect", sorted(DIALECTS))
@pytest.mark.parametrize("kind", list(KINDS.values()))
def test_an_export_reads_back_to_the_record(tmp_path: Path, kind: StandKind, dialect: str) -> None:
    settings = replace(settings_for(kind, noise=True), laps=12, running_in_laps=3)
    sim = SIMULATORS[kind].simulate(settings, 7)
    path = tmp_path / f"{kind.value}-{dialect}.txt"
    path.write_bytes(export_text(kind, sim, dialect))
    data = doc_map(kind, dialect)
    # the lab types what its test was run with: the load and the geometry of the preamble
    if "constants" in data:
        data["constants"]["normal_load"] = {"value": sim.truth.load, "unit": "N"}
    wanted = sim.run_create.configuration
    for name in ("track_radius", "stroke_length", "frequency"):
        if name in data["run"]["configuration"]:
            data["run"]["configuration"][name] = wanted[name]
    map_path = tmp_path / "map.json"
    map_path.write_text(json.dumps(data), encoding="utf-8")
    got = import_file(path, tmp_path / "spool", stand=kind.value, mapping=load_map(map_path))
    assert got.rejects == []
    record = sim.columns("friction")
    spec = DIALECTS[dialect]
    columns = spec.columns + (spec.stroke_columns if kind is StandKind.RECIPROCATING else ())
    for column in columns:
        np.testing.assert_allclose(
            got.columns[column.channel], record[column.channel], rtol=1e-12, err_msg=column.header
        )
    if "constants" in data:
        assert got.columns["normal_load"] == pytest.approx([sim.truth.load] * len(record["time"]))
    assert got.opening["configuration"] == pytest.approx(
        {k: wanted[k] for k in data["run"]["configuration"]}
    )
    notes = got.opening["notes"]
    assert ("Normal load: " in notes) is (dialect == "tab-comma")
    assert ("Instrument: rigsim TRB-sim" in notes) is (dialect == "utf16-tab")
