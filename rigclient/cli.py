"""``rigclient``: connect a real stand's lab PC to a rigserver through a durable spool.

::

    rigclient tail FILE --stand smts2 --group friction --map smts2.toml --url URL --key KEY
    rigclient import FILE --stand mtos --group steps --map mtos.toml --url URL --key KEY
    rigclient import export.txt --map tribometer.toml   # docs/tribometers.md
    rigclient profile trace.x3p --url URL --key KEY
    rigclient status --spool DIR                # what waits, and what retry/drop would do
    rigclient send --url URL --key KEY          # deliver what the spool still holds
    rigclient retry RUN                         # queue a refused or damaged run again
    rigclient drop RUN [--damaged]              # drop what is pending of a run
    rigclient salvage --spool DIR               # a damaged spool: keep what still reads

Exit status: 0 when everything the command was given is on the server; 1 otherwise (an
error, a refusal, or rows that still wait in the spool: the message says which).
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
from datetime import datetime
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
from rigclient.http import Api, RetryPolicy
from rigclient.imported import Held, digest_key, import_files, imported_before
from rigclient.lock import SpoolLock, held_by
from rigclient.mapping import StandMap, load_map
from rigclient.profile import GROUP, read_profile, roughness_lines
from rigclient.salvage import salvage
from rigclient.spool import RunRecord, Spool, SpoolLimits, amount
from rigclient.summary import result_notes, results_tables
from schemas.runs import RunState
from schemas.stands import StandKind

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
    parser.add_argument(
        "--key",
        default=os.environ.get("RIG_KEY"),
        help="API key, or set RIG_KEY; it applies to everything the spool holds (a new key "
        "delivers what a refused one left), and is never kept in the spool",
    )
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
        if name == "import":
            cmd.add_argument(
                "file",
                type=Path,
                nargs="+",
                help="the file, or several files or a folder of them read as one run in "
                "natural order (file2 before file10)",
            )
        else:
            cmd.add_argument("file", type=Path)
        cmd.add_argument(
            "--stand", help=f"{', '.join(k.value for k in StandKind)} (or the map's [run])"
        )
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
        if name == "import":
            cmd.add_argument(
                "--again",
                action="store_true",
                help="import a file imported before as a new run (else its digest finds "
                "the run that holds it)",
            )
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
    retry = sub.add_parser(
        "retry", help="queue a run again that the server refused or the spool found damaged"
    )
    retry.add_argument("run", help="the run's id (the server's, or the local one)")
    _common(retry, server=False)
    drop = sub.add_parser("drop", help="drop what is pending of a run (its batches, its finish)")
    drop.add_argument("run", help="the run's id (the server's, or the local one)")
    drop.add_argument(
        "--damaged", action="store_true", help="only its damaged batches; the rest goes on"
    )
    _common(drop, server=False)
    save = sub.add_parser(
        "salvage",
        help="a spool SQLite cannot read: keep what still reads in a new spool (then "
        "`rigclient send`), the damaged file moved aside",
    )
    _common(save, server=False)
    return parser


def _client(args: argparse.Namespace) -> Client:
    limits = SpoolLimits(
        max_bytes=int(args.spool_max_mb * 1e6), max_age=args.spool_max_age_hours * 3600.0
    )
    return Client(args.url, args.key, spool=args.spool, limits=limits, say=_say)


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


def _announce(client: Client, run: RunHandle, wait: float) -> None:
    """The run id on the first line of output: the server's, or the local one as soon as a
    try fails (the sender has said why, with the URL) or ``wait`` s pass. A refused opening
    (422), damage, or a key the server refuses stop the agent here; the run stays in the
    spool with its cursor, so the same command with the right key goes on with it."""
    started, deadline = time.time(), time.monotonic() + wait

    def failed_now(r: RunRecord) -> bool:  # a failure of this process, not an earlier one
        return r.failed_at is not None and r.failed_at >= started

    record = run.status()
    while (
        record.server_id is None
        and not record.stopped
        and not failed_now(record)
        and time.monotonic() < deadline
    ):
        time.sleep(0.05)
        record = run.status()
    if record.refused is not None:
        raise RigclientError(
            f"the server refused the run's {record.refused_what}: {record.refused.get('status')} "
            f"{record.refused.get('detail')} (kept in the spool as {run.local_id}; see `status`)"
        )
    if record.damaged is not None:
        raise RigclientError(f"{record.damaged} (kept in the spool; see `status`)")
    if record.server_id is None and failed_now(record) and record.last_status in (401, 403):
        raise RigclientError(
            f"the server refused the key ({record.last_status}, see above); stopped. The run "
            f"{run.local_id} and its readings stay in the spool: start the same command again "
            "with the right --key (or RIG_KEY), it goes on with this run"
        )
    print(record.server_id or run.local_id, flush=True)
    if record.server_id is None:
        why = (
            "see above" if failed_now(record) else f"no answer within {wait:g} s from {client.url}"
        )
        _say(
            f"run {run.local_id}: not opened on the server yet ({why}); the readings are "
            "spooled and sent once it answers"
        )


def _file_args(args: argparse.Namespace) -> tuple[StandMap | None, str, str]:
    mapping = load_map(args.map) if args.map else None
    stand = args.stand or (mapping.stand if mapping else None)
    group = args.group or (mapping.group if mapping else None)
    if not stand or not group:
        raise RigclientError("say the stand and the group (--stand, --group, or in the map)")
    return mapping, stand, group


def _finish_up(client: Client, run: RunHandle, drain: float) -> int:
    """Wait up to ``drain`` s for the run's delivery; 0 if the server has it all, else 1
    with what waits in the spool and why."""
    deadline = time.monotonic() + drain
    record = run.status()
    while not record.done and not record.stopped and time.monotonic() < deadline:
        time.sleep(0.05)
        record = run.status()
    kept = amount(record.pending, record.rows_pending)
    if record.refused is not None:
        _say(
            f"run {record.name}: the server refused its {record.refused_what}: "
            f"{record.refused.get('status')} {record.refused.get('detail')}; {kept} kept in "
            "the spool: `rigclient status` says what `rigclient retry` or `drop` would do"
        )
        return 1
    if record.damaged is not None:
        _say(f"run {record.name}: {record.damaged}; {kept} kept in the spool (`rigclient status`)")
        return 1
    if not record.done:
        what = kept + (" and the finish" if record.finish_queued else "")
        why = f" (last try: {record.last_error})" if record.last_error else ""
        _say(
            f"run {record.name}: not delivered yet: {what} wait in the spool{why}; "
            "`rigclient send` (with the right --url and --key) or the next start of the agent "
            "delivers them"
        )
        return 1
    return 0


def _tail(args: argparse.Namespace, *, follow: bool) -> int:
    files = [args.file] if follow else import_files(args.file)
    args.file = files[0]
    mapping, stand, group = _file_args(args)
    metadata = run_metadata(args.file, stand, mapping, operator=args.operator, title=args.title)
    key = None if follow or args.again else digest_key(*files)
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
            on_run=lambda run: _announce(client, run, args.id_wait),
            kind="tail" if follow else "import",
            idempotency_key=key,
            more=files[1:],
        )
        if key is not None:
            held = imported_before(client, agent, _api(args), key)
            if held is not None:
                _say(f"{args.file}: imported before (its content, {key}): {held.describe()}")
                return _held(args, client, held)
        outcome = agent.run(stop) if follow else _import(client, agent, args.drain, stop)
        if outcome is None or outcome.run is None:
            _say(
                f"{args.file}: stopped before the file had a "
                f"{'header' if follow else 'row'}; no run opened"
            )
            return 1
        _say(
            f"{args.file}: {outcome.rows} rows in {outcome.batches} batches spooled, "
            f"{outcome.rejected} lines refused"
        )
        code = _finish_up(client, outcome.run, args.drain if follow else 0.0)
        if not follow and code == 0:
            _print_results(args, outcome.run.status())
        return code


def _api(args: argparse.Namespace) -> Api:
    return Api(args.url, args.key, retry=RetryPolicy(attempts=3, deadline=10.0))


def _held(args: argparse.Namespace, client: Client, held: Held) -> int:
    """The run that holds a file imported before: its id, and its results once finished
    (not those of a run read with other values: exit 1, and how to import it again)."""
    if held.other_values:
        print(held.name, flush=True)
        return 1
    if held.run is None:
        print(held.server_id, flush=True)
        _print_results(args, None, held.server_id or "")
        return 0
    print(held.run.server_id or held.run.local_id, flush=True)
    code = _finish_up(client, held.run, args.drain)
    if code == 0:
        _print_results(args, held.run.status())
    return code


def _print_results(args: argparse.Namespace, record: RunRecord | None, run_id: str = "") -> None:
    """The headline results of a finished run (nothing while it is not)."""
    if record is not None:
        if not record.finished or record.server_id is None:
            return
        run_id = record.server_id
    console = Console(width=None if sys.stdout.isatty() else 120)
    with _api(args) as api:
        try:
            if api.get_run(run_id).state is not RunState.FINISHED:
                return
            results = api.results(run_id)
        except RigclientError as exc:
            _say(f"run {run_id}: its results could not be read: {exc}")
            return
    console.print(results_tables(results)[0])
    for line in result_notes(results):
        console.print(line, markup=False, highlight=False)


def _import(client: Client, agent: Agent, drain: float, stop: threading.Event) -> Outcome | None:
    """The whole file through ``agent``, then its delivery, with progress bars. A file
    imported before whose run is not delivered yet is delivered, not imported again."""
    size = sum(p.stat().st_size for p in agent.files if p.exists())
    with Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=Console(stderr=True),
    ) as bar:

        def say(text: str) -> None:
            bar.console.print(text, markup=False, highlight=False, soft_wrap=True)

        agent.say = client.say = say
        earlier = client.undelivered(agent.key)
        if earlier is not None:
            say(
                f"{agent.path}: imported before as run {earlier.local_id}, not delivered yet: "
                f"delivering that run, not the file again (`rigclient drop {earlier.local_id}` "
                "first to import it anew)"
            )
            agent.on_run(earlier)
            outcome: Outcome | None = Outcome(earlier)
        else:
            task = bar.add_task(f"spooling {agent.path.name} (bytes)", total=size)
            agent.progress = lambda done: bar.update(task, completed=done)
            outcome = agent.run(stop, follow=False)
        if outcome is not None and outcome.run is not None:
            _deliver(client, outcome.run, bar, drain)
        client.say = _say
    return outcome


def _deliver(client: Client, run: RunHandle, bar: Progress, drain: float) -> None:
    """A second bar: batches acknowledged by the server, until all are, the run stops (a
    refusal, damage), or ``drain`` s."""
    record = run.status()
    task = bar.add_task("delivering (batches)", total=record.batches)
    deadline = time.monotonic() + drain
    while not record.done and not record.stopped and time.monotonic() < deadline:
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
        code = _finish_up(client, run, args.drain)
        print(run.server_id or run.local_id, flush=True)
        _say(f"{args.file}: {trace.x.size} points, x from {trace.x[0]:g} to {trace.x[-1]:g} mm")
        if code == 0 and run.server_id is not None:  # delivered and finished: results ready
            _say_roughness(client, run.server_id)
        return code


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
        damaged = {r.local_id: spool.damaged_batches(r.local_id) for r in runs if r.damaged}
    holder = held_by(args.spool)
    if args.json:
        out = [
            _record_json(r, rejects.get(r.local_id, []), damaged.get(r.local_id, []), holder)
            for r in runs
        ]
        print(json.dumps(out, indent=2))
        return 0
    table = RichTable(title=f"spool {args.spool}")
    for column in ("run", "stand", "title", "state", "batches", "acknowledged", "pending"):
        table.add_column(column)
    table.add_column("refused / failing / rejected lines", overflow="fold")
    for r in runs:
        why = []
        if r.refused is not None:
            why.append(f"{r.refused_what}: {r.refused.get('status')} {r.refused.get('detail')}")
        if r.damaged is not None:
            why.append(f"damaged: {r.damaged}")
        if r.last_error is not None and not r.done:
            why.append(f"{r.tries} tries failed, last: {r.last_error}")
        if r.rejects:
            why.append(f"{r.rejects} lines, first: {rejects[r.local_id][0].message}")
        table.add_row(
            r.name,
            r.stand,
            r.title,
            r.state,
            str(r.batches),
            str(r.acknowledged),
            f"{r.pending} ({r.rows_pending} rows)",
            "; ".join(why),
        )
    Console(width=None if sys.stdout.isatty() else 200).print(table)
    waiting = [r for r in runs if not r.done]
    if holder:
        print(f"in use by {holder}: it delivers what waits")
    elif waiting:
        print("no agent runs on this spool: `rigclient send` delivers what waits")
    else:
        print("nothing waits in this spool")
    for r in runs:
        for line in _actions(r, holder):
            print(line)
    return 0


def _actions(r: RunRecord, holder: str | None) -> list[str]:
    """What the operator sees about a run that is not delivered, and what ``rigclient
    retry`` and ``drop`` would do to it."""
    if r.done:
        return []
    finish = " and its finish" if r.finish_queued else ""
    kept = amount(r.pending, r.rows_pending) + finish
    head = f"run {r.name}" + (f" ({r.local_id})" if r.server_id else "")
    then = "the agent on this spool sends them" if holder else "`rigclient send` sends them"
    if r.refused is not None:
        head += (
            f": refused at its {r.refused_what}: {r.refused.get('status')} "
            f"{r.refused.get('title', '')}: {r.refused.get('detail')}"
        )
        lines = [head, f"  rigclient retry {r.name}   would queue its {kept} again; {then}"]
    elif r.damaged is not None:
        lines = [
            f"{head}: damaged: {r.damaged}",
            f"  rigclient retry {r.name}   would check its damaged batches again and queue "
            f"those intact ({kept} in all)",
            f"  rigclient drop {r.name} --damaged   would drop only the damaged batches; the "
            "rest goes on without their rows",
        ]
    elif r.last_error is not None:
        since = (
            datetime.fromtimestamp(r.failing_since).strftime("%Y-%m-%d %H:%M:%S")
            if r.failing_since
            else "?"
        )
        lines = [f"{head}: {kept} wait, failing since {since} ({r.tries} tries): {r.last_error}"]
        if r.last_status in (401, 403):
            lines.append(
                "  the key is refused: start the agent (or `rigclient send`) with the right "
                "--key or RIG_KEY; it applies to everything waiting"
            )
        lines.append(
            f"  rigclient retry {r.name}   would forget its {r.tries} failed tries (it is "
            "tried again anyway)"
        )
    else:
        lines = [f"{head}: {kept} wait; {then}"]
    if r.server_id:
        batches = f"{r.acknowledged} batch{'' if r.acknowledged == 1 else 'es'}"
        keeps = f"the server keeps the {batches} it has"
    else:
        keeps = "the server never had the run"
    lines.append(f"  rigclient drop {r.name}    would drop its {kept}; {keeps}")
    return lines


def _record_json(
    r: RunRecord, rejects: list[Any], damaged: list[tuple[int, int, str]], holder: str | None
) -> dict[str, Any]:
    return {
        "local_id": r.local_id,
        "server_id": r.server_id,
        "stand": r.stand,
        "title": r.title,
        "state": r.state,
        "batches": r.batches,
        "acknowledged": r.acknowledged,
        "pending": r.pending,
        "rows_pending": r.rows_pending,
        "finish_queued": r.finish_queued,
        "refused": r.refused,
        "refused_what": r.refused_what,
        "damaged": r.damaged,
        "damaged_batches": [{"seq": q, "rows": n, "why": w} for q, n, w in damaged],
        "dropped": r.dropped,
        "last_error": r.last_error,
        "last_status": r.last_status,
        "failing_since": r.failing_since,
        "tries": r.tries,
        "agent": holder,
        "actions": [line.strip() for line in _actions(r, holder)[1:]],
        "rejects": [
            {"file": j.file, "line": j.line, "column": j.column, "message": j.message}
            for j in rejects
        ],
    }


def _send(args: argparse.Namespace) -> int:
    with _client(args) as client:
        delivered = client.wait(args.drain)
        status = client.status()
    left = [r for r in status.runs if not r.done]
    if delivered:
        _say("everything delivered")
        return 0
    _say(
        f"not everything delivered: {status.pending} batches "
        f"({sum(r.rows_pending for r in left)} rows) of {len(left)} runs wait in the spool, "
        f"{len(status.stopped)} of them stopped (refused or damaged): `rigclient status`"
    )
    return 1


def _retry(args: argparse.Namespace) -> int:
    with Spool(args.spool, create=False) as spool:
        local_id = spool.find(args.run)
        (before,) = spool.runs(local_id)
        if before.done:
            _say(f"run {before.name} is {before.state}: nothing of it waits")
            return 0
        done = spool.retry(local_id)
        (record,) = spool.runs(local_id)
    finish = " and its finish" if record.finish_queued else ""
    _say(
        f"run {record.name}: {amount(done.batches, done.rows)}{finish} queued again; "
        f"it was {done.was}"
    )
    if done.still_damaged:
        seqs = ", ".join(str(q) for q in done.still_damaged)
        _say(
            f"run {record.name}: batch {seqs} still damaged: never sent, the run waits there; "
            f"`rigclient drop {record.name} --damaged` drops them and the rest goes on"
        )
        return 1
    holder = held_by(args.spool)
    _say(
        f"the agent on this spool ({holder}) sends them now"
        if holder
        else "`rigclient send` (or the next start of an agent on this spool) sends them"
    )
    return 0


def _drop(args: argparse.Namespace) -> int:
    with SpoolLock(args.spool), Spool(args.spool, create=False) as spool:
        local_id = spool.find(args.run)
        (before,) = spool.runs(local_id)
        if before.dropped is not None:
            _say(f"run {before.name} was dropped before: nothing of it waits")
            return 0
        gone = spool.drop(local_id, damaged_only=args.damaged)
        (record,) = spool.runs(local_id)
    rows = amount(gone.batches, gone.rows)
    if args.damaged:
        _say(f"run {record.name}: dropped its {rows} damaged; the rest goes on without them")
        return 0
    finish = " and its finish" if gone.finish else ""
    if record.server_id is None:
        where = "the server never had the run"
    else:
        batches = f"{record.acknowledged} batch{'' if record.acknowledged == 1 else 'es'}"
        where = f"the server keeps the {batches} it has of it"
        if not record.finished:
            where += " (the run stays open there: finish or abort it on the server)"
    _say(f"run {record.name}: dropped {rows}{finish}; {where}")
    return 0


def _salvage(args: argparse.Namespace) -> int:
    done = salvage(args.spool)
    _say(f"spool {args.spool}: {done.describe()}")
    _say("`rigclient status` shows what was saved; `rigclient send` delivers it")
    return 1 if done.lost else 0


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.command in ("tail", "import"):
            return _tail(args, follow=args.command == "tail")
        if args.command == "profile":
            return _profile(args)
        if args.command == "status":
            return _status(args)
        if args.command == "retry":
            return _retry(args)
        if args.command == "drop":
            return _drop(args)
        if args.command == "salvage":
            return _salvage(args)
        return _send(args)
    except RigclientError as exc:
        _say(f"rigclient: {exc}")
        return 1


if __name__ == "__main__":
    sys.exit(main())
