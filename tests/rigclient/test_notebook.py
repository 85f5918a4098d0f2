"""docs/notebooks/lab.ipynb runs, every cell, against a lab this test starts and fills: a
tribometer's speed sweep of four steps, an MTOS series of two runs, a profile (issue 41,
item 4)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import httpx
import nbformat
import numpy as np
import pytest
from nbclient import NotebookClient

from rigsim.client import LabClient
from rigsim.simulators import simulate
from rigsim.simulators.mtos import MtosSettings
from schemas.runs import RunCreate
from tests.api.conftest import READER, WRITER, Server, served
from tests.reports.simulated import series_of

NOTEBOOK = Path(__file__).resolve().parents[2] / "docs" / "notebooks" / "lab.ipynb"
RADII = (6e-3, 9e-3, 12e-3, 15e-3)  # m: the sweep's track radii
SPEEDS = (0.075, 0.150, 0.225, 0.300)  # m/s: its sliding speeds
STEP_SECONDS, RATE = 180.0, 10.0  # a 3-minute step read at 10 Hz


def speed_sweep() -> dict[str, np.ndarray]:
    """Four steps at the radii and speeds above, the rotational speed in rpm
    (n = 60·v/(2π·r)), μ falling with the speed, as a Stribeck curve's mixed branch."""
    rows = int(STEP_SECONDS * RATE)
    columns: dict[str, list[np.ndarray]] = {}
    for k, (radius, speed) in enumerate(zip(RADII, SPEEDS, strict=True)):
        part = {
            "time": k * STEP_SECONDS + np.arange(rows) / RATE,
            "step": np.full(rows, k + 1.0),
            "track_radius": np.full(rows, radius),
            "rotational_speed": np.full(rows, 60.0 * speed / (2 * np.pi * radius)),
            "normal_load": np.full(rows, 3.0),
            "friction_coefficient": np.full(rows, 0.4 - 0.5 * speed),
        }
        for name, values in part.items():
            columns.setdefault(name, []).append(values)
    return {name: np.concatenate(parts) for name, parts in columns.items()}


@pytest.fixture(scope="module")
def filled_lab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    with served(tmp_path_factory.mktemp("notebook")) as srv:
        with LabClient(srv.url, WRITER) as client:
            sweep = client.create_run(
                RunCreate(stand="pin_on_disc", operator="Petrova", title="speed sweep")
            )
            client.post_columns(sweep.id, 0, "friction", speed_sweep())
            client.finish(sweep.id)
            runs = [client.run(simulate("mtos", MtosSettings(), seed=s)) for s in (7, 8)]
            client.run(simulate("profilometer", None, seed=9))
        with httpx.Client(base_url=srv.url) as http:
            run_ids = [o.run.id for o in runs]
            series_of(http, WRITER, run_ids, name="MTOS repeats", purpose="repeatability")
        yield srv


def test_the_notebook_runs_and_draws_its_three_plots(
    filled_lab: Server, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("RIG_URL", filled_lab.url)
    monkeypatch.setenv("RIG_KEY", READER)
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    NotebookClient(
        notebook,
        timeout=300,
        kernel_name="python3",
        resources={"metadata": {"path": str(NOTEBOOK.parent)}},
    ).execute()
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    images = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(images) == 3  # μ(v), the Hersey-Stribeck diagram, the profile
    tables = [o["data"]["text/plain"] for o in outputs if "text/html" in o.get("data", {})]
    sweep = tables[0]  # the steps of the sweep: every speed there, in order
    for speed in SPEEDS:
        assert f"{speed:g}" in sweep
