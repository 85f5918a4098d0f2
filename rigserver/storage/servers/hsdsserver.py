"""A local HSDS service for a cluster on one machine (``scripts/cluster``) and the tests.

``hsds --socket_dir`` makes the service and data nodes listen on unix sockets in that
directory only (without it the data node listens on ``0.0.0.0:6101`` whatever ``--host``
says); POSIX storage under ``root``; one data node. The process group is the service:
:meth:`LocalHsds.stop` (or :meth:`LocalHsds.kill`, as a crash) ends all of it.
"""

from __future__ import annotations

import contextlib
import importlib.resources
import importlib.util
import os
import secrets
import signal
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import quote

from rigserver.storage.cluster.hsds_settings import HsdsSettings
from rigserver.storage.errors import StorageError
from rigserver.storage.servers._processes import STARTED, start_logged

#: Seconds the service has to answer after it was started
START_SECONDS = 60.0
BUCKET = "rig"
USER = "rig"
#: Settings of the service changed from its packaged config.yml: write chunks to storage
#: soon after they change and answer a flush as soon as they are written (its defaults,
#: whole seconds, make every flush take about two seconds); the user is its admin
TUNED = {
    "s3_sync_interval": "0.1",
    "s3_age_time": "0",
    "flush_sleep_interval": "0.05",
    "admin_user": USER,  # makes the top folder of the runs
}


class NoHsds(RuntimeError):
    """hsds or h5pyd is not installed (the ``cluster`` extra)."""


def hsds_missing() -> str | None:
    """Why a local HSDS cannot run here, or None."""
    missing = [m for m in ("hsds", "h5pyd") if importlib.util.find_spec(m) is None]
    if missing:
        return f"{' and '.join(missing)} not installed (pip install 'rig[cluster]')"
    return None


@dataclass
class LocalHsds:
    """A service started by :func:`start_hsds` in ``directory`` (its pid in ``hsds.pid``)."""

    directory: Path
    settings: HsdsSettings

    @property
    def pid(self) -> int:
        return int((self.directory / "hsds.pid").read_text(encoding="utf-8"))

    def kill(self) -> None:
        """SIGKILL the service's process group (a crash)."""
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.pid, signal.SIGKILL)
        _wait_gone(self.pid)

    def stop(self) -> None:
        """End the service (its chunks are in storage once flushed; nothing else is kept)."""
        self.kill()
        (self.directory / "hsds.pid").unlink(missing_ok=True)

    def restart(self) -> None:
        """Start the service again on the same storage and sockets."""
        _launch(self.directory, self.settings)


def _settings(directory: Path, password: str) -> HsdsSettings:
    socket = directory / "sockets" / "sn_1.sock"
    return HsdsSettings(
        endpoint=f"http+unix://{quote(str(socket), safe='')}",
        username=USER,
        password=password,
        bucket=BUCKET,
    )


def start_hsds(directory: Path) -> LocalHsds:
    """Start HSDS with storage in ``directory/storage`` and sockets in
    ``directory/sockets``; ``NoHsds`` if it is not installed."""
    why = hsds_missing()
    if why is not None:
        raise NoHsds(why)
    directory.mkdir(parents=True, exist_ok=True)
    (directory / "storage" / BUCKET).mkdir(parents=True, exist_ok=True)
    (directory / "sockets").mkdir(exist_ok=True)
    password_file = directory / "password"
    if not password_file.exists():
        password_file.touch(0o600)
        password_file.write_text(secrets.token_hex(16), encoding="utf-8")
    settings = _settings(directory, password_file.read_text(encoding="utf-8"))
    _write_config(directory / "config")
    _launch(directory, settings)
    return LocalHsds(directory, settings)


def _write_config(config_dir: Path) -> None:
    """The packaged config.yml with :data:`TUNED` in ``config_dir``."""
    packaged = importlib.resources.files("admin.config").joinpath("config.yml").read_text()
    lines = []
    for line in packaged.splitlines():
        key = line.split(":", 1)[0]
        lines.append(f"{key}: {TUNED[key]}" if key in TUNED else line)
    config_dir.mkdir(exist_ok=True)
    (config_dir / "config.yml").write_text("\n".join(lines) + "\n", encoding="utf-8")


def _users_file(directory: Path, settings: HsdsSettings) -> Path:
    """HSDS's password file (``user:password`` lines, mode 600): the password stays out
    of the command lines of its processes."""
    users = directory / "passwd.txt"
    users.touch(0o600)
    users.write_text(f"{settings.username}:{settings.password}\n", encoding="utf-8")
    return users


def _launch(directory: Path, settings: HsdsSettings) -> None:
    for stale in (directory / "sockets").glob("*.sock"):
        stale.unlink()
    command = [
        sys.executable,
        "-c",
        "import sys; from hsds.app import main; sys.exit(main())",
        "--root_dir",
        str(directory / "storage"),
        "--bucket_name",
        BUCKET,
        "--socket_dir",
        str(directory / "sockets"),
        "--count",
        "1",
        "--password_file",
        str(_users_file(directory, settings)),
        "--config_dir",
        str(directory / "config"),
        "--logfile",
        str(directory / "hsds.log"),
        "--loglevel",
        "WARNING",
    ]
    proc = start_logged(
        command, log=directory / "hsds.out", pid_file=directory / "hsds.pid", cwd=directory
    )
    from rigserver.storage.cluster.hsds import HsdsArrays  # the cluster extra, checked above

    arrays = HsdsArrays(settings)
    deadline = time.monotonic() + START_SECONDS
    while True:
        if proc.poll() is not None:
            raise NoHsds(f"hsds exited ({proc.returncode}); see {directory / 'hsds.log'}")
        try:
            arrays.ready()
            return
        except StorageError:
            if time.monotonic() > deadline:
                os.killpg(proc.pid, signal.SIGKILL)
                _wait_gone(proc.pid)
                raise
            time.sleep(0.25)


def _wait_gone(pid: int) -> None:
    """Until the process group has gone (reaped if it was a child of this process)."""
    proc = STARTED.pop(pid, None)
    if proc is not None:
        proc.wait(10)
    for _ in range(200):
        try:
            os.killpg(pid, 0)
        except ProcessLookupError:
            return
        time.sleep(0.05)
