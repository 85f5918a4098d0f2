"""What the service does per request beyond its own work (docs/speed.md, issue 25)."""

from __future__ import annotations

from pathlib import Path

import pytest
from fastapi.testclient import TestClient
from opentelemetry import metrics, trace

from tests.api.conftest import WRITER, auth
from tests.hardening.conftest import API, hdf5_app, open_run


def test_a_post_asks_no_opentelemetry_provider(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # FastAPI's native telemetry, left on, asks for the global providers on every request
    asked: list[str] = []
    for module in (trace, metrics):
        name = "get_tracer_provider" if module is trace else "get_meter_provider"
        real = getattr(module, name)
        monkeypatch.setattr(module, name, lambda real=real, name=name: asked.append(name) or real())
    with TestClient(hdf5_app(tmp_path / "data")) as http:
        run_id = open_run(http)
        for seq in range(3):
            reading = {"time": [seq * 1e-3], "load": [300.0], "speed": [1000.0]}
            reading |= {"friction_moment": [2.5], "revolutions": [0.0]}
            r = http.post(
                f"{API}/runs/{run_id}/readings",
                json={"seq": seq, "group": "friction", "columns": reading},
                headers=auth(WRITER),
            )
            assert r.status_code == 201, r.text
    assert asked == []
