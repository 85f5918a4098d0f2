"""Issue 37, items 2 and 3: a rotary tribometer's recipe of steps as its export writes it (a
``Step`` column, the radial stage's position in mm, the spindle's speed in rpm, the time
restarting at each step, no sliding speed or distance), read by the map docs/tribometers.md
gives for it, comes back as the simulated sweep and is analysed step by step as the
simulated record is. The file is written here from that description (no real export is
kept in the repository)."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from rigclient.mapping import load_map
from rigsim.batches import split
from rigsim.simulators.tribometer import simulate_sweep
from schemas.results import PinOnDiscResults
from schemas.stands import StandKind
from tests.reports.simulated import analysed
from tests.rigclient.importing import import_file
from tests.rigclient.test_tribometer_exports import doc_map

HEADER = "Step,Time (s),Radial position (mm),Speed (rpm),Fz (N),COF"


def sweep_export(path: Path, record: dict[str, np.ndarray]) -> None:
    """The record as the instrument writes it: the time from the start of each step, the
    radius in mm, every number as Python prints it (its shortest exact form)."""
    columns = {name: values.tolist() for name, values in record.items()}
    starts = {s: columns["time"][columns["step"].index(s)] for s in set(columns["step"])}
    lines = [HEADER]
    for k, step in enumerate(columns["step"]):
        values = (
            columns["time"][k] - starts[step],
            columns["track_radius"][k] * 1e3,
            columns["rotational_speed"][k],
            columns["normal_load"][k],
            columns["friction_coefficient"][k],
        )
        lines.append(f"{step:g}," + ",".join(repr(v) for v in values))
    path.write_text("\n".join(lines) + "\n", "utf-8")


def test_a_speed_sweep_export_comes_back_step_by_step(tmp_path: Path) -> None:
    sim = simulate_sweep(seed=3, step_time=30.0)
    record = sim.columns("friction")
    path = tmp_path / "sweep.csv"
    sweep_export(path, record)
    mapping = tmp_path / "sweep.json"
    mapping.write_text(json.dumps(doc_map(StandKind.PIN_ON_DISC, "recipe-steps")), "utf-8")
    got = import_file(
        path, tmp_path / "spool", stand="pin_on_disc", mapping=load_map(mapping), rows=500
    )
    assert got.rejects == []
    # continue_time: each step's time goes on one reading (0.1 s) after the last one's
    for name in ("time", "step", "rotational_speed", "normal_load", "friction_coefficient"):
        np.testing.assert_allclose(got.columns[name], record[name], rtol=1e-12, err_msg=name)
    # mm in the file, m stored: one rounding of the decimal conversion
    np.testing.assert_allclose(got.columns["track_radius"], record["track_radius"], rtol=1e-15)
    imported = {name: np.asarray(values) for name, values in got.columns.items()}
    through_file = analysed(
        StandKind.PIN_ON_DISC,
        replace(sim, batches=tuple(split("friction", imported, imported["time"], rows=500))),
    ).result.values
    direct = analysed(StandKind.PIN_ON_DISC, sim).result.values
    assert isinstance(through_file, PinOnDiscResults) and isinstance(direct, PinOnDiscResults)
    assert len(through_file.steps) == len(sim.truth.sliding_speed) == 4
    for read, simulated, speed in zip(
        through_file.steps, direct.steps, sim.truth.sliding_speed, strict=True
    ):
        # v = 2πRn/60 of the file's radius and rpm: the sweep's speed to round-off
        assert read.sliding_speed == pytest.approx(speed, rel=1e-9)
        assert read.model_dump() == pytest.approx(simulated.model_dump(), rel=1e-9)
