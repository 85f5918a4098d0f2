"""Profiles that the post accepts and that once broke the finish (issue 39): a gap that made
the resampling (and the X3P) grow with the span of x instead of the points received (item 1),
and heights whose derived numbers overflow (item 7)."""

from __future__ import annotations

import io
import math
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest
import x3pio
from fastapi.testclient import TestClient
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from numpy.typing import ArrayLike
from pydantic import BaseModel

from rigserver.analysis import analyse
from rigserver.core.profile_filter import RESAMPLING_LIMIT
from schemas.runs import Run
from tests.analysis.conftest import FakeReadings
from tests.api.conftest import READER, WRITER, auth
from tests.api.test_service import open_run

API = "/api/v1"


def _post_profile(client: TestClient, x_mm: list[float], y_um: list[float]) -> str:
    run_id = open_run(client, "profilometer")
    body = {"seq": 0, "group": "profile", "columns": {"x": x_mm, "y": y_um}}
    r = client.post(f"{API}/runs/{run_id}/readings", json=body, headers=auth(WRITER))
    assert r.status_code == 201, r.text
    return run_id


def grids_made(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The sizes of the grids np.interp is asked for from now on (every resampling)."""
    made: list[int] = []
    interp = np.interp

    def spy(grid: ArrayLike, *args: Any, **kwargs: Any) -> Any:
        made.append(np.size(grid))
        return interp(grid, *args, **kwargs)

    monkeypatch.setattr(np, "interp", spy)
    return made


def test_a_trace_with_a_huge_gap_is_analysed_in_parts_within_its_size(
    client: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    """1000 points 1 µm apart, then one point 100 mm away: before, the finish interpolated the
    trace onto a grid of 10⁵ points of 1 µm (and the X3P held them all)."""
    n = 1000
    x_mm = [i * 1e-3 for i in range(n)] + [100.0]  # the post's limit of x
    y_um = [float(np.sin(2 * np.pi * i / 40)) for i in range(n)] + [0.0]
    received = len(x_mm)
    made = grids_made(monkeypatch)
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


def _numbers(node: object, path: str = "") -> Iterator[tuple[str, float]]:
    """Every number of a results model (or its JSON), with its path."""
    if isinstance(node, BaseModel):
        node = dict(node)
    if isinstance(node, dict):
        for key, value in node.items():
            yield from _numbers(value, f"{path}.{key}")
    elif isinstance(node, list | tuple):
        for i, value in enumerate(node):
            yield from _numbers(value, f"{path}[{i}]")
    elif isinstance(node, float | int) and not isinstance(node, bool):
        yield path, float(node)


_SCALES = (1e-300, 1e-200, 1e-12, 1e-3, 1.0, 1000.0)  # µm, within the post's limit of ±1000


@st.composite
def posted_profiles(draw: st.DrawFn) -> tuple[list[float], list[float]]:
    """Profiles the post accepts: x strictly increasing in [0, 100] mm (steps down to 1e-300
    mm, a gap or none), heights within ±1000 µm of any magnitude, constant, a step or two
    points."""
    n = draw(st.integers(min_value=2, max_value=300))
    step = draw(st.sampled_from((1e-300, 1e-9, 1e-3, 0.01, 1.0)))
    x = draw(st.floats(min_value=0.0, max_value=10.0)) + step * np.arange(n)
    if draw(st.booleans()):  # a gap before the last point, to the post's limit of x
        x[-1] = 100.0
    assume(np.all(np.diff(x) > 0) and x[-1] <= 100.0)
    scale = draw(st.sampled_from(_SCALES))
    shape = draw(st.sampled_from(("random", "constant", "step", "sine")))
    if shape == "random":
        unit = np.array(draw(st.lists(st.floats(-1.0, 1.0), min_size=n, max_size=n)))
    elif shape == "constant":
        unit = np.full(n, draw(st.floats(-1.0, 1.0)))
    elif shape == "step":
        unit = np.where(np.arange(n) < n // 2, 0.0, 1.0)
    else:
        unit = np.sin(np.arange(n) * 0.7)
    return [float(v) for v in x], [float(v) for v in scale * unit]


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(profile=posted_profiles())
@example(profile=([0.01 * i for i in range(60)], [1e-300 * math.sin(0.7 * i) for i in range(60)]))
@example(profile=([0.0, 1.0], [1.0, -1.0]))
@example(  # Rsk and Rku of ISO: Rq³ underflowed to 0
    profile=([0.001 * i for i in range(300)], [1e-300 * math.sin(0.7 * i) for i in range(300)])
)
@example(  # Δ and b of (1.8) overflowed
    profile=(
        [1e-300 * i for i in range(16)] + [100.0],
        [1e-300 * math.sin(0.7 * i) for i in range(17)],
    )
)
@example(profile=([0.01 * i for i in range(300)], [1e-300 * (i >= 150) for i in range(300)]))
@example(profile=([0.01 * i for i in range(60)], [5.0] * 60))
@example(profile=([1e-300 * i for i in range(60)], [math.sin(0.7 * i) for i in range(60)]))
def test_every_profile_the_post_accepts_finishes_with_finite_results(
    client: TestClient, profile: tuple[list[float], list[float]]
) -> None:
    """A profile of heights around 1e-300 µm once posted (201) and then every finish answered
    422 "radius must be finite, got inf": the run could never finish. Now the finish answers
    200 and what cannot be computed is None with the reason in pending or notes."""
    x_mm, y_um = profile
    run_id = _post_profile(client, x_mm, y_um)
    finished = client.post(f"{API}/runs/{run_id}/finish", headers=auth(WRITER))
    assert finished.status_code == 200, finished.text
    values = client.get(f"{API}/runs/{run_id}/results", headers=auth(READER)).json()["values"]
    run = Run.model_validate(finished.json())
    found = analyse(run, FakeReadings({"profile": {"x": x_mm, "y": y_um}}, {}))
    bad = [(p, v) for p, v in _numbers(found.values) if not math.isfinite(v)]
    assert not bad, bad
    assert values["ra"] is not None or values["pending"]
    assert values["complex_parameter"] is not None or values["pending"] or values["notes"]
    x3p = client.get(f"{API}/runs/{run_id}/profile.x3p", headers=auth(READER))
    assert x3p.status_code == 200 and len(x3p.content) <= 24 * len(x_mm) + 16_384
