"""``rigclient``: connect a real stand's lab PC to a rigserver through a durable spool.

::

    rigclient tail FILE --stand smts2 --group friction --map smts2.toml --url URL --key KEY
    rigclient import FILE --stand mtos --group steps --map mtos.toml --url URL --key KEY
    rigclient profile trace.x3p --url URL --key KEY
    rigclient status --spool DIR
    rigclient send --url URL --key KEY          # deliver what the spool still holds
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from types import FrameType
from typing import Any

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TextColumn,
    TimeElapsedColumn,
)
from rich.table import Table as RichTable

from rigclient.agent import Agent, Batching, Outcome, constants, run_metadata, stand_of
from rigclient.client import Client, RunHandle
from rigclient.errors import RigclientError, ServerError
from rigclient.mapping import StandMap, load_map
from rigclient.profile import GROUP, read_profile, roughness_lines
from rigclient.spool import RunRecord, Spool, SpoolLimits

DEFAULT_SPOOL = Path.home() / ".rigclient" / "spool"


def _common(parser: argparse.ArgumentParser, *, server: bool = True) -> None:
    parser.add_argument(
        "--spool",
        type=Path,
        default=Path(os.environ.get("RIG_SPOOL", DEFAULT_SPOOL)),
        help=f"spool directory (or set RIG_SPOOL; default {DEFAULT_SPOOL})",
    )
    if not server:
        return
    parser.add_argument("--url", default=os.environ.get("RIG_URL", "http://127.0.0.1:8000"))
    parser.add_argument("--key", default=os.environ.get("RIG_KEY"), help="or set RIG_KEY")
    parser.add_argument(
        "--spool-max-mb", type=float, default=2048.0, help="bound of the undelivered batches"
    )
    parser.add_argument(
        "--spool-max-age-hours", type=float, default=336.0, help="bound of the oldest batch"
    )
    parser.add_argument(
        "--drain",
        type=float,
        default=30.0,
        help="seconds to wait for delivery at the end (what is left stays in the spool)",
    )


def _run_fields(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--map", type=Path, help="the file's map (TOML or JSON)")
    parser.add_argument("--operator")
    parser.add_argument("--title")


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="rigclient", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    for name, text in (
        ("tail", "follow a CSV/TSV that the stand's software is writing, as one run"),
        ("import", "post a finished CSV/TSV as one run"),
    ):
        cmd = sub.add_parser(name, help=text)
        cmd.add_argument("file", type=Path)
        cmd.add_argument("--stand", help="smts2, slide_bearing, mtos, profilometer (or the map)")
        cmd.add_argument("--group", help="the channel group of the file's rows (or the map)")
        _run_fields(cmd)
        cmd.add_argument("--rows", type=int, default=200, help="rows per batch (default 200)")
        cmd.add_argument(
            "--seconds", type=float, default=2.0, help="longest wait of a row, s (default 2)"
        )
        _common(cmd)
        if name == "tail":
            cmd.add_argument(
                "--finish-after-idle",
                type=float,
                help="finish the run when the file has not grown for this many seconds",
            )
            cmd.add_argument("--poll", type=float, default=0.2, help="s between looks at it")
        cmd.add_argument(
            "--id-wait",
            type=float,
            default=5.0,
            help="s to wait for the server's run id before printing the local one",
        )
    prof = sub.add_parser("profile", help="post a profilometer trace (CSV/TXT, X3P, SDF)")
    prof.add_argument("file", type=Path)
    _run_fields(prof)
    prof.add_argument("--row", type=int, default=0, help="the row of an areal file")
    prof.add_argument("--rows", type=int, default=5000, help="points per batch")
    _common(prof)
    status = sub.add_parser("status", help="runs in the spool: pending, acknowledged, refused")
    status.add_argument("--json", action="store_true", help="as JSON")
    _common(status, server=False)
    send = sub.add_parser("send", help="deliver what the spool holds, then stop")
    _common(send)
    return parser


def _client(args: argparse.Namespace) -> Client:
    limits = SpoolLimits(
        max_bytes=int(args.spool_max_mb * 1e6), max_age=args.spool_max_age_hours * 3600.0
    )
    return Client(args.url, args.key, spool=args.spool, limits=limits)


@contextmanager
def _stop_on_signals() -> Iterator[threading.Event]:
    """An event set by SIGTERM, and by SIGINT unless the shell ignores it; the handlers
    before are restored at the end."""
    stop = threading.Event()

    def handler(signum: int, frame: FrameType | None) -> None:
        stop.set()

    before = {s: signal.getsignal(s) for s in (signal.SIGTERM, signal.SIGINT)}
    signal.signal(signal.SIGTERM, handler)
    if before[signal.SIGINT] is not signal.SIG_IGN:
        signal.signal(signal.SIGINT, handler)
    try:
        yield stop
    finally:
        for signum, previous in before.items():
            signal.signal(signum, previous)


def _say(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def _announce(run: RunHandle, wait: float) -> None:
    """The run id on the first line of output: the server's, or the local one while the
    server is out of reach."""
    deadline = time.monotonic() + wait
    record = run.status()
    while record.server_id is None and record.refused is None and time.monotonic() < deadline:
        time.sleep(0.05)
        record = run.status()
    if record.refused is not None:
        raise RigclientError(
            f"the server refused the run's {record.refused_what}: {record.refused.get('status')} "
            f"{record.refused.get('detail')} (kept in the spool {run.local_id}; see `status`)"
        )
    print(run.server_id or run.local_id, flush=True)
    if run.server_id is None:
        _say(f"run {run.local_id}: the server has not answered yet; the readings are spooled")


def _file_args(args: argparse.Namespace) -> tuple[StandMap | None, str, str]:
    mapping = load_map(args.map) if args.map else None
    stand = args.stand or (mapping.stand if mapping else None)
    group = args.group or (mapping.group if mapping else None)
    if not stand or not group:
        raise RigclientError("say the stand and the group (--stand, --group, or in the map)")
    return mapping, stand, group


def _finish_up(client: Client, run: RunHandle, drain: float) -> int:
    delivered = client.wait(drain)
    record = run.status()
    if record.refused is not None:
        _say(
            f"run {record.server_id or record.local_id}: the server refused {record.refused_what}: "
            f"{record.refused.get('detail')} ({record.pending} batches kept in the spool)"
        )
        return 1
    if not delivered:
        _say(
            f"run {record.server_id or record.local_id}: {record.pending} batches wait in the "
            "spool; `rigclient send` or the next start delivers them"
        )
    return 0


def _tail(args: argparse.Namespace, *, follow: bool) -> int:
    mapping, stand, group = _file_args(args)
    metadata = run_metadata(args.file, stand, mapping, operator=args.operator, title=args.title)
    batching = Batching(
        rows=args.rows,
        seconds=args.seconds,
        finish_after_idle=getattr(args, "finish_after_idle", None),
        poll=getattr(args, "poll", 0.2),
    )
    with _stop_on_signals() as stop, _client(args) as client:
        agent = Agent(
            client,
            args.file,
            stand=stand,
            group=group,
            mapping=mapping,
            metadata=metadata,
            batching=batching,
            say=_say,
            on_run=lambda run: _announce(run, args.id_wait),
            kind="tail" if follow else "import",
        )
        outcome = agent.run(stop) if follow else _import(client, agent, args.drain, stop)
        if outcome is None:
            _say(f"{args.file}: stopped before the file had a header; no run opened")
            return 1
        _say(
            f"{args.file}: {outcome.rows} rows in {outcome.batches} batches spooled, "
            f"{outcome.rejected} lines refused"
        )
        return _finish_up(client, outcome.run, args.drain)


def _import(client: Client, agent: Agent, drain: float, stop: threading.Event) -> Outcome | None:
    """The whole file through ``agent``, then its delivery, with progress bars."""
    size = agent.path.stat().st_size if agent.path.exists() else 0
    with Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=Console(stderr=True),
    ) as bar:
        task = bar.add_task(f"spooling {agent.path.name} (bytes)", total=size)
        agent.say = lambda text: bar.console.print(
            text, markup=False, highlight=False, soft_wrap=True
        )
        agent.progress = lambda done: bar.update(task, completed=done)
        outcome = agent.run(stop, follow=False)
        if outcome is not None:
            _deliver(client, outcome.run, bar, drain)
    return outcome


def _deliver(client: Client, run: RunHandle, bar: Progress, drain: float) -> None:
    """A second bar: batches acknowledged by the server, until all are or ``drain`` s."""
    record = run.status()
    task = bar.add_task("delivering (batches)", total=record.batches)
    deadline = time.monotonic() + drain
    while not record.done and record.refused is None and time.monotonic() < deadline:
        bar.update(task, completed=record.acknowledged)
        time.sleep(0.1)
        record = run.status()
    bar.update(task, completed=record.acknowledged)


def _profile(args: argparse.Namespace) -> int:
    mapping = load_map(args.map) if args.map else None
    trace = read_profile(args.file, mapping=mapping, row=args.row)
    if trace.skipped:
        _say(f"{args.file}: {trace.skipped} points not measured were left out")
    metadata = run_metadata(
        args.file, "profilometer", mapping, operator=args.operator, title=args.title
    )
    stand = stand_of("profilometer", metadata.get("configuration"))
    with _client(args) as client:
        run = client.open_run(**metadata, constants=constants(stand, mapping))
        for start in range(0, trace.x.size, max(args.rows, 1)):
            part = slice(start, start + args.rows)
            run.post(GROUP, {"x": trace.x[part], "y": trace.y[part]})
        run.finish()
        delivered = client.wait(args.drain)
        print(run.server_id or run.local_id, flush=True)
        _say(f"{args.file}: {trace.x.size} points, x from {trace.x[0]:g} to {trace.x[-1]:g} mm")
        if delivered and run.server_id is not None:
            _say_roughness(client, run.server_id)
        return _finish_up(client, run, 0.0)


def _say_roughness(client: Client, run_id: str) -> None:
    """The roughness the server computed: the manual's and the ISO 21920-2 one."""
    try:
        payload = client.results(run_id)
    except ServerError as exc:
        _say(f"run {run_id}: its results could not be read ({exc})")
        return
    for line in roughness_lines(payload):
        _say(line)


