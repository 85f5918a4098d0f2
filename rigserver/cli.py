"""``rigserver serve``: run the service on uvicorn, with the embedded HDF5 storage or, given
a database URL, as one worker of a cluster (:class:`~rigserver.storage.PostgresStore`);
``rigserver check``: list the damaged runs of a data directory; ``rigserver migrate``:
move a data directory into a cluster.

SIGTERM and Ctrl-C stop ``serve`` cleanly: no new connections, the requests under way get
``SHUTDOWN_GRACE`` seconds, the store is closed.
"""

from __future__ import annotations

import argparse
import ctypes
import gc
import logging
import sqlite3
import sys
import types
import typing
from collections.abc import Callable, Sequence
from pathlib import Path
from types import FrameType
from typing import Any, Literal, Union

import uvicorn
from fastapi import FastAPI
from pydantic import ValidationError
from pydantic.fields import FieldInfo

from rigserver.api.app import create_app
from rigserver.api.auth import ApiKey, load_keys
from rigserver.api.settings import Flag, Settings
from rigserver.commands.check import check_data_dir
from rigserver.commands.migrate import MigrationMismatch, migrate
from rigserver.storage import HDF5Store, PostgresStore, RunStore, StorageError
from rigserver.storage.cluster.hsds_settings import HsdsSettings
from rigserver.storage.cluster.notes_postgres import PostgresNotes
from rigserver.storage.cluster.series_postgres import PostgresSeries
from rigserver.storage.cluster.sketches_postgres import PostgresSketches
from rigserver.storage.notes import NotesStore, SqliteNotes
from rigserver.storage.series import SeriesStore, SqliteSeries
from rigserver.storage.sketches import SketchStore, SqliteSketches
from schemas.stands import configure_stands
from schemas.strict_json import JsonRefused, strict_loads


def _keys(path: Path) -> list[ApiKey]:
    """The keys file's keys; a bad file stops the start with a message that shows no key."""
    try:
        return load_keys(path)
    except ValidationError as exc:
        where = "; ".join(
            f"{'.'.join(str(p) for p in e['loc'])}: {e['msg']}"
            for e in exc.errors(include_input=False, include_url=False)
        )
        raise SystemExit(f"rigserver: the keys file {path} is not valid: {where}") from None
    except (OSError, ValueError) as exc:
        raise SystemExit(f"rigserver: the keys file {path} cannot be read: {exc}") from None


def _stand_overrides(path: Path) -> Any:
    """The stands file's JSON, read strictly (no key twice, no nesting beyond the limit);
    a file that cannot be read stops the start with one line naming it."""
    try:
        return strict_loads(path.read_bytes())
    except JsonRefused as exc:
        raise SystemExit(f"rigserver: the stands file {path} is not valid: {exc}") from None
    except (OSError, ValueError) as exc:
        raise SystemExit(f"rigserver: the stands file {path} cannot be read: {exc}") from None


#: Allocations up to this size come from the heap, not from a fresh mapping (glibc's
#: M_MMAP_THRESHOLD; its default, 128 KiB, rises only by chance), bytes
HEAP_UP_TO = 32 << 20
#: Freed heap kept for the next allocations before it goes back to the system (glibc's
#: M_TRIM_THRESHOLD), bytes
KEEP_FREED = 64 << 20


def keep_freed_memory() -> bool:
    """Let the C library's malloc reuse freed memory for the next large request bodies.

    A batch body of megabytes is otherwise mapped afresh and unmapped once answered, so
    every page of every body is a page fault (what it gained: docs/speed.md, "Findings the
    code rests on"). Returns False where the C library is not glibc.
    """
    try:
        mallopt = ctypes.CDLL("libc.so.6").mallopt
    except (OSError, AttributeError):
        return False
    m_trim_threshold, m_mmap_threshold = -1, -3  # from glibc's malloc.h
    return bool(mallopt(m_mmap_threshold, HEAP_UP_TO)) and bool(
        mallopt(m_trim_threshold, KEEP_FREED)
    )


#: The collector's thresholds while serving (CPython's: 700, 10, 10). A request's objects
#: die young by reference counting, so a young collection finds about the same few live
#: ones however rarely it runs: run every 20 000 allocations instead of 700, the
#: collections (their cost: docs/speed.md, "Findings the code rests on") mostly go.
GC_THRESHOLDS = (20_000, 10, 10)

