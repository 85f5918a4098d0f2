"""A file imported once: its content's digest finds the run that holds it.

The digest (SHA-256 of the file's bytes) is the Idempotency-Key of the run's opening,
``sha256:<hex>``. The spool finds a run opened with it; a spool that has none (a fresh one,
another PC of the same API key) asks the server with the opening itself: a run opened
before with this key is answered 200 (the run), or 409 naming it when it was opened with
other values (another map, title or operator); 201 opens the run now, and the spool's own
opening with the same key is then answered with it. Out of reach, the server is asked by
the spooled opening later, and answers the same.
"""

from __future__ import annotations

import hashlib
import json
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rigclient.client import Client, RunHandle
from rigclient.errors import InputError, RigclientError, ServerRefused
from rigclient.http import Api, TryLater
from rigclient.mapping import MAP_NOTE
from schemas.runs import RUN_ID_PATTERN, Run, RunCreate

if TYPE_CHECKING:
    from rigclient.agent import Agent

_RUN_ID = re.compile(RUN_ID_PATTERN.strip("^$"))


def digest_key(*paths: Path) -> str:
    """The Idempotency-Key of a file's content: ``sha256:`` and its hex digest; of several
    files, the digest of their digests in order (their names aside)."""
    digests = []
    for path in paths:
        digest = hashlib.sha256()
        try:
            with path.open("rb") as f:
                while chunk := f.read(1 << 20):
                    digest.update(chunk)
        except OSError as exc:
            raise InputError(f"cannot read it: {exc.strerror}", file=str(path)) from None
        digests.append(digest.hexdigest())
    if len(digests) == 1:
        return f"sha256:{digests[0]}"
    return f"sha256:{hashlib.sha256(' '.join(digests).encode()).hexdigest()}"


def natural_key(path: Path) -> list[tuple[int, str]]:
    """A file's sort key in natural order: ``file2`` before ``file10`` (a shell's
    ``*.csv`` gives file10 first)."""
    parts = re.split(r"(\d+)", str(path).casefold())
    return [(int(p), "") if p.isdigit() else (-1, p) for p in parts]


def import_files(given: list[Path]) -> list[Path]:
    """The files of an import in natural order: those given, and a folder's files (not
    hidden, not its subfolders)."""
    out: list[Path] = []
    for path in given:
        if path.is_dir():
            inner = [p for p in path.iterdir() if p.is_file() and not p.name.startswith(".")]
            if not inner:
                raise InputError("a folder without files", file=str(path))
            out += inner
        else:
            out.append(path)
    return sorted(dict.fromkeys(out), key=natural_key)


@dataclass(frozen=True, slots=True)
class Held:
    """The run that holds a file's content: in the spool (``run``), or on the server only
    (``server_id``); ``other_values``: it was opened with another map, title or operator,
    ``differs`` says what."""

    run: RunHandle | None
    server_id: str | None
    other_values: bool = False
    differs: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        return (self.run.server_id or self.run.local_id) if self.run else str(self.server_id)

    def describe(self) -> str:
        where = "in the spool" if self.run is not None else "on the server"
        if not self.other_values:
            return f"run {self.name} ({where})"
        what = "; ".join(self.differs) or "another map, title or operator"
        return (
            f"run {self.name} ({where}) holds it, read with other values: {what}. Its "
            "results are not these values': to import the file again with them as a new "
            f"run, give the same command with --again (run {self.name} stays as it is; "
            "delete it on the server if it is wrong)"
        )


def _short(value: Any) -> str:
    text = value if isinstance(value, str) else json.dumps(value, ensure_ascii=False)
    return text if len(text) <= 200 else text[:197] + "..."


def _map_line(notes: Any) -> str:
    lines = str(notes or "").splitlines()
    return next((t[len(MAP_NOTE) :] for t in lines if t.startswith(MAP_NOTE)), "")


def differences(before: Mapping[str, Any], now: Mapping[str, Any]) -> list[str]:
    """What differs between the opening of a run and the one an import would send: the
    map's reading of the file (its line of the notes), the title, operator, specimen, test
    plan, and the configuration's fields given now."""
    out = []
    if _map_line(before.get("notes")) != _map_line(now.get("notes")):
        was = _map_line(before.get("notes")) or "none"
        out.append(
            f"the map reads {_short(_map_line(now.get('notes')) or 'none')} (was {_short(was)})"
        )
    for key in ("title", "operator", "specimen", "test_plan"):
        if before.get(key) != now.get(key) and (before.get(key) or now.get(key)):
            out.append(f"{key} {_short(now.get(key))} (was {_short(before.get(key))})")
    old = before.get("configuration") or {}
    for key, value in (now.get("configuration") or {}).items():
        if old.get(key) != value:
            out.append(f"configuration.{key} {_short(value)} (was {_short(old.get(key))})")
    return out


def imported_before(client: Client, agent: Agent, api: Api, key: str) -> Held | None:
    """The run that holds the file of ``agent`` (whose content is ``key``), or None: a new
    file, an import cut short (it goes on), or a server out of reach (asked later)."""
    local = client.run_by_key(key)
    body = RunCreate.model_validate(agent.opening())
    now = body.model_dump(mode="json")
    if local is not None:
        if client.source(agent.key) is not None:
            return None  # an import cut short: it goes on
        differs = differences(client.opening(local.local_id), now)
        return Held(local, local.server_id, bool(differs), tuple(differs))
    try:
        answer = api.attempt("POST", "/runs", **Api.opening(body, key))
    except ServerRefused as exc:
        found = _RUN_ID.search(exc.problem.detail) if exc.problem.status == 409 else None
        if found is None:
            raise
        try:
            before = api.get_run(found.group()).model_dump(mode="json")
        except RigclientError:
            return Held(None, found.group(), other_values=True)
        return Held(None, found.group(), True, tuple(differences(before, now)))
    if isinstance(answer, TryLater) or answer.status_code != 200:
        return None
    return Held(None, Run.model_validate(answer.json()).id)
