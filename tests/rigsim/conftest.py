"""A real rigserver over HTTP for the end-to-end tests (the API tests' ``Server`` helper)."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.api.conftest import KEYS, Server


@pytest.fixture
def server(tmp_path: Path) -> Iterator[Server]:
    keys_file = tmp_path / "keys.json"
    keys_file.write_text(json.dumps(KEYS))
    srv = Server(tmp_path / "data", keys_file)
    srv.start()
    yield srv
    srv.stop()
