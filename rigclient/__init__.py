"""rigclient: the lab PC's side of rig. A client library with a durable spool, and an agent.

- :class:`Client`: ``open_run`` -> :class:`RunHandle`; ``post`` returns once the batch is
  durable in the local spool; a sender thread delivers it (retries, backoff, Retry-After);
  one client per spool (an OS lock).
- :mod:`rigclient.spool`: the spool (SQLite in WAL mode, a checksum with each batch);
  :mod:`rigclient.lock`: one agent per spool.
- :mod:`rigclient.http`: the server's API, one request at a time or retried.
- :mod:`rigclient.cli`: ``rigclient tail | import | profile | status | send | retry | drop |
  salvage``.
- :class:`Lab` (:mod:`rigclient.lab`): the read side, runs, readings and results as pandas
  frames (the ``frames`` extra: pandas and pyarrow).

Needs httpx, numpy, pydantic (the wire schemas), rich, x3pio and sdfio; none of the
server's packages.
"""

from rigclient.client import Client, ClientStatus, RunHandle
from rigclient.errors import (
    InputError,
    RigclientError,
    ServerError,
    ServerRefused,
    ServerUnavailable,
    SpoolBusy,
    SpoolDamaged,
    SpoolError,
    SpoolFull,
    SpoolUnreadable,
    UnknownRun,
)
from rigclient.http import Api, RetryPolicy, problem_of, retry_after
from rigclient.lab import Lab, LabRun, LabSeries
from rigclient.spool import Cursor, Reject, RunRecord, SpoolLimits

__all__ = [
    "Api",
    "Client",
    "ClientStatus",
    "Cursor",
    "InputError",
    "Lab",
    "LabRun",
    "LabSeries",
    "Reject",
    "RetryPolicy",
    "RigclientError",
    "RunHandle",
    "RunRecord",
    "ServerError",
    "ServerRefused",
    "ServerUnavailable",
    "SpoolBusy",
    "SpoolDamaged",
    "SpoolError",
    "SpoolFull",
    "SpoolLimits",
    "SpoolUnreadable",
    "UnknownRun",
    "problem_of",
    "retry_after",
]
