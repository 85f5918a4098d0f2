"""rigclient.Lab against a live server: runs, readings, results, steps, series, the live
rows (a dropped connection resumed), downloads, and a key without ``read`` refused.

The expected numbers come from what the test posted (the simulator's columns) and from the
API's own JSON answers, an independent path from the Arrow stream and the results table.
"""

from __future__ import annotations

import io
import threading
import time
import zipfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import h5py
import httpx
import numpy as np
import pandas as pd
import pytest

from rigclient import Lab, LabRun
from rigclient.errors import ServerRefused
from rigsim.client import LabClient
from rigsim.simulators import simulate
from rigsim.simulators.mtos import MtosSettings
from rigsim.simulators.tribometer import TribometerSettings
from schemas.runs import RunCreate
from schemas.stands import default_stands
from tests.api.conftest import MTOS_ONLY, READER, WRITER, Server, auth, served
from tests.api.test_readme import block, section
from tests.reports.simulated import series_of


@pytest.fixture(scope="module")
def lab_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    with served(tmp_path_factory.mktemp("lab")) as srv:
        yield srv


@pytest.fixture(scope="module")
def posted(lab_server: Server) -> dict[str, Any]:
    """Two MTOS runs in a series, a profile and a tribometer's record, posted as rigsim
    posts them; the simulated runs kept to compare with."""
    with LabClient(lab_server.url, WRITER) as client:
        mtos = [simulate("mtos", MtosSettings(model="short"), seed=s) for s in (3, 4)]
        mtos_runs = [client.run(sim) for sim in mtos]
        profile = simulate("profilometer", None, seed=1)
        profile_run = client.run(profile)
        tribo = simulate("pin_on_disc", TribometerSettings(laps=200), seed=2)
        tribo_run = client.run(tribo)
    with httpx.Client(base_url=lab_server.url) as http:
        series = series_of(
            http,
            WRITER,
            [o.run.id for o in mtos_runs],
            name="MTOS, two repeats",
            purpose="repeatability",
        )
    return {
        "mtos": list(zip(mtos, [o.run.id for o in mtos_runs], strict=True)),
        "profile": (profile, profile_run.run.id),
        "tribo": (tribo, tribo_run.run.id),
        "series": series,
    }


@pytest.fixture
def lab(lab_server: Server) -> Iterator[Lab]:
    with Lab(lab_server.url, READER) as lab:
        yield lab


def test_runs_are_listed_newest_first_filtered_and_paged(
    lab: Lab, posted: dict[str, Any], monkeypatch: pytest.MonkeyPatch
) -> None:
    every = lab.runs()
    created = [r.info.created for r in every]
    assert created == sorted(created, reverse=True)
    every_posted = {run_id for _, run_id in posted["mtos"]} | {posted["tribo"][1]}
    assert every_posted <= {r.id for r in every}
    mtos = lab.runs(stand="mtos", state="finished")
    assert {r.id for r in mtos} == {run_id for _, run_id in posted["mtos"]}
    monkeypatch.setattr("rigclient.lab.PAGE", 1)  # one run a page: three more pages read
    assert [r.id for r in lab.runs()] == [r.id for r in every]
    assert lab.runs(stand="mtos", until="2000-01-01T00:00:00Z") == []


def test_readings_are_the_posted_columns_with_their_units(lab: Lab, posted: dict[str, Any]) -> None:
    sim, run_id = posted["tribo"]
    run = lab.run(run_id)
    frame = run.readings("friction")
    record = default_stands()[run.info.stand].groups[0]
    assert list(frame.columns) == [c.name for c in record.channels]
    assert frame.attrs["units"] == {c.name: c.unit for c in record.channels}
    for name, values in sim.columns("friction").items():  # what was posted, bit for bit
        np.testing.assert_array_equal(frame[name].to_numpy(), values)
    assert len(run.readings()) == len(frame)  # the record, without naming it
    masses = run.readings("measurements")
    posted_masses = sim.columns("measurements")
    assert len(masses) == 1
    for name in masses.columns:
        assert masses[name].iloc[0] == posted_masses[name][-1]


def test_original_readings_of_an_uncorrected_run_are_the_same(
    lab: Lab, posted: dict[str, Any]
) -> None:
    _, run_id = posted["profile"]
    run = lab.run(run_id)
    pd.testing.assert_frame_equal(run.readings("profile"), run.readings("profile", original=True))


def test_readings_as_corrected_and_as_typed(lab_server: Server, lab: Lab) -> None:
    with LabClient(lab_server.url, WRITER) as client:
        run_id = client.run(simulate("profilometer", None, seed=11)).run.id
    typed_y = lab.run(run_id).readings("profile")["y"].iloc[3]
    httpx.patch(
        f"{lab_server.url}/api/v1/runs/{run_id}/readings/profile/3",
        json={"values": {"y": typed_y + 0.001}, "reason": "misread"},
        headers=auth(WRITER),
    ).raise_for_status()
    run = lab.run(run_id)
    assert run.readings("profile")["y"].iloc[3] == typed_y + 0.001
    assert run.readings("profile", original=True)["y"].iloc[3] == typed_y


