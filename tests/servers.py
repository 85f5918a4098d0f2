"""The throwaway servers of the tests (PostgreSQL, HSDS): each started in a temp directory of
its own and removed with it; the tests that need one are skipped, with one reason, when its
binaries are not installed."""

from __future__ import annotations

import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TypeVar

import pytest

T = TypeVar("T")


def throwaway(
    prefix: str,
    start: Callable[[Path], T],
    stop: Callable[[T], None],
    missing: type[Exception],
    reason: str,
) -> Iterator[T]:
    """The body of a fixture: ``start(directory)`` in a new temp directory named ``prefix...``,
    stopped by ``stop`` and the directory removed after the last test; the tests skipped with
    ``reason`` (formatted with the error) when ``start`` raises ``missing``."""
    with tempfile.TemporaryDirectory(prefix=prefix, ignore_cleanup_errors=True) as name:
        try:
            server = start(Path(name))
        except missing as exc:
            pytest.skip(reason.format(exc))
        try:
            yield server
        finally:
            stop(server)
