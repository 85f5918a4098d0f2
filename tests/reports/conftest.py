"""The service the report and download routes are tried on (in process, in-memory store)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from schemas.stands import StandKind
from tests.api.conftest import WRITER, in_process
from tests.reports.simulated import post, simulated


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[TestClient, dict[str, str]]]:
    """The service with finished SMTs-2, MTOS and profilometer runs and an open
    slide-bearing run."""
    with in_process(Path(tmp_path_factory.mktemp("data"))) as client:
        ids = {
            "smts2": post(client, simulated(StandKind.SMTS2).sim, WRITER),
            "open": post(client, simulated(StandKind.SLIDE_BEARING).sim, WRITER, finish=False),
            "mtos": post(client, simulated(StandKind.MTOS).sim, WRITER),
            "profile": post(client, simulated(StandKind.PROFILOMETER).sim, WRITER),
        }
        yield client, ids
