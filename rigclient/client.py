"""The lab PC's client: runs and batches go to the durable spool; a sender delivers them.

::

    client = Client("http://rig:8000", key, spool="C:/rig-spool")
    run = client.open_run(stand="smts2", operator="Ivanova", title="St3sp on R9")
    run.post("friction", {"time": t, "load": n, ...})   # returns once durable on disk
    run.finish()                                        # queued after the last batch
    client.wait(60)                                     # True once the server has it all

``post`` checks the group and channel names against the stand's declaration (schemas) and
returns when the batch is committed to the spool (SQLite WAL, fsync'd): never after the
network. A full disk, or a spool past its size or age bound, raises :class:`SpoolFull`
before anything is acknowledged.

A client holds its spool's lock for its life: a second client (another agent, in this
process or another) on the same spool raises :class:`SpoolBusy` naming the holder. The key
is the client's, never the spool's: a client started with a new key delivers everything
pending with it.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal, TypeVar

import httpx
import numpy as np
from numpy.typing import ArrayLike
from pydantic import ValidationError

from rigclient.errors import InputError
from rigclient.http import Api, RetryPolicy
from rigclient.lock import SpoolLock
from rigclient.sender import Sender
from rigclient.spool import Cursor, Reject, RunRecord, Spool, SpoolLimits
from schemas.corrections import CorrectedRow
from schemas.runs import RunCreate
from schemas.stands import Stand, default_stands
from schemas.wire import Scalar

T = TypeVar("T")
WAIT_POLL = 0.05  # s between looks at the spool while waiting


@dataclass(frozen=True, slots=True)
class ClientStatus:
    """The spool's runs, and what the sender last met.

    Attributes
    ----------
    runs : list of RunRecord
        Every run in the spool, oldest first (pending, acknowledged, refused).
    waiting : str or None
        Why the sender is waiting to try again (no network, 503 ...), or None.
    retries : int
        Tries the sender made again since the client started.
    duplicates : int
        Batches the server answered as stored before (a retry whose answer was lost).
    """

    runs: list[RunRecord]
    waiting: str | None
    retries: int
    duplicates: int

    @property
    def pending(self) -> int:
        return sum(r.pending for r in self.runs)

    @property
    def refused(self) -> list[RunRecord]:
        """Runs stopped by the server's 422 (not dropped)."""
        return [r for r in self.runs if r.refused is not None and r.dropped is None]

    @property
    def stopped(self) -> list[RunRecord]:
        """Runs whose delivery stopped until the operator acts: refused, or damaged."""
        return [r for r in self.runs if r.stopped]


class RunHandle:
    """A run opened through the spool; ``local_id`` at once, ``server_id`` once delivered."""

    def __init__(self, client: Client, local_id: str, stand: Stand) -> None:
        self._client = client
        self.local_id = local_id
        self.stand = stand

    def __repr__(self) -> str:
        return f"RunHandle({self.local_id!r}, stand={self.stand.kind.value!r})"

    @property
    def server_id(self) -> str | None:
        """The server's run id, or None while the opening is not delivered."""
        return self.status().server_id

    def status(self) -> RunRecord:
        return self._client._locked(lambda s: s.runs(self.local_id)[0])

    def post(
        self,
        group: str,
        columns: Mapping[str, ArrayLike],
        *,
        cursor: Cursor | None = None,
        rejects: tuple[Reject, ...] = (),
    ) -> int:
        """Spool a batch of ``group`` (channel -> values in the channel's unit); its seq.

        Returns once the batch is durable on the lab PC's disk. ``cursor`` (where a followed
        file stands after these rows) and ``rejects`` (lines that could not be read) are
        written in the same transaction.
        """
        arrays = check_columns(self.stand, group, columns)
        seq = self._client._locked(
            lambda s: s.append(self.local_id, group, arrays, cursor=cursor, rejects=rejects)
        )
        self._client._sender.wake.set()
        assert seq is not None
        return seq

    def mark(self, cursor: Cursor | None, rejects: tuple[Reject, ...] = ()) -> None:
        """Record a file position and rejected lines without a batch."""
        self._client._locked(
            lambda s: s.append(self.local_id, None, None, cursor=cursor, rejects=rejects)
        )

    def correct(
        self, group: str, index: int, values: Mapping[str, float], reason: str
    ) -> CorrectedRow:
        """Correct cells of row ``index`` (from 0, as posted) of ``group`` on the server,
        with the ``reason`` the report prints; the server keeps the values as typed. Sent
        at once, not spooled: the run must be delivered first (:meth:`Client.wait`), else
        :class:`InputError`; the server's refusal (a row it has not, a value beyond the
        channel's limit) raises ``ServerRefused``."""
        return self._client._api.correct(self._delivered(), group, index, values, reason)

    def strike(self, group: str, index: int, reason: str) -> CorrectedRow:
        """Strike row ``index`` of ``group`` out on the server (as :meth:`correct`)."""
        return self._client._api.strike(self._delivered(), group, index, reason)

    def _delivered(self) -> str:
        """The server's run id, once the run is there (its rows: the server says)."""
        server_id = self.server_id
        if server_id is None:
            raise InputError(
                f"run {self.local_id} is not on the server yet: wait for it (client.wait()) "
                "before correcting its readings"
            )
        return server_id

    def finish(self) -> None:
        """Queue the run's finish after its last batch."""
        self._client._locked(lambda s: s.queue_finish(self.local_id))
        self._client._sender.wake.set()


