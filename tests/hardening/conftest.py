"""The service with HDF5 storage in process, readings of the SMTs-2 friction record, and the
real server in a subprocess (tests.api.conftest.Server) with extra options."""

from __future__ import annotations

import io
import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fastapi import FastAPI
from fastapi.testclient import TestClient
from numpy.typing import NDArray

from rigserver.api.app import create_app
from rigserver.api.auth import ApiKey
from rigserver.api.settings import Settings
from rigserver.storage import HDF5Store
from schemas.stands import configure_stands
from tests.api.conftest import KEYS, WRITER, Server, auth

API = "/api/v1"


def hdf5_app(data_dir: Path, **settings: Any) -> FastAPI:
    """The service over an HDF5 store in ``data_dir``, with the test keys."""
    store = HDF5Store(data_dir)
    keys = [ApiKey.model_validate(k) for k in KEYS]
    return create_app(Settings(data_dir=data_dir, **settings), store, keys, configure_stands())


@pytest.fixture
def hdf5_client(tmp_path: Path) -> Iterator[TestClient]:
    with TestClient(hdf5_app(tmp_path / "data"), raise_server_exceptions=False) as c:
        yield c


def friction(start: int, rows: int) -> dict[str, NDArray[np.float64]]:
    """Rows ``start ..`` of a friction record; row k has time k (s), so rows are traceable."""
    k = np.arange(start, start + rows, dtype=np.float64)
    return {
        "time": k,
        "load": np.full(rows, 300.0),
        "speed": np.full(rows, 1000.0),
        "friction_moment": 2.5 + (k % 10) / 10,
        "revolutions": np.floor(k / 100),
    }


def json_batch(seq: int, start: int, rows: int) -> dict[str, Any]:
    columns = {name: values.tolist() for name, values in friction(start, rows).items()}
    return {"seq": seq, "group": "friction", "columns": columns}


def npz_body(columns: dict[str, Any]) -> bytes:
    buffer = io.BytesIO()
    np.savez(buffer, **columns)
    return buffer.getvalue()


def open_run(http: Any, stand: str = "smts2") -> str:
    """Open a run through a TestClient or an httpx.Client (base URL of the server)."""
    r = http.post(f"{API}/runs", json={"stand": stand, "operator": "Sidorov"}, headers=auth(WRITER))
    assert r.status_code == 201, r.text
    return str(r.json()["id"])


def is_problem(response: Any) -> bool:
    return bool(
        response.headers.get("content-type", "").startswith("application/problem+json")
        and response.json()["status"] == response.status_code
    )


def keys_file(tmp_path: Path) -> Path:
    path = tmp_path / "keys.json"
    path.write_text(json.dumps(KEYS))
    return path


def serve(tmp_path: Path, *args: str, **env: str) -> Server:
    """A started server on ``tmp_path/data`` with more ``rigserver serve`` options."""
    server = Server(tmp_path / "data", keys_file(tmp_path), args=args, env=env)
    server.start()
    return server
