"""``GET /runs/{id}/profile.x3p``: the traced profile as an X3P file (ISO 25178-72) that
other software opens, read back here with x3pio (issue 23)."""

from __future__ import annotations

import io

import numpy as np
import pytest
import x3pio
from fastapi.testclient import TestClient

from rigserver.analysis import profilometer
from rigserver.core.profile_filter import RESAMPLING_LIMIT
from rigserver.reports.i18n import Messages
from rigserver.reports.labs import iso_profile
from rigserver.reports.x3p import NoProfile, profile_group, profile_x3p
from schemas.stands import StandKind, default_stands
from tests.analysis.conftest import FakeReadings, make_run
from tests.api.conftest import READER, auth
from tests.api.test_profile_robustness import grids_made
from tests.reports.simulated import simulated

API = "/api/v1"
PROFILE = default_stands()[StandKind.PROFILOMETER].group("profile")


def test_the_profile_reads_back_as_posted(served: tuple[TestClient, dict[str, str]]) -> None:
    client, ids = served
    answer = client.get(f"{API}/runs/{ids['profile']}/profile.x3p", headers=auth(READER))
    assert answer.status_code == 200
    assert answer.headers["content-type"] == "application/x-x3p"
    assert f'filename="{ids["profile"]}-profile.x3p"' in answer.headers["content-disposition"]
    found = x3pio.read(io.BytesIO(answer.content))
    assert isinstance(found, x3pio.Profile)
    layer = found.layers[0]
    posted = simulated(StandKind.PROFILOMETER).sim.columns("profile")
    x_m, y_m = posted["x"] * 1e-3, posted["y"] * 1e-6  # mm and µm as posted
    assert layer.header.x.is_incremental
    assert layer.header.x.increment == pytest.approx(float(np.median(np.diff(x_m))), rel=1e-9)
    assert np.allclose(np.asarray(layer.z).ravel(), y_m, rtol=0, atol=1e-15)
    assert found.metadata is not None and found.metadata.instrument.model == "ABRIS-PM7"
    assert ids["profile"] in (found.metadata.comment or "")


def test_a_run_without_a_profile_has_no_x3p(served: tuple[TestClient, dict[str, str]]) -> None:
    client, ids = served
    answer = client.get(f"{API}/runs/{ids['smts2']}/profile.x3p", headers=auth(READER))
    assert answer.status_code == 404
    assert answer.headers["content-type"].startswith("application/problem+json")
    other = client.get(
        f"{API}/runs/{ids['profile']}/profile.x3p?group=measurements", headers=auth(READER)
    )
    assert other.status_code == 404
    assert client.get(f"{API}/runs/nope/profile.x3p", headers=auth(READER)).status_code == 404


def test_the_x3p_needs_a_read_key(served: tuple[TestClient, dict[str, str]]) -> None:
    client, ids = served
    assert client.get(f"{API}/runs/{ids['profile']}/profile.x3p").status_code == 401


def test_an_uneven_trace_is_written_on_a_uniform_step() -> None:
    x_mm = np.array([0.0, 0.001, 0.0021, 0.003, 0.004, 0.0049, 0.006])
    y_um = np.array([0.0, 1.0, 0.0, -1.0, 0.0, 1.0, 0.0])
    readings = FakeReadings({"profile": {"x": list(x_mm), "y": list(y_um)}}, {})
    assert PROFILE is not None
    data = profile_x3p(make_run(StandKind.PROFILOMETER), PROFILE, readings)
    found = x3pio.read(io.BytesIO(data))
    layer = found.layers[0]
    assert layer.header.x.increment == pytest.approx(1e-6)  # the median step
    grid = np.arange(7) * 1e-6
    expected = np.interp(grid, x_mm * 1e-3, y_um * 1e-6)
    assert np.allclose(np.asarray(layer.z).ravel(), expected, atol=1e-15)
    assert found.metadata is not None and "interpolated" in (found.metadata.comment or "")


def test_only_a_group_of_lengths_is_a_profile() -> None:
    stand = default_stands()[StandKind.SMTS2]
    with pytest.raises(NoProfile):
        profile_group(stand.groups, "friction")


def test_the_run_page_links_the_x3p_of_a_profile_only(
    served: tuple[TestClient, dict[str, str]],
) -> None:
    client, ids = served
    page = client.get(f"/runs/{ids['profile']}", headers=auth(READER)).text
    assert f'href="{API}/runs/{ids["profile"]}/profile.x3p"' in page
    assert "profile.x3p" not in client.get(f"/runs/{ids['smts2']}", headers=auth(READER)).text


def test_the_run_page_and_the_csv_show_the_iso_results(
    served: tuple[TestClient, dict[str, str]],
) -> None:
    client, ids = served
    page = client.get(f"/runs/{ids['profile']}/results?lang=ru", headers=auth(READER)).text
    for path in ("ra", "iso.ra", "iso.rk", "iso.lambda_c", "iso.lambda_s", "iso.ends"):
        assert f'data-path="{path}"' in page, path
    text = client.get(f"{API}/runs/{ids['profile']}/results.csv", headers=auth(READER)).text
    assert "cut-off λc of the roughness filter" in text
    assert "arithmetic mean height of the roughness profile" in text


def test_the_iso_figure_of_a_trace_with_a_gap_stays_within_its_points(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The report's ISO figure analyses the trace again: a gap of 100 mm after 1000 points
    1 µm apart draws the parts, not a grid of 10⁵ points (issue 39)."""
    x = np.r_[np.arange(1000) * 1e-6, 0.1]
    y = np.r_[1e-6 * np.sin(2 * np.pi * np.arange(1000) / 40), 0.0]
    readings = FakeReadings({"profile": {"x": list(x * 1e3), "y": list(y * 1e6)}}, {})
    values = profilometer.analyse(make_run(StandKind.PROFILOMETER), readings)
    assert values.iso is not None and values.iso.parts == 1
    made = grids_made(monkeypatch)
    section = iso_profile.profilometer_section(Messages("en"), values, {"x": x, "y": y})
    assert section is not None
    assert made and max(made) <= RESAMPLING_LIMIT * x.size
