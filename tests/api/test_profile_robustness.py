"""Profiles that the post accepts and that once broke the finish (issue 39): a gap that made
the resampling (and the X3P) grow with the span of x instead of the points received (item 1),
and heights whose derived numbers overflow (item 7)."""

from __future__ import annotations

import io
from typing import Any

import numpy as np
import pytest
import x3pio
from fastapi.testclient import TestClient
from numpy.typing import ArrayLike

from rigserver.core.profile_filter import RESAMPLING_LIMIT
from tests.api.conftest import READER, WRITER, auth
from tests.api.test_service import open_run

API = "/api/v1"


def _post_profile(client: TestClient, x_mm: list[float], y_um: list[float]) -> str:
    run_id = open_run(client, "profilometer")
    body = {"seq": 0, "group": "profile", "columns": {"x": x_mm, "y": y_um}}
    r = client.post(f"{API}/runs/{run_id}/readings", json=body, headers=auth(WRITER))
    assert r.status_code == 201, r.text
    return run_id


def test_a_trace_with_a_huge_gap_is_analysed_in_parts_within_its_size(
    client: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    """1000 points 1 µm apart, then one point 100 mm away: before, the finish interpolated the
    trace onto a grid of 10⁵ points of 1 µm (and the X3P held them all)."""
    n = 1000
    x_mm = [i * 1e-3 for i in range(n)] + [100.0]  # the post's limit of x
    y_um = [float(np.sin(2 * np.pi * i / 40)) for i in range(n)] + [0.0]
    received = len(x_mm)
    made: list[int] = []
    interp = np.interp

    def spy(grid: ArrayLike, *args: Any, **kwargs: Any) -> Any:
        made.append(np.size(grid))
        return interp(grid, *args, **kwargs)

    monkeypatch.setattr(np, "interp", spy)
    run_id = _post_profile(client, x_mm, y_um)
    finished = client.post(f"{API}/runs/{run_id}/finish", headers=auth(WRITER))
    assert finished.status_code == 200, finished.text
    assert max(made) <= RESAMPLING_LIMIT * received
    values = client.get(f"{API}/runs/{run_id}/results", headers=auth(READER)).json()["values"]
    assert values["iso"]["parts"] == 1  # the lone point is too short a part to analyse
    assert any("analysed in its parts" in note for note in values["notes"])
    # the first part alone: a sine of 40 steps, Rq = A/√2 (the filter passes λ = 40 µm
    # at λc = 0.08 mm with 1 - exp(-π(αλc/λ)²) > 0.99)
    assert values["iso"]["rq"] == pytest.approx(1e-6 / np.sqrt(2), rel=0.02)
    made.clear()
    x3p = client.get(f"{API}/runs/{run_id}/profile.x3p", headers=auth(READER))
    assert x3p.status_code == 200
    assert not made or max(made) <= RESAMPLING_LIMIT * received
    # the points as received, 3 coordinates of 8 bytes each, and the file's XML
    assert len(x3p.content) <= 24 * received + 16_384
    found = x3pio.read(io.BytesIO(x3p.content))
    assert "points as received" in (found.metadata.comment or "")
