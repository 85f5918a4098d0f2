"""Test-wide settings and fixtures: hypothesis runs derandomized in CI, so a failure
reproduces; ``server`` is a ``rigserver serve`` process on a fresh data directory."""

import json
import os
from collections.abc import Iterator
from pathlib import Path

import pytest
from hypothesis import settings

from tests.api.conftest import KEYS, Server

settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


@pytest.fixture
def server(tmp_path: Path) -> Iterator[Server]:
    """The service over HTTP, with the test keys (tests.api.conftest.KEYS)."""
    keys_file = tmp_path / "keys.json"
    keys_file.write_text(json.dumps(KEYS))
    srv = Server(tmp_path / "data", keys_file)
    srv.start()
    yield srv
    srv.stop()
