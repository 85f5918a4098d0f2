"""Test-wide settings and fixtures: hypothesis runs derandomized in CI, so a failure
reproduces; ``server`` is a ``rigserver serve`` process on a fresh data directory."""

import json
import os
from collections.abc import Iterator
from pathlib import Path

import pytest
from hypothesis import settings

from tests.api.conftest import KEYS, Server
from tests.processes import kill_leftovers, leftovers

# A finished run's reports are rendered at its first download, not at once in the background:
# hundreds of tests finish runs, and rendering each one's four reports was most of the suite's
# CPU. tests/api/test_report_files.py turns it back on where the background render is the
# point; the servers the tests start inherit the setting.
os.environ.setdefault("RIG_REPORTS_ON_FINISH", "false")

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
    try:
        yield srv
    finally:
        srv.stop()


@pytest.fixture(scope="session", autouse=True)
def no_process_left_behind() -> Iterator[None]:
    """The session ends with no ``rigserver`` or ``rigsim`` process of its own running
    (issue 14, item 7): every test stops the process groups it started."""
    yield
    stray = leftovers()
    kill_leftovers()
    assert not stray, f"processes left behind by the tests: {stray}"