#: Seconds the requests under way (a live stream, a report) get to end once SIGTERM or
#: Ctrl-C asks the server to stop; then they are cancelled and the store is closed.
SHUTDOWN_GRACE = 5


class _Server(uvicorn.Server):
    """uvicorn's server that also tells the app when it is asked to stop (SIGTERM,
    Ctrl-C), so that live streams end at once instead of holding the shutdown."""

    def __init__(self, config: uvicorn.Config, stop: Callable[[], None]) -> None:
        super().__init__(config)
        self._stop = stop

    def handle_exit(self, sig: int, frame: FrameType | None) -> None:
        self._stop()
        super().handle_exit(sig, frame)


def build_app(settings: Settings) -> FastAPI:
    """The service with the data directory, keys and stands of ``settings``."""
    keys = _keys(settings.keys_file) if settings.keys_file else []
    overrides = _stand_overrides(settings.stands_file) if settings.stands_file else None
    settings.data_dir.mkdir(parents=True, exist_ok=True)
    store: RunStore
    series: SeriesStore
    notes: NotesStore
    sketches: SketchStore
    if settings.hsds_endpoint and not settings.database_url:
        raise ValueError("hsds_endpoint needs database_url: HSDS holds a cluster's arrays")
    if settings.database_url:
        store = PostgresStore(
            settings.database_url,
            files_dir=settings.data_dir,
            hsds=_hsds(settings),
            hsds_reads=settings.hsds_reads,
        )
        series = PostgresSeries(settings.database_url)
        notes = PostgresNotes(settings.database_url)
        sketches = PostgresSketches(settings.database_url)
    else:
        store = HDF5Store(settings.data_dir, synchronous=settings.synchronous)
        series = SqliteSeries(settings.data_dir / "series.sqlite")
        notes = SqliteNotes(settings.data_dir / "notes.sqlite")
        sketches = SqliteSketches(settings.data_dir / "sketches.sqlite")
    return create_app(settings, store, keys, configure_stands(overrides), series, notes, sketches)


def _hsds(settings: Settings) -> HsdsSettings | None:
    """Where the cluster's run arrays live in HSDS, if anywhere."""
    if settings.hsds_endpoint is None:
        return None
    return HsdsSettings(
        endpoint=settings.hsds_endpoint,
        username=settings.hsds_username,
        password=settings.hsds_password,
        bucket=settings.hsds_bucket,
    )


def check_command(data_dir: Path) -> int:
    """Print each damaged run of ``data_dir`` and what is wrong with it: 1 if any, else 0
    (and one line saying so); 2 if ``data_dir`` is no data directory."""
    try:
        report = check_data_dir(data_dir)
    except (OSError, sqlite3.Error) as exc:
        print(f"rigserver check: {exc}", file=sys.stderr)
        return 2
    for damage in report.damaged:
        print(f"{damage.run_id}: {damage.what}")
    if report.damaged:
        runs = len({d.run_id for d in report.damaged})
        print(f"rigserver check: {runs} of the runs in {data_dir} damaged", file=sys.stderr)
        return 1
    print(f"rigserver check: {data_dir}: {report.runs} runs, none damaged")
    return 0


def _migrate(source: Path, target: str) -> int:
    """``rigserver migrate``: every run of ``source`` copied into ``target`` and verified."""
    if not (source / "journal.sqlite").exists():
        raise SystemExit(f"rigserver: {source} is not a data directory (no journal.sqlite)")
    with PostgresStore(target) as cluster:
        try:
            done = migrate(source, cluster, progress=lambda line: print(line, file=sys.stderr))
        except (StorageError, MigrationMismatch) as exc:
            raise SystemExit(f"rigserver: the migration stopped: {exc}") from None
    print(f"rigserver: {done.copied} runs copied, {done.verified} there already; all verified")
    return 0


def _flag_type(annotation: Any) -> Any:
    """The type of a setting, its ``| None`` taken off."""
    args = [a for a in typing.get_args(annotation) if a is not type(None)]
    if typing.get_origin(annotation) in (Union, types.UnionType) and len(args) == 1:
        return args[0]
    return annotation


def _flag_help(name: str, field: FieldInfo) -> str:
    """The setting's description, its variable in the environment and its default."""
    env = f"{Settings.model_config.get('env_prefix', '')}{name}".upper()
    default = field.get_default(call_default_factory=True)
    said = "" if default in (None, (), "") else f"; default {default}"
    return f"{field.description}; {env}{said}".replace("%", "%%")