def test_results_are_the_pages_table_with_uncertainties(lab: Lab, posted: dict[str, Any]) -> None:
    _, run_id = posted["tribo"]
    run = lab.run(run_id)
    payload = run.payload()
    frame = run.results()
    steady = frame.loc["friction_steady"]
    # μ_ss is dimensionless: the value and its standard uncertainty as the results hold them
    assert steady["value"] == pytest.approx(payload["values"]["friction_steady"], rel=1e-12)
    assert steady["uncertainty"] == pytest.approx(
        payload["values"]["friction_steady_uncertainty"], rel=1e-12
    )
    assert "friction_steady_uncertainty" not in frame.index  # folded into its value's row
    assert set(frame.columns) == {"quantity", "symbol", "value", "uncertainty", "unit", "part"}
    russian = run.results(lang="ru")
    assert list(russian.index) == list(frame.index)
    assert russian.loc["friction_steady", "quantity"] != steady["quantity"]


def test_results_in_display_units(lab: Lab, posted: dict[str, Any]) -> None:
    _, run_id = posted["profile"]
    frame = lab.run(run_id).results()
    payload = lab.run(run_id).payload()
    ra = frame.loc["ra"]
    assert payload["units"]["ra"] == "m" and ra["unit"] in ("µm", "μm")
    assert ra["value"] == pytest.approx(payload["values"]["ra"] * 1e6, rel=1e-12)


def test_steps_are_one_row_per_load_step(lab: Lab, posted: dict[str, Any]) -> None:
    sim, run_id = posted["mtos"][0]
    steps = lab.run(run_id).steps()
    payload = lab.run(run_id).payload()
    assert len(steps) == sim.rows("steps") == 12
    np.testing.assert_array_equal(
        steps["friction_measured"].to_numpy(),
        [s["friction_measured"] for s in payload["values"]["steps"]],
    )
    assert steps.attrs["units"]["load"] == "N"
    assert "temperature_rise.t2" in steps.columns  # a mapping spread over columns
    assert lab.run(posted["profile"][1]).steps().empty


def test_a_series_members_and_statistics(lab: Lab, posted: dict[str, Any]) -> None:
    series = lab.series(posted["series"])
    members = series.members()
    assert set(members.index) == {run_id for _, run_id in posted["mtos"]}
    assert set(members["stand"]) == {"mtos"}
    stats = series.statistics()
    assert len(stats) > 0
    key = stats.index[0][0]
    row = stats.loc[(key, None)]
    # the mean over the runs of the members' own values (an independent average)
    assert row["n"] == 2
    assert row["mean"] == pytest.approx(members[key].mean(), rel=1e-9)


def test_a_run_followed_while_rigsim_posts_it(lab_server: Server, lab: Lab) -> None:
    sim = simulate(
        "pin_on_disc", TribometerSettings(laps=60, running_in_laps=10, batch_rows=300), seed=5
    )
    client = LabClient(lab_server.url, WRITER)
    run = client.create_run(sim.run_create)
    delivered = threading.Event()

    def post() -> None:
        for seq, batch in enumerate(sim.batches):
            client.post_batch(run.id, seq, batch)
            time.sleep(0.01)
        client.finish(run.id)
        delivered.set()

    poster = threading.Thread(target=post)
    poster.start()
    try:
        pieces = list(lab.run(run.id).follow("friction"))
    finally:
        poster.join(60)
        client.close()
    assert delivered.is_set()
    followed = pd.concat(pieces)
    assert list(followed.index) == list(range(sim.rows("friction")))  # none lost or repeated
    np.testing.assert_array_equal(followed["time"], sim.columns("friction")["time"])


class _DropOnce(httpx.BaseTransport):
    """The network, but the first live stream breaks after its first event."""

    def __init__(self) -> None:
        self._http = httpx.HTTPTransport()
        self.dropped = 0
        self.resumed_from: list[str] = []

    def handle_request(self, request: httpx.Request) -> httpx.Response:
        response = self._http.handle_request(request)
        if not request.url.path.endswith("/live"):
            return response
        self.resumed_from.append(request.headers.get("last-event-id", ""))
        if self.dropped:
            return response
        self.dropped += 1
        stream = response.stream

        class Broken(httpx.SyncByteStream):
            def __iter__(self) -> Iterator[bytes]:
                passed = b""
                for piece in stream:  # type: ignore[union-attr]
                    yield piece
                    passed += piece
                    _, rows, after = passed.partition(b"event: rows")
                    if rows and b"\n\n" in after:  # one whole event of rows went through
                        raise httpx.ReadError("connection reset by peer")

            def close(self) -> None:
                stream.close()  # type: ignore[union-attr]

        return httpx.Response(response.status_code, headers=response.headers, stream=Broken())


