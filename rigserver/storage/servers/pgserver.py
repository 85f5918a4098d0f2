"""A throwaway local PostgreSQL server in a directory, for the tests, ``scripts/cluster`` and
the benchmarks: Debian's ``postgresql`` binaries, ``initdb`` and ``pg_ctl``.

The server listens on a unix socket inside its directory and, if asked, on one loopback
port; never on another address. PostgreSQL refuses to run as root, so when this process is
root the directory is given to an unprivileged user (``postgres``, which the Debian package
creates, else ``nobody``) and the commands run as that user through ``runuser``.
"""

from __future__ import annotations

import os
import pwd
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

#: Where Debian puts each major version's binaries
_DEBIAN_BIN = Path("/usr/lib/postgresql")
#: The database and role the server is made with
DATABASE = "rig"


class NoPostgres(RuntimeError):
    """The PostgreSQL server binaries are not installed (or cannot run here)."""


def server_bin() -> Path:
    """The directory of ``initdb``, ``pg_ctl`` and ``postgres``; ``NoPostgres`` if missing."""
    found = shutil.which("pg_ctl")
    if found:
        return Path(found).resolve().parent
    versions = sorted(
        (p for p in _DEBIAN_BIN.glob("*/bin") if (p / "pg_ctl").exists()),
        key=lambda p: int(p.parent.name) if p.parent.name.isdigit() else 0,
    )
    if not versions:
        raise NoPostgres(
            "the PostgreSQL server is not installed (Debian: apt-get install postgresql)"
        )
    return versions[-1]


def _unprivileged() -> str | None:
    """The user to run the server as when we are root, else ``None``."""
    if os.geteuid() != 0:
        return None
    for name in ("postgres", "nobody"):
        try:
            pwd.getpwnam(name)
        except KeyError:
            continue
        return name
    raise NoPostgres("running as root and no unprivileged user (postgres, nobody) to run as")


@dataclass(frozen=True, slots=True)
class LocalPostgres:
    """A PostgreSQL server whose data, socket and log live in ``directory``."""

    directory: Path
    port: int

    @property
    def data(self) -> Path:
        return self.directory / "pgdata"

    @property
    def socket_dir(self) -> Path:
        return self.directory / "socket"

    @property
    def log(self) -> Path:
        return self.directory / "postgres.log"

    @property
    def url(self) -> str:
        """The libpq URL of the database, through the unix socket."""
        return f"postgresql:///{DATABASE}?host={self.socket_dir}&port={self.port}&user={DATABASE}"

    def _run(self, *command: str) -> subprocess.CompletedProcess[str]:
        user = _unprivileged()
        argv = [str(server_bin() / command[0]), *command[1:]]
        if user is not None:
            argv = ["runuser", "-u", user, "--", *argv]
        return subprocess.run(
            argv, capture_output=True, text=True, check=False, stdin=subprocess.DEVNULL
        )

    def _check(self, done: subprocess.CompletedProcess[str], doing: str) -> None:
        if done.returncode != 0:
            raise NoPostgres(f"{doing} failed: {(done.stderr or done.stdout).strip()[-800:]}")

    def init(self) -> None:
        """``initdb`` the directory (owned by the unprivileged user when we are root)."""
        self.directory.mkdir(parents=True, exist_ok=True)
        self.socket_dir.mkdir(exist_ok=True)
        user = _unprivileged()
        if user is not None:
            entry = pwd.getpwnam(user)
            for path in (self.directory, self.socket_dir):
                os.chown(path, entry.pw_uid, entry.pw_gid)
            # the user must be able to reach its directory through the path's parents
            for parent in self.directory.resolve().parents:
                if parent.stat().st_mode & 0o001 == 0:
                    raise NoPostgres(f"{parent} is closed to the user {user} that runs PostgreSQL")
        done = self._run(
            "initdb",
            "-D",
            str(self.data),
            "-U",
            DATABASE,
            "--auth=trust",
            "--encoding=UTF8",
            "--no-instructions",
        )
        self._check(done, "initdb")

    def start(self, *, tcp: bool = False, timeout: float = 30.0) -> None:
        """Start the server (socket only, or also on 127.0.0.1 with ``tcp``) and wait."""
        listen = "127.0.0.1" if tcp else "''"
        options = (
            f"-c listen_addresses={listen} -c port={self.port} "
            f"-c unix_socket_directories={self.socket_dir} -c max_connections=200 "
            "-c fsync=on -c synchronous_commit=on"
        )
        done = self._run(
            "pg_ctl",
            "-D",
            str(self.data),
            "-l",
            str(self.log),
            "-o",
            options,
            "-w",
            "-t",
            str(int(timeout)),
            "start",
        )
        self._check(done, "pg_ctl start")

    def create_database(self) -> None:
        created = self._run(
            "createdb", "-h", str(self.socket_dir), "-p", str(self.port), "-U", DATABASE, DATABASE
        )
        if created.returncode != 0 and "already exists" not in created.stderr:
            self._check(created, "createdb")

    def stop(self, mode: str = "fast") -> None:
        """``pg_ctl stop`` (mode fast, or immediate: as after a crash)."""
        if (self.data / "postmaster.pid").exists():
            self._run("pg_ctl", "-D", str(self.data), "-m", mode, "-w", "stop")

    def running(self) -> bool:
        return self._run("pg_ctl", "-D", str(self.data), "status").returncode == 0


def start_local(directory: Path, port: int, *, tcp: bool = False) -> LocalPostgres:
    """A new server in ``directory`` (made with ``initdb``), started, with its database."""
    server = LocalPostgres(directory, port)
    server.init()
    server.start(tcp=tcp)
    try:
        server.create_database()
    except BaseException:
        server.stop()
        raise
    return server