def _status(args: argparse.Namespace) -> int:
    with Spool(args.spool, create=False) as spool:
        runs = spool.runs()
        rejects = {r.local_id: spool.rejects(r.local_id) for r in runs if r.rejects}
    if args.json:
        print(json.dumps([_record_json(r, rejects.get(r.local_id, [])) for r in runs], indent=2))
        return 0
    table = RichTable(title=f"spool {args.spool}")
    for column in ("run", "stand", "title", "state", "batches", "acknowledged", "pending"):
        table.add_column(column)
    table.add_column("refused / rejected lines", overflow="fold")
    for r in runs:
        why = ""
        if r.refused is not None:
            why = f"{r.refused_what}: {r.refused.get('status')} {r.refused.get('detail')}"
        if r.rejects:
            first = rejects[r.local_id][0]
            why += f"{'; ' if why else ''}{r.rejects} lines, first: {first.message}"
        table.add_row(
            r.server_id or r.local_id,
            r.stand,
            r.title,
            r.state,
            str(r.batches),
            str(r.acknowledged),
            str(r.pending),
            why,
        )
    Console(width=None if sys.stdout.isatty() else 200).print(table)
    return 0


def _record_json(r: RunRecord, rejects: list[Any]) -> dict[str, Any]:
    return {
        "local_id": r.local_id,
        "server_id": r.server_id,
        "stand": r.stand,
        "title": r.title,
        "state": r.state,
        "batches": r.batches,
        "acknowledged": r.acknowledged,
        "pending": r.pending,
        "refused": r.refused,
        "refused_what": r.refused_what,
        "rejects": [
            {"file": j.file, "line": j.line, "column": j.column, "message": j.message}
            for j in rejects
        ],
    }


def _send(args: argparse.Namespace) -> int:
    with _client(args) as client:
        delivered = client.wait(args.drain)
        status = client.status()
    _say(
        f"{'everything delivered' if delivered else 'not everything delivered'}: "
        f"{status.pending} batches pending, {len(status.refused)} runs refused"
    )
    return 0 if delivered else 1


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.command in ("tail", "import"):
            return _tail(args, follow=args.command == "tail")
        if args.command == "profile":
            return _profile(args)
        if args.command == "status":
            return _status(args)
        return _send(args)
    except RigclientError as exc:
        _say(f"rigclient: {exc}")
        return 1


if __name__ == "__main__":
    sys.exit(main())
