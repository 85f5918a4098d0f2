"""Services started in the background (a cluster's workers, HSDS): each in a process group
of its own, its output to a log, its process id in a file beside it.

:data:`STARTED` keeps the processes this process started, so that stopping them can reap
them (a process whose parent is gone is left to init, which does not reap everywhere).
"""

from __future__ import annotations

import subprocess
from collections.abc import Mapping, Sequence
from pathlib import Path

#: The processes this process started, by process id
STARTED: dict[int, subprocess.Popen[bytes]] = {}


def start_logged(
    command: Sequence[str],
    *,
    log: Path,
    pid_file: Path,
    env: Mapping[str, str] | None = None,
    cwd: Path | None = None,
) -> subprocess.Popen[bytes]:
    """Start ``command`` in a new session, its output appended to ``log``, its id written to
    ``pid_file``; no standard input."""
    with log.open("ab") as out:
        proc = subprocess.Popen(
            list(command),
            stdout=out,
            stderr=out,
            stdin=subprocess.DEVNULL,
            start_new_session=True,
            env=None if env is None else dict(env),
            cwd=cwd,
        )
    STARTED[proc.pid] = proc
    pid_file.write_text(f"{proc.pid}\n", encoding="utf-8")
    return proc