def check_columns(
    stand: Stand, group: str, columns: Mapping[str, ArrayLike]
) -> dict[str, np.ndarray[Any, np.dtype[np.float64]]]:
    """The columns as float arrays, if the group and channels are the stand's and an
    aligned group's columns have one length; else :class:`InputError` naming them."""
    decl = stand.group(group)
    if decl is None:
        known = ", ".join(g.name for g in stand.groups)
        raise InputError(
            f"stand {stand.kind.value!r} has no channel group {group!r}; known: {known}"
        )
    names = {c.name for c in decl.channels}
    unknown = sorted(set(columns) - names)
    if unknown or not columns:
        raise InputError(
            f"group {group!r} of {stand.kind.value!r} has the channels {', '.join(sorted(names))}; "
            f"got {', '.join(unknown) or 'none'}"
        )
    try:
        arrays = {k: np.atleast_1d(np.asarray(v, dtype=np.float64)) for k, v in columns.items()}
    except (TypeError, ValueError) as exc:
        raise InputError(f"group {group!r}: the values are not numbers ({exc})") from exc
    lengths = {k: v.size for k, v in arrays.items()}
    if any(v.ndim != 1 for v in arrays.values()):
        raise InputError(f"group {group!r}: every column must be 1-D")
    if decl.aligned:
        lacks = decl.missing(columns.keys())
        if lacks is not None:
            raise InputError(lacks)
        if len(set(lengths.values())) > 1:
            raise InputError(f"group {group!r}: columns of different lengths {lengths}")
    return arrays


