"""Test-wide settings and fixtures: hypothesis runs derandomized in CI, so a failure
reproduces; ``server`` is a ``rigserver serve`` process on a fresh data directory."""

import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from hypothesis import settings

from tests.api.conftest import Server, served
from tests.processes import kill_leftovers, leftovers

# A finished run's reports are rendered at its first download, not at once in the background:
# hundreds of tests finish runs, and rendering each one's four reports was most of the suite's
# CPU. tests/api/test_report_files.py turns it back on where the background render is the
# point; the servers the tests start inherit the setting.
os.environ.setdefault("RIG_REPORTS_ON_FINISH", "false")

settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


#: Packages whose package-scoped fixture costs most of their time (tests/eln: every stand's
#: run rendered and exported): the whole package goes to one worker, so it is built once.
ONE_WORKER = ("tests/eln/",)


def pytest_xdist_make_scheduler(config: pytest.Config, log: Any) -> Any:
    """``--dist loadfile`` that keeps each of :data:`ONE_WORKER` on one worker."""
    if config.getoption("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class Scheduling(LoadFileScheduling):
        def _split_scope(self, nodeid: str) -> str:
            package = next((p for p in ONE_WORKER if nodeid.startswith(p)), None)
            return package or super()._split_scope(nodeid)

    return Scheduling(config, log)


@pytest.fixture
def server(tmp_path: Path) -> Iterator[Server]:
    """The service over HTTP, with the test keys (tests.api.conftest.KEYS)."""
    with served(tmp_path) as srv:
        yield srv


@pytest.fixture(scope="session", autouse=True)
def no_process_left_behind() -> Iterator[None]:
    """The session ends with no ``rigserver`` or ``rigsim`` process of its own running
    (issue 14, item 7): every test stops the process groups it started."""
    yield
    stray = leftovers()
    kill_leftovers()
    assert not stray, f"processes left behind by the tests: {stray}"