def add_settings_flags(parser: argparse.ArgumentParser) -> None:
    """One flag for each field of :class:`Settings`: named after it, its help the field's
    description, its type, choices and repetition the field's; not given, the setting
    comes from the environment or its default."""
    for name, field in Settings.model_fields.items():
        flag = next((m for m in field.metadata if isinstance(m, Flag)), Flag())
        if flag.env_only:
            continue
        kind = _flag_type(field.annotation)
        how: dict[str, Any] = {"dest": name, "help": _flag_help(name, field)}
        if kind is bool:
            how["action"] = argparse.BooleanOptionalAction
        elif typing.get_origin(kind) in (tuple, list):  # repeatable
            how |= {"action": "append", "type": typing.get_args(kind)[0]}
        elif typing.get_origin(kind) is Literal:
            how["choices"] = typing.get_args(kind)
        else:
            how["type"] = kind
        parser.add_argument(f"--{flag.name or name.replace('_', '-')}", **how)


def given_settings(args: argparse.Namespace) -> Settings:
    """The settings of the flags given, the others from the environment or their
    defaults."""
    given: dict[str, Any] = {
        name: value
        for name in Settings.model_fields
        if (value := getattr(args, name, None)) is not None
    }
    try:
        return Settings(**given)
    except ValidationError as exc:
        said = "; ".join(_refused(e, given) for e in exc.errors(include_url=False))
        raise SystemExit(f"rigserver: {said}") from None


def _refused(error: Any, given: dict[str, Any]) -> str:
    """One refused setting: its flag (given) or its variable (from the environment), why,
    and the value (no secret is checked beyond being text, so none is repeated)."""
    name = str(error["loc"][0]) if error["loc"] else ""
    field = Settings.model_fields.get(name)
    flag = next((m for m in field.metadata if isinstance(m, Flag)), Flag()) if field else Flag()
    if name in given:
        where = f"--{flag.name or name.replace('_', '-')}"
    else:
        where = f"{Settings.model_config.get('env_prefix', '')}{name}".upper()
    return f"{where}: {error['msg']} (given {error['input']!r})"


def parser() -> argparse.ArgumentParser:
    """``rigserver``'s commands and their flags."""
    parser = argparse.ArgumentParser(prog="rigserver", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    serve = sub.add_parser("serve", help="run the service")
    serve.add_argument("--host", default="127.0.0.1")
    serve.add_argument("--port", type=int, default=8000)
    add_settings_flags(serve)
    serve.add_argument("--log-level", default="info")
    check = sub.add_parser("check", help="list the damaged runs of a data directory")
    check.add_argument("--data-dir", type=Path, required=True, help="the data directory")
    move = sub.add_parser(
        "migrate", help="move an embedded data directory into a cluster (resumable, verified)"
    )
    move.add_argument("--from", dest="source", type=Path, required=True, help="DATA_DIR")
    move.add_argument("--to", dest="target", required=True, help="the cluster's database URL")
    return parser


def _serve(args: argparse.Namespace) -> int:
    """``rigserver serve``: the service on uvicorn until SIGTERM or Ctrl-C; 130 after
    Ctrl-C."""
    settings = given_settings(args)
    logging.basicConfig(
        level=args.log_level.upper(), format="%(asctime)s %(levelname)s %(message)s"
    )
    try:
        app = build_app(settings)
    except StorageError as exc:  # the data directory in use, unwritable, its journal damaged
        raise SystemExit(f"rigserver: {exc}") from None
    keep_freed_memory()
    gc.collect()
    gc.freeze()  # what was built to start is never garbage: keep it out of the collections
    gc.set_threshold(*GC_THRESHOLDS)
    where = "run files (journal in PostgreSQL)" if settings.database_url else "data"
    print(f"rigserver: {where} in {settings.data_dir.resolve()}", file=sys.stderr)
    config = uvicorn.Config(
        app,
        host=args.host,
        port=args.port,
        log_level=args.log_level,
        access_log=False,
        timeout_graceful_shutdown=SHUTDOWN_GRACE,
    )
    try:
        _Server(config, app.state.services.stop).run()
    except KeyboardInterrupt:  # uvicorn stopped on Ctrl-C, then raised it again
        return 130
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """``rigserver``'s commands: ``serve``, ``check``, ``migrate``."""
    args = parser().parse_args(argv)
    if args.command == "check":
        return check_command(args.data_dir)
    if args.command == "migrate":
        return _migrate(args.source, args.target)
    return _serve(args)


if __name__ == "__main__":
    raise SystemExit(main())