class Client:
    """A lab PC's connection to a rigserver, through a durable spool.

    Parameters
    ----------
    url : str
        The server, e.g. ``http://rig.lab:8000``.
    key : str or None
        API key with the scope ``write:<stand>``.
    spool : str or Path
        Directory of the spool (made if missing); the same directory after a crash or a
        reboot resumes delivery where it stopped.
    limits : SpoolLimits
        Size and age bounds of the spool.
    binary : bool
        Send batches as npz archives (default) or JSON columns.
    transport, retry, seed, timeout, deadline
        As :class:`rigclient.http.Api` (tests pass an :class:`httpx.MockTransport`).
    start : bool
        Start the sender (False: only spool).
    say : callable, optional
        Told, in a line, what fails while delivering (with the URL), what the server
        refused, what is damaged in the spool, and when the server answers again.

    Raises
    ------
    SpoolBusy
        Another client holds the spool (its pid and command are named).
    """

    def __init__(
        self,
        url: str,
        key: str | None = None,
        *,
        spool: str | Path,
        limits: SpoolLimits | None = None,
        binary: bool = True,
        transport: httpx.BaseTransport | None = None,
        retry: RetryPolicy | None = None,
        seed: int | None = None,
        start: bool = True,
        say: Callable[[str], None] | None = None,
        timeout: float = 30.0,
        deadline: float = 60.0,
    ) -> None:
        self.directory = Path(spool)
        self._owner = SpoolLock(self.directory)
        self._owner.acquire()
        try:
            self._spool = Spool(self.directory, limits)
        except BaseException:
            self._owner.release()
            raise
        self._lock = threading.Lock()
        self._api = Api(
            url,
            key,
            transport=transport,
            retry=retry,
            seed=seed,
            timeout=timeout,
            deadline=deadline,
        )
        self._sender = Sender(self.directory, self._api, binary=binary, say=say)
        if start:
            self._sender.start()

    @property
    def url(self) -> str:
        return self._api.url

    @property
    def say(self) -> Callable[[str], None]:
        """Where the sender's messages go (settable: e.g. above a progress bar)."""
        return self._sender.say

    @say.setter
    def say(self, value: Callable[[str], None]) -> None:
        self._sender.say = value

    def __enter__(self) -> Client:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Stop the sender (what it has not delivered stays in the spool); release the
        spool."""
        self._sender.stop(timeout=30.0)
        self._api.close()
        self._spool.close()
        self._owner.release()

    def _locked(self, action: Callable[[Spool], T]) -> T:
        with self._lock:
            return action(self._spool)

    def open_run(
        self,
        *,
        stand: str,
        operator: str,
        title: str = "",
        specimen: Mapping[str, Scalar] | None = None,
        test_plan: Mapping[str, Scalar | list[float]] | None = None,
        configuration: Mapping[str, Any] | None = None,
        notes: str = "",
        given_by: Literal["operator", "file"] = "operator",
        constants: Mapping[str, Mapping[str, ArrayLike]] | None = None,
        cursor: Cursor | None = None,
        idempotency_key: str | None = None,
    ) -> RunHandle:
        """Spool the opening of a run (and its ``constants``: group -> columns, e.g. the
        masses and zero readings; the file ``cursor`` it follows; the ``idempotency_key``
        that opens it, else a fresh one); its handle. ``given_by``: who gave the
        ``configuration``, the operator or the file and its map."""
        try:
            body = RunCreate(
                stand=stand,
                operator=operator,
                title=title,
                specimen=dict(specimen or {}),
                test_plan=dict(test_plan or {}),
                configuration=dict(configuration or {}),
                notes=notes,
                given_by=given_by,
            )
        except ValidationError as exc:
            first = exc.errors()[0]
            field = ".".join(str(p) for p in first["loc"])
            raise InputError(f"the run's {field}: {first['msg']}") from None
        decl = default_stands()[body.stand].for_run(body.configuration)
        checked = {g: check_columns(decl, g, cols) for g, cols in (constants or {}).items()}
        local_id = self._locked(
            lambda s: s.open_run(
                body.stand.value,
                body.model_dump(mode="json"),
                constants=checked,
                cursor=cursor,
                idempotency_key=idempotency_key,
            )
        )
        self._sender.wake.set()
        return RunHandle(self, local_id, decl)

    def opening(self, local_id: str) -> dict[str, Any]:
        """The body of a spooled run's opening."""
        return self._locked(lambda s: s.opening(local_id))[0]

    def run(self, local_id: str) -> RunHandle:
        """The handle of a run already in the spool (after a restart)."""
        record = self._locked(lambda s: s.runs(local_id)[0])
        body, _ = self._locked(lambda s: s.opening(local_id))
        stand = default_stands()[RunCreate.model_validate(body).stand]
        return RunHandle(self, record.local_id, stand.for_run(body.get("configuration", {})))

    def source(self, key: str) -> tuple[RunHandle, Cursor] | None:
        """The run that follows the file ``key`` and where it stopped, if one does."""
        cursor: Cursor | None = self._locked(lambda s: s.source(key))
        local_id: str | None = self._locked(lambda s: s.source_run(key))
        if cursor is None or local_id is None:
            return None
        return self.run(local_id), cursor

    def run_by_key(self, idempotency_key: str) -> RunHandle | None:
        """The run the spool opened with ``idempotency_key`` (an imported file's digest)."""
        local_id = self._locked(lambda s: s.run_by_key(idempotency_key))
        return None if local_id is None else self.run(local_id)

    def keep_header(self, cursor: Cursor, start: int, text: str) -> None:
        """A header line met mid-file (:meth:`Spool.keep_header`)."""
        self._locked(lambda s: s.keep_header(cursor, start, text))

    def header_before(self, cursor: Cursor) -> tuple[int, str] | None:
        """The header in effect at ``cursor`` if one was met mid-file."""
        return self._locked(lambda s: s.header_before(cursor))

    def forget_headers(self, key: str) -> None:
        self._locked(lambda s: s.forget_headers(key))

    def undelivered(self, key: str) -> RunHandle | None:
        """A run spooled before from the source ``key`` (e.g. a file imported) whose finish
        is queued and not delivered yet, or None."""
        local_id = self._locked(lambda s: s.undelivered(key))
        return None if local_id is None else self.run(local_id)

    def status(self) -> ClientStatus:
        state = self._sender.state
        return ClientStatus(
            runs=self._locked(lambda s: s.runs()),
            waiting=state.waiting,
            retries=state.retries,
            duplicates=state.duplicates,
        )

    def results(self, run_id: str) -> dict[str, Any]:
        """The server's results of the run ``run_id`` (its id on the server)."""
        return self._api.results(run_id)

    def wait(self, timeout: float | None = None) -> bool:
        """Wait until the server has everything the spool holds; False at ``timeout`` (s) or
        as soon as all that is left is stopped (refused by the server, or damaged)."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            runs = self._locked(lambda s: s.runs())
            left = [r for r in runs if not r.done]
            if not left:
                return True
            if all(r.stopped for r in left):
                return False
            if deadline is not None and time.monotonic() >= deadline:
                return False
            time.sleep(WAIT_POLL)