def test_a_dropped_live_connection_is_resumed(
    lab_server: Server, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr("rigclient.lab.RESUME_DELAY", 0.01)
    sim = simulate(
        "pin_on_disc", TribometerSettings(laps=40, running_in_laps=10, batch_rows=300), seed=6
    )
    client = LabClient(lab_server.url, WRITER)
    run = client.create_run(sim.run_create)
    half = len(sim.batches) // 2
    for seq, batch in enumerate(sim.batches[:half]):
        client.post_batch(run.id, seq, batch)
    transport = _DropOnce()
    with Lab(lab_server.url, READER, transport=transport) as lab:
        followed: list[pd.DataFrame] = []
        for piece in lab.run(run.id).follow("friction"):
            followed.append(piece)
            if len(followed) == 1:  # the rest arrives after the drop
                for seq, batch in enumerate(sim.batches[half:], start=half):
                    client.post_batch(run.id, seq, batch)
                client.finish(run.id)
    client.close()
    assert transport.dropped == 1 and len(transport.resumed_from) >= 2
    assert transport.resumed_from[1] == str(followed[0].index[-1] + 1)  # where it broke
    rows = pd.concat(followed)
    assert list(rows.index) == list(range(sim.rows("friction")))
    for name, values in sim.columns("friction").items():
        np.testing.assert_array_equal(rows[name], values)


def test_a_key_without_read_is_refused_saying_so(lab_server: Server) -> None:
    with Lab(lab_server.url, MTOS_ONLY) as lab, pytest.raises(ServerRefused) as refused:
        lab.runs()
    assert refused.value.problem.status == 403
    assert "read" in str(refused.value) and "/api/v1/runs" in str(refused.value)
    with Lab(lab_server.url) as anonymous, pytest.raises(ServerRefused) as unknown:
        anonymous.run("no-such-run")
    assert unknown.value.problem.status == 401


def test_readings_refused_say_why(lab: Lab, posted: dict[str, Any], lab_server: Server) -> None:
    """The readings' own connection says a refusal as every other request does: the
    problem document, the method and the URL."""
    _, run_id = posted["tribo"]
    with pytest.raises(ServerRefused) as refused:
        lab.run(run_id).readings("no_such_group")
    assert refused.value.problem.status == 422 and "no_such_group" in str(refused.value)
    assert f"/runs/{run_id}/readings" in str(refused.value)
    with Lab(lab_server.url, MTOS_ONLY) as other, pytest.raises(ServerRefused) as forbidden:
        LabRun(other, lab.run(run_id).info).readings("friction")
    assert forbidden.value.problem.status == 403


def test_an_unknown_run_says_which(lab: Lab) -> None:
    with pytest.raises(ServerRefused, match="404") as refused:
        lab.run("0" * 26)
    assert "0" * 26 in str(refused.value)


def test_downloads(lab: Lab, posted: dict[str, Any], tmp_path: Path) -> None:
    sim, run_id = posted["profile"]
    run = lab.run(run_id)
    pdf = run.download("report.pdf", tmp_path / "report.pdf", lang="ru")
    assert pdf.read_bytes().startswith(b"%PDF-")
    eln = run.download("export.eln", tmp_path / "run.eln")
    with zipfile.ZipFile(io.BytesIO(eln.read_bytes())) as archive:
        assert any(n.endswith("ro-crate-metadata.json") for n in archive.namelist())
    h5 = run.download("hdf5", tmp_path / "run.h5")
    with h5py.File(h5, "r") as f:
        np.testing.assert_array_equal(f["entry/profile/y"][...], sim.columns("profile")["y"])
    assert not list(tmp_path.glob("*.part"))
    with pytest.raises(Exception, match="choose one of"):
        run.download("report.docx", tmp_path / "x")


def test_a_lab_of_a_run_as_it_was_created(lab: Lab, lab_server: Server) -> None:
    """``info`` is the run as the API describes it: what it was opened with."""
    with LabClient(lab_server.url, WRITER) as client:
        opened = client.create_run(RunCreate(stand="profilometer", operator="Ivanova", title="T"))
    run: LabRun = lab.run(opened.id)
    assert (run.stand, run.state, run.info.operator, run.info.title) == (
        "profilometer",
        "open",
        "Ivanova",
        "T",
    )
    assert "Ivanova" in {r.info.operator for r in lab.runs(operator="Ivanova")}


def test_the_readmes_lines_get_a_run_into_a_frame(
    lab_server: Server, posted: dict[str, Any]
) -> None:
    """README, "Your data in Python": the block as printed, with this server's URL."""
    code = block(section("Your data in Python"), "python")
    assert '"http://127.0.0.1:8000"' in code
    namespace: dict[str, Any] = {"key": READER}
    exec(code.replace('"http://127.0.0.1:8000"', repr(lab_server.url)), namespace)
    namespace["lab"].close()
    sim, run_id = posted["mtos"][1]  # the newest finished MTOS run
    assert namespace["run"].id == run_id
    np.testing.assert_array_equal(namespace["df"]["load"], sim.columns("steps")["load"])
    assert namespace["df"].attrs["units"]["load"] == "N"
