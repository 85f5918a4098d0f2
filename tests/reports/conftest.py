"""The service the report and download routes are tried on (in process, in-memory store)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from rigserver.api.app import create_app
from rigserver.api.auth import ApiKey
from rigserver.api.settings import Settings
from rigserver.storage import MemoryStore
from schemas.stands import StandKind, configure_stands
from tests.api.conftest import KEYS, WRITER
from tests.reports.simulated import post, simulated


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[TestClient, dict[str, str]]]:
    """The service with finished SMTs-2, MTOS and profilometer runs and an open
    slide-bearing run."""
    settings = Settings(data_dir=Path(tmp_path_factory.mktemp("data")))
    app = create_app(
        settings, MemoryStore(), [ApiKey.model_validate(k) for k in KEYS], configure_stands()
    )
    with TestClient(app, raise_server_exceptions=False) as client:
        ids = {
            "smts2": post(client, simulated(StandKind.SMTS2).sim, WRITER),
            "open": post(client, simulated(StandKind.SLIDE_BEARING).sim, WRITER, finish=False),
            "mtos": post(client, simulated(StandKind.MTOS).sim, WRITER),
            "profile": post(client, simulated(StandKind.PROFILOMETER).sim, WRITER),
        }
        yield client, ids
