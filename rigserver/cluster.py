"""``scripts/cluster up|down``: a local cluster, PostgreSQL and N rigserver workers.

``up --workers N --dir DIR`` makes a PostgreSQL server in ``DIR/postgres`` (``initdb``, as
an unprivileged user when run as root; it listens on a unix socket in that directory
only), writes an API key with every scope to ``DIR/keys.json``, starts N ``rigserver
serve`` workers on free loopback ports sharing the database and the run files directory
``DIR/files``, writes each worker's process id to ``DIR/worker-N.pid`` and its log to
``DIR/worker-N.log``, and prints one line per worker: its URL. ``down --dir DIR`` stops
exactly those workers (their process groups) and that server (``pg_ctl stop``).

When hsds and h5pyd are installed (the ``cluster`` extra), ``up`` also starts HSDS in
``DIR/hsds`` (unix sockets only, POSIX storage; :mod:`rigserver.storage.servers.hsdsserver`) and
the workers materialise the run arrays there (``--hsds-endpoint``); otherwise it says so
in one line and the arrays stay in the journal. ``down`` stops it too.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import secrets
import signal
import socket
import sys
import time
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path

import httpx

from rigserver.storage.cluster.hsds_settings import HsdsSettings
from rigserver.storage.servers._processes import STARTED, start_logged
from rigserver.storage.servers.hsdsserver import LocalHsds, hsds_missing, start_hsds
from rigserver.storage.servers.pgserver import LocalPostgres, NoPostgres, start_local

#: Seconds a worker has to answer after it was started, and to stop after SIGTERM
START_SECONDS = 60.0
STOP_SECONDS = 15.0


def free_port() -> int:
    """A loopback port free now (the OS picks it)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def postgres_of(directory: Path) -> LocalPostgres:
    """The PostgreSQL server ``up`` started in ``directory``."""
    state = json.loads((directory / "cluster.json").read_text(encoding="utf-8"))
    return LocalPostgres(directory / "postgres", int(state["postgres_port"]))


def _state(directory: Path) -> dict[str, object]:
    path = directory / "cluster.json"
    return dict(json.loads(path.read_text(encoding="utf-8"))) if path.exists() else {}


def hsds_of(directory: Path) -> LocalHsds | None:
    """The HSDS service ``up`` started in ``directory``, if it started one."""
    found = _state(directory).get("hsds")
    if not isinstance(found, dict):
        return None
    return LocalHsds(directory / "hsds", HsdsSettings(**found))


def write_keys(directory: Path) -> str:
    """A new API key with every scope in ``directory/keys.json`` (mode 600); the key."""
    key = secrets.token_urlsafe(32)
    keys_file = directory / "keys.json"
    keys_file.write_text(
        json.dumps([{"key": key, "scopes": ["read", "write:*"], "name": "cluster"}], indent=2),
        encoding="utf-8",
    )
    keys_file.chmod(0o600)
    return key


def start_worker(directory: Path, n: int, url: str | None, *, args: Sequence[str] = ()) -> str:
    """Start worker ``n`` (its own process group) on a free port with the database ``url``
    (``None``: the embedded store in ``directory/files``); its URL once it answers."""
    port = free_port()
    key = json.loads((directory / "keys.json").read_text(encoding="utf-8"))[0]["key"]
    hsds = hsds_of(directory) if url else None
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    if hsds is not None:
        args = ["--hsds-endpoint", hsds.settings.endpoint, *args]
        env |= {
            "RIG_HSDS_USERNAME": hsds.settings.username,
            "RIG_HSDS_PASSWORD": hsds.settings.password,
            "RIG_HSDS_BUCKET": hsds.settings.bucket,
            "RIG_HSDS_READS": "1" if _state(directory).get("hsds_reads") else "0",
        }
    command = [
        sys.executable,
        "-m",
        "rigserver.cli",
        "serve",
        "--host",
        "127.0.0.1",
        "--port",
        str(port),
        "--data-dir",
        str(directory / "files"),
        "--keys-file",
        str(directory / "keys.json"),
        *(["--database-url", url] if url else []),
        "--log-level",
        "warning",
        *args,
    ]
    log = directory / f"worker-{n}.log"
    proc = start_logged(command, log=log, pid_file=directory / f"worker-{n}.pid", env=env)
    base = f"http://127.0.0.1:{port}"
    deadline = time.monotonic() + START_SECONDS
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise RuntimeError(f"worker {n} exited: {log.read_text(errors='replace')[-1500:]}")
        try:
            headers = {"Authorization": f"Bearer {key}"}
            httpx.get(f"{base}/api/v1/stands", headers=headers, timeout=1)
            return base
        except httpx.TransportError:
            time.sleep(0.1)
    raise RuntimeError(f"worker {n} did not answer within {START_SECONDS:.0f} s (see {log})")


