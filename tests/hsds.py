"""A throwaway HSDS service (unix sockets, POSIX storage in a temp directory) for the tests
of the run arrays in HSDS; skipped with one reason when hsds or h5pyd is not installed."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from rigserver.storage.servers.hsdsserver import LocalHsds, NoHsds, start_hsds
from tests.servers import throwaway

NO_HSDS = "the HSDS tests are skipped: {}"


@pytest.fixture(scope="session")
def hsds_service() -> Iterator[LocalHsds]:
    yield from throwaway("rig-hsds-test-", start_hsds, LocalHsds.stop, NoHsds, NO_HSDS)
