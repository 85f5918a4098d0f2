"""Every stand's run file, as a simulated run leaves it through the real service, opens in
a NeXus reader (nexusformat) whose default plot is what the stand measures: the friction
moment against time (SMTs-2), the gauge pressures against the limb angle (slide bearing),
the indicator against the load (MTOS), the profile height against the position
(profilometer) — the plot h5web and silx draw when the file is opened.

A real ``rigserver serve`` (one for the four stands) and rigsim's lab-PC client."""

from __future__ import annotations

import json
from collections.abc import Iterator

import numpy as np
import pytest
from nexusformat.nexus import NXdata, nxload

from rigsim.client import LabClient
from rigsim.simulators import simulate
from schemas.stands import StandKind
from tests.api.conftest import KEYS, WRITER, Server

pytestmark = pytest.mark.slow

#: stand -> (channel group, the signals, the axis): the quantities of the lab manual's
#: plots (lab 2: M_tr(t); lab 3: p1..p5 over the limb angle, table 3.1, first p3, the middle
#: manometer at z = 0; lab 4: Δl over N, tables 4.1-4.3; lab 1: the profile y(x); a
#: tribometer: μ and F_t over time).
DEFAULT_PLOT = {
    StandKind.SMTS2: ("friction", ["friction_moment"], "time"),
    StandKind.SLIDE_BEARING: ("rows", ["p3", "p1", "p2", "p4", "p5"], "limb_angle"),
    StandKind.MTOS: ("steps", ["indicator"], "load"),
    StandKind.PROFILOMETER: ("profile", ["y"], "x"),
    StandKind.PIN_ON_DISC: ("friction", ["friction_coefficient", "friction_force"], "time"),
    StandKind.RECIPROCATING: ("friction", ["friction_coefficient", "friction_force"], "time"),
}


@pytest.fixture(scope="module")
def service(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    home = tmp_path_factory.mktemp("nexus")
    (home / "keys.json").write_text(json.dumps(KEYS))
    server = Server(home / "data", home / "keys.json")
    server.start()
    yield server
    server.stop()


@pytest.mark.parametrize("stand", list(StandKind))
def test_the_default_plot_is_the_measured_quantity(service: Server, stand: StandKind) -> None:
    group, signals, axis = DEFAULT_PLOT[stand]
    sim = simulate(stand, seed=7)
    with LabClient(service.url, WRITER) as client:
        outcome = client.run(sim)
    posted = {
        name: np.concatenate([b.columns[name] for b in sim.batches if b.group == group])
        for name in [*signals, axis]
    }

    root = nxload(str(service.data_dir / "runs" / f"{outcome.run.id}.h5"), "r")
    assert root.nxclass == "NXroot" and root.attrs["default"] == "entry"
    entry = root["entry"]
    assert entry.nxclass == "NXentry" and entry.attrs["default"] == group
    data = root.get_default()  # NXroot@default -> NXentry@default -> NXdata
    assert isinstance(data, NXdata) and data.nxname == group
    assert data.nxsignal.nxname == signals[0]
    assert [s.nxname for s in data.nxauxiliary_signals or []] == signals[1:]
    assert [a.nxname for a in data.nxaxes] == [axis]
    for name in [*signals, axis]:  # the plot is of the readings posted
        np.testing.assert_array_equal(data[name].nxdata, posted[name])
        assert data[name].attrs["units"]
    assert data.is_plottable()
