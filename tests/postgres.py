"""A throwaway PostgreSQL server for the tests of the cluster deployment.

``postgres_server`` (session scope) starts one in a temp directory with
:mod:`rigserver.storage.servers.pgserver`, or skips with one reason when the server binaries are
not installed; ``postgres_url`` gives each test empty tables; :func:`sqlite_or_postgres` opens
a small store embedded or in the cluster, for the tests that hold both to the same behaviour.
"""

from __future__ import annotations

import socket
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Protocol, TypeVar

import psycopg
import pytest

from rigserver.storage.servers.pgserver import LocalPostgres, NoPostgres, start_local
from tests.servers import throwaway

NO_POSTGRES = "the PostgreSQL tests are skipped: {}"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _start(directory: Path) -> LocalPostgres:
    directory.chmod(0o711)  # the server's user (not root) passes through it
    return start_local(directory / "pg", free_port())


def _stop(server: LocalPostgres) -> None:
    server.stop("immediate")


@pytest.fixture(scope="session")
def postgres_server() -> Iterator[LocalPostgres]:
    yield from throwaway("rig-pg-test-", _start, _stop, NoPostgres, NO_POSTGRES)


#: The run store's tables in the cluster.
RUN_TABLES = "rig_corrections, rig_batches, rig_runs, rig_hsds_marks"


def empty_tables(url: str, tables: str = RUN_TABLES) -> None:
    """Drop what the last test stored in ``tables`` (the store creates its tables again)."""
    with psycopg.connect(url, autocommit=True) as conn:
        conn.execute(f"DROP TABLE IF EXISTS {tables}")


@pytest.fixture
def postgres_url(postgres_server: LocalPostgres) -> Iterator[str]:
    empty_tables(postgres_server.url)
    yield postgres_server.url
    empty_tables(postgres_server.url)


class Closing(Protocol):
    def close(self) -> None: ...


Embedded = TypeVar("Embedded", bound=Closing)
Cluster = TypeVar("Cluster", bound=Closing)


def sqlite_or_postgres(
    request: pytest.FixtureRequest,
    sqlite: Callable[[], Embedded],
    postgres: Callable[[str], Cluster],
    tables: str,
) -> Iterator[Embedded | Cluster]:
    """The body of a fixture with ``params=["sqlite", "postgres"]``: the embedded store, or the
    cluster's on empty ``tables``; closed after the test."""
    store: Embedded | Cluster
    if request.param == "sqlite":
        store = sqlite()
    else:
        url = request.getfixturevalue("postgres_url")
        empty_tables(url, tables)
        store = postgres(url)
    yield store
    store.close()
