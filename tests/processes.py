"""Processes the tests start: each in its own process group, stopped as a group.

A test that starts ``rigserver serve`` or ``rigsim demo`` (which starts a server of its own)
does it through :func:`spawn`, so the process and everything it starts share a new process
group (a new session: no terminal, no SIGINT from one), and stops it with :func:`stop`:
SIGTERM to the group, SIGKILL after a bound. Nothing relies on SIGINT, which a background
job or a CI runner may ignore. :func:`leftovers` lists what is still running, for the
session's final check (``tests/conftest.py``).
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import time
from pathlib import Path
from typing import Any

#: Seconds a group has to stop after SIGTERM before it is killed.
GRACE_SECONDS = 15.0

_groups: set[int] = set()


def spawn(cmd: list[str], **kwargs: Any) -> subprocess.Popen[bytes]:
    """``Popen(cmd)`` in a new session: its own process group, led by the process."""
    proc: subprocess.Popen[bytes] = subprocess.Popen(cmd, start_new_session=True, **kwargs)
    _groups.add(proc.pid)
    return proc


def _group_alive(pgid: int) -> bool:
    try:
        os.killpg(pgid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # the id now names someone else's group
        return False
    return True


def _signal_group(pgid: int, sig: signal.Signals) -> None:
    with contextlib.suppress(ProcessLookupError):
        os.killpg(pgid, sig)


def stop(
    proc: subprocess.Popen[bytes],
    *,
    sig: signal.Signals = signal.SIGTERM,
    grace: float = GRACE_SECONDS,
) -> int:
    """Send ``sig`` to the process's group, SIGKILL it after ``grace`` s; the leader's status.

    Returns once the leader is reaped and no process of the group is left.
    """
    pgid = proc.pid
    _signal_group(pgid, sig)
    deadline = time.monotonic() + grace
    with contextlib.suppress(subprocess.TimeoutExpired):
        proc.wait(timeout=grace)
    while _group_alive(pgid) and time.monotonic() < deadline:
        time.sleep(0.05)
    if _group_alive(pgid) or proc.poll() is None:
        _signal_group(pgid, signal.SIGKILL)
        proc.wait()
        while _group_alive(pgid):
            time.sleep(0.01)
    _groups.discard(pgid)
    return proc.returncode


def _children() -> dict[int, list[int]]:
    found: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        ppid = int(stat.rpartition(")")[2].split()[1])
        found.setdefault(ppid, []).append(int(entry.name))
    return found


def descendants(pid: int) -> set[int]:
    """The processes ``pid`` started, the processes they started, and so on (from /proc)."""
    children = _children()
    found: set[int] = set()
    todo = [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            found.add(child)
            todo.append(child)
    return found


def _command(pid: int) -> str:
    try:
        raw = Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return ""
    return raw.replace(b"\0", b" ").decode(errors="replace").strip()


def leftovers(names: tuple[str, ...] = ("rigserver", "rigsim")) -> list[str]:
    """What is still running of the spawned groups, and any descendant of this process
    whose command line names one of ``names``: ``"pid command"`` each."""
    stray: dict[int, str] = {}
    for pid in descendants(os.getpid()):
        command = _command(pid)
        if any(name in command for name in names):
            stray[pid] = command
    for pgid in sorted(_groups):
        if _group_alive(pgid):
            stray.setdefault(pgid, f"process group {pgid}: {_command(pgid)}")
    return [f"{pid} {command}" for pid, command in sorted(stray.items())]


def kill_leftovers() -> None:
    """SIGKILL every spawned group still alive (the final check's clean-up)."""
    for pgid in list(_groups):
        _signal_group(pgid, signal.SIGKILL)
        _groups.discard(pgid)
