"""A throwaway HSDS service (unix sockets, POSIX storage in a temp directory) for the tests
of the run arrays in HSDS; skipped with one reason when hsds or h5pyd is not installed."""

from __future__ import annotations

import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

from rigserver.storage.servers.hsdsserver import LocalHsds, NoHsds, start_hsds

NO_HSDS = "the HSDS tests are skipped: {}"


@pytest.fixture(scope="session")
def hsds_service() -> Iterator[LocalHsds]:
    directory = Path(tempfile.mkdtemp(prefix="rig-hsds-test-"))
    try:
        service = start_hsds(directory)
    except NoHsds as exc:
        shutil.rmtree(directory, ignore_errors=True)
        pytest.skip(NO_HSDS.format(exc))
    try:
        yield service
    finally:
        service.stop()
        shutil.rmtree(directory, ignore_errors=True)
