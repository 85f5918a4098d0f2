"""Low-level failures (OSError, sqlite3, h5py) translated into the storage error tree."""

from __future__ import annotations

import errno
import sqlite3
from collections.abc import Iterator
from contextlib import contextmanager

from rigserver.storage.errors import StorageError, StorageFull, StorageUnavailable

#: What the journal and the HDF5 layer raise when the disk, the file or the library fails
#: (h5py raises ``OSError`` for I/O and ``RuntimeError`` for some library failures).
LOW_LEVEL: tuple[type[Exception], ...] = (OSError, RuntimeError, sqlite3.Error)
#: What reading a damaged run file may raise (pydantic's ValidationError is a ValueError).
UNREADABLE: tuple[type[Exception], ...] = (*LOW_LEVEL, ValueError, KeyError)

_FULL_TEXTS = ("no space left on device", "database or disk is full", "disk quota exceeded")


def is_disk_full(exc: BaseException) -> bool:
    """ENOSPC/EDQUOT from the OS (h5py puts the errno text in its message) or SQLITE_FULL."""
    if isinstance(exc, OSError) and exc.errno in (errno.ENOSPC, errno.EDQUOT):
        return True
    if isinstance(exc, sqlite3.Error) and getattr(exc, "sqlite_errorcode", None) == (
        sqlite3.SQLITE_FULL
    ):
        return True
    text = str(exc).lower()
    return any(t in text for t in _FULL_TEXTS)


def translated(exc: BaseException, doing: str) -> StorageError:
    """The storage error to raise (``from exc``) for a low-level failure while ``doing``."""
    if isinstance(exc, StorageError):
        return exc
    if is_disk_full(exc):
        return StorageFull(
            f"the disk of the data directory is full while {doing}; nothing more was "
            f"acknowledged: free some space and retry ({exc})"
        )
    return StorageUnavailable(f"storage failed while {doing}: {exc}")


@contextmanager
def failures_as(doing: str) -> Iterator[None]:
    """Translate the low-level failures raised in the block (``raise ... from``)."""
    try:
        yield
    except LOW_LEVEL as exc:
        raise translated(exc, doing) from exc
