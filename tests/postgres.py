"""A throwaway PostgreSQL server for the tests of the cluster deployment.

``postgres_server`` (session scope) starts one in a temp directory with
:mod:`rigserver.storage.servers.pgserver`, or skips with one reason when the server binaries are
not installed; ``postgres_url`` gives each test empty tables.
"""

from __future__ import annotations

import shutil
import socket
import tempfile
from collections.abc import Iterator
from pathlib import Path

import psycopg
import pytest

from rigserver.storage.servers.pgserver import LocalPostgres, NoPostgres, start_local

NO_POSTGRES = "the PostgreSQL tests are skipped: {}"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture(scope="session")
def postgres_server() -> Iterator[LocalPostgres]:
    directory = Path(tempfile.mkdtemp(prefix="rig-pg-test-"))
    directory.chmod(0o711)  # the server's user (not root) passes through it
    try:
        server = start_local(directory / "pg", free_port())
    except NoPostgres as exc:
        shutil.rmtree(directory, ignore_errors=True)
        pytest.skip(NO_POSTGRES.format(exc))
    try:
        yield server
    finally:
        server.stop("immediate")
        shutil.rmtree(directory, ignore_errors=True)


def empty_tables(url: str) -> None:
    """Drop what the last test stored (the store creates its tables again)."""
    with psycopg.connect(url, autocommit=True) as conn:
        conn.execute("DROP TABLE IF EXISTS rig_corrections, rig_batches, rig_runs, rig_hsds_marks")


@pytest.fixture
def postgres_url(postgres_server: LocalPostgres) -> Iterator[str]:
    empty_tables(postgres_server.url)
    yield postgres_server.url
    empty_tables(postgres_server.url)
