"""An import through the agent against the fake server: what was stored, refused and said."""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx

from rigclient import Client, RetryPolicy
from rigclient.agent import Agent, Batching, Outcome, run_metadata
from rigclient.mapping import StandMap
from rigclient.spool import Reject, Spool
from tests.rigclient.fake import FakeServer


@dataclass
class Imported:
    """The rows the server stored (in seq order), the lines refused, the run's opening."""

    outcome: Outcome
    columns: dict[str, list[float]]
    rejects: list[Reject]
    opening: dict[str, Any]
    said: list[str] = field(default_factory=list)


def stored(server: FakeServer, group_channel: str = "time") -> dict[str, list[float]]:
    """The server's batches joined channel by channel, those with ``group_channel``."""
    out: dict[str, list[float]] = {}
    for seq in sorted(server.stored):
        batch = server.stored[seq]
        if group_channel not in batch:
            continue
        for name, values in batch.items():
            out.setdefault(name, []).extend(values)
    return out


def import_file(
    path: Path,
    spool: Path,
    *,
    stand: str = "smts2",
    group: str = "friction",
    mapping: StandMap | None = None,
    server: FakeServer | None = None,
    rows: int = 4,
    first: str = "time",
    more: tuple[Path, ...] = (),
    key: str | None = None,
) -> Imported:
    """``rigclient import`` of ``path`` (without the CLI's bars), delivered to ``server``."""
    server = server or FakeServer()
    said: list[str] = []
    with Client(
        "http://rig.test",
        "key",
        spool=spool,
        transport=httpx.MockTransport(server),
        retry=RetryPolicy(base_delay=0.01, max_delay=0.05),
    ) as client:
        agent = Agent(
            client,
            path,
            stand=stand,
            group=group,
            mapping=mapping,
            metadata=run_metadata(path, stand, mapping, operator="Ivanova"),
            batching=Batching(rows=rows, seconds=60.0, poll=0.01),
            say=said.append,
            kind="import",
            more=more,
            idempotency_key=key,
        )
        outcome = agent.run(threading.Event(), follow=False)
        assert outcome is not None
        assert client.wait(20.0)
    with Spool(spool) as s:
        rejects = s.rejects(outcome.run.local_id)
        opening, _ = s.opening(outcome.run.local_id)
    return Imported(outcome, stored(server, first), rejects, opening, said)