def up(directory: Path, workers: int, *, hsds: bool = True, hsds_reads: bool = False) -> list[str]:
    """Start the database, HSDS (if ``hsds`` and it is installed) and the workers (reading
    the arrays materialised in HSDS from there if ``hsds_reads``); the workers' URLs."""
    directory.mkdir(parents=True, exist_ok=True)
    directory.chmod(0o711)  # the database's user (not root) passes through it
    (directory / "files").mkdir(exist_ok=True)
    port = free_port()
    state: dict[str, object] = {"postgres_port": port}
    (directory / "cluster.json").write_text(json.dumps(state), encoding="utf-8")
    server = start_local(directory / "postgres", port)
    write_keys(directory)
    urls = []
    try:
        why = hsds_missing() if hsds else None
        if hsds and why is None:
            state["hsds"] = asdict(start_hsds(directory / "hsds").settings)
            state["hsds_reads"] = hsds_reads
            (directory / "cluster.json").write_text(json.dumps(state), encoding="utf-8")
            (directory / "cluster.json").chmod(0o600)  # HSDS's password
        elif why is not None:
            print(
                f"cluster: HSDS not started, the arrays stay in the journal: {why}", file=sys.stderr
            )
        for n in range(1, workers + 1):
            urls.append(start_worker(directory, n, server.url))
    except BaseException:
        down(directory)
        raise
    return urls


def stop_worker(pid_file: Path) -> None:
    """SIGTERM the worker's process group, SIGKILL it if it has not gone in time."""
    pid = int(pid_file.read_text(encoding="utf-8"))
    with contextlib.suppress(ProcessLookupError):  # the group has gone already
        os.killpg(pid, signal.SIGTERM)
        deadline = time.monotonic() + STOP_SECONDS
        while alive(pid):
            if time.monotonic() > deadline:
                os.killpg(pid, signal.SIGKILL)
                break
            time.sleep(0.1)
    proc = STARTED.pop(pid, None)
    if proc is not None:  # started by this process: collect its exit (no zombie left)
        proc.wait(STOP_SECONDS)
    pid_file.unlink()


def alive(pid: int) -> bool:
    """Whether ``pid`` runs: a zombie (exited, its status not collected because its parent
    was ``up``, gone since, and init here does not reap) counts as gone."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except (FileNotFoundError, ProcessLookupError):
        return False
    return stat.rpartition(")")[2].split()[0] != "Z"


def down(directory: Path) -> None:
    """Stop the workers ``up`` started in ``directory``, then its database."""
    for pid_file in sorted(directory.glob("worker-*.pid")):
        stop_worker(pid_file)
    hsds = hsds_of(directory)
    if hsds is not None and (hsds.directory / "hsds.pid").exists():
        hsds.stop()
    if (directory / "cluster.json").exists():
        server = postgres_of(directory)
        postmaster = server.data / "postmaster.pid"
        pid = int(postmaster.read_text().split()[0]) if postmaster.exists() else None
        server.stop()
        if pid is not None:  # pg_ctl returns once the pid file has gone, a moment before
            _wait_exited(pid)


def _wait_exited(pid: int) -> None:
    deadline = time.monotonic() + STOP_SECONDS
    while time.monotonic() < deadline:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return
        time.sleep(0.05)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="scripts/cluster", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    start = sub.add_parser("up", help="start PostgreSQL and N workers")
    start.add_argument("--workers", type=int, default=2)
    start.add_argument("--dir", type=Path, required=True)
    start.add_argument("--no-hsds", action="store_true", help="keep the arrays in the journal")
    start.add_argument(
        "--hsds-reads", action="store_true", help="read the arrays materialised in HSDS there"
    )
    stop = sub.add_parser("down", help="stop what up started")
    stop.add_argument("--dir", type=Path, required=True)
    args = parser.parse_args(argv)
    if args.command == "down":
        down(args.dir)
        return 0
    if args.workers < 1:
        parser.error(f"--workers must be at least 1, not {args.workers}")
    try:
        urls = up(args.dir, args.workers, hsds=not args.no_hsds, hsds_reads=args.hsds_reads)
    except NoPostgres as exc:
        print(f"cluster: {exc}", file=sys.stderr)
        return 1
    for url in urls:
        print(url)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
