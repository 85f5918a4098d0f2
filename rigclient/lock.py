"""One agent per spool: an OS lock on ``spool.lock`` in the spool's directory.

A :class:`rigclient.Client` holds :class:`SpoolLock` for its life: ``fcntl.flock`` on POSIX,
``msvcrt.locking`` on Windows, taken without blocking and dropped by the OS when the process
ends, however it ends (a kill -9 or a power cut leave no stale lock). ``spool.owner`` (pid,
command, since when) names the holder in the error a second agent gets.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import sys
import time
from datetime import datetime
from pathlib import Path

from rigclient.errors import SpoolBusy, SpoolError
from rigclient.jsontext import loads_json

LOCKNAME = "spool.lock"
OWNERNAME = "spool.owner"


class SpoolLock:
    """The lock of the spool in ``directory``: one process delivers it at a time.

    An OS lock (``flock`` on POSIX, ``msvcrt.locking`` on Windows) on ``spool.lock``, held
    until :meth:`release` or the end of the process, however it ends (a kill -9 or a power
    cut leave no stale lock). ``spool.owner`` says who holds it: pid, command, since when.
    """

    def __init__(self, directory: str | Path) -> None:
        self.directory = Path(directory)
        self.path = self.directory / LOCKNAME
        self._fd: int | None = None

    def acquire(self, wait: float = 2.0) -> None:
        """Take the lock, waiting up to ``wait`` s; :class:`SpoolBusy` naming its holder."""
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise SpoolError(
                f"could not open the lock of the spool {self.directory}: {exc}"
            ) from exc
        deadline = time.monotonic() + wait
        while not _try_lock(fd):
            if time.monotonic() >= deadline:
                os.close(fd)
                raise SpoolBusy(
                    f"the spool {self.directory} is in use by {owner(self.directory)}; one "
                    "agent per spool: stop that one first, or give this one its own --spool"
                )
            time.sleep(0.05)
        self._fd = fd
        since = datetime.now().astimezone().isoformat(timespec="seconds")
        prog = Path(sys.argv[0]).name if sys.argv and sys.argv[0] else "python"
        if prog in ("cli.py", "__main__.py", "-c"):  # python -m rigclient.cli
            prog = "rigclient"
        command = " ".join([prog, *sys.argv[1:]])
        info = {"pid": os.getpid(), "command": command, "since": since}
        with contextlib.suppress(OSError):  # who holds it is a courtesy; the lock is the fd
            (self.directory / OWNERNAME).write_text(json.dumps(info), encoding="utf-8")

    def release(self) -> None:
        if self._fd is not None:
            with contextlib.suppress(OSError):
                (self.directory / OWNERNAME).unlink()
            os.close(self._fd)  # closing the descriptor drops the OS lock
            self._fd = None

    def __enter__(self) -> SpoolLock:
        self.acquire()
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()


def held_by(directory: str | Path) -> str | None:
    """Who holds the spool's lock now (pid, command, since when), or None if nobody does."""
    path = Path(directory) / LOCKNAME
    try:
        fd = os.open(path, os.O_RDWR)
    except OSError:
        return None
    try:
        if _try_lock(fd):
            return None
        return owner(directory)
    finally:
        os.close(fd)  # drops the lock if this look took it


def owner(directory: str | Path) -> str:
    """What ``spool.owner`` says about the process holding the lock."""
    try:
        info = loads_json((Path(directory) / OWNERNAME).read_text(encoding="utf-8"))
        return f"pid {info['pid']} ({info['command']}, since {info['since']})"
    except (OSError, ValueError, KeyError, TypeError):
        return "another process (it has not said which yet)"


if sys.platform == "win32":
    import msvcrt

    def _try_lock(fd: int) -> bool:
        os.lseek(fd, 0, os.SEEK_SET)
        try:
            msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)
        except OSError:
            return False
        return True

else:
    import fcntl

    def _try_lock(fd: int) -> bool:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            if exc.errno in (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK):
                return False
            raise
        return True
