"""The sender: a thread that delivers what the spool holds, in order, for as long as it takes.

For each run, oldest first: the opening (with the Idempotency-Key kept in the spool, so a
retried opening after a crash is answered with the same run), then the batches in seq order,
then the finish once it is queued and every batch is acknowledged. A batch is dropped from
the spool only in the transaction that records its receipt; a receipt marked ``duplicate``
(the server had stored that seq before the answer was lost) counts as delivered.

A try the server cannot take now (no network, 408, 429, 502-504) is retried after the
server's ``Retry-After`` or an exponential backoff with full jitter, without a deadline: an
outage of hours only delays delivery. A refusal (any other error answer) stops that run's
delivery with the server's problem kept in the spool; the other runs go on.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import httpx

from rigclient.errors import ServerRefused, SpoolError
from rigclient.http import Api, TryLater
from rigclient.spool import Pending, RunRecord, Spool, columns_of
from schemas.readings import BatchReceipt
from schemas.runs import Run, RunCreate, RunState

Progress = Literal["progress", "idle"]
IDLE_POLL = 0.5  # s between looks at an idle spool (a post wakes the sender at once)


@dataclass(slots=True)
class SenderState:
    """What the sender last saw: tries retried, the last reason to wait, duplicates."""

    retries: int = 0
    duplicates: int = 0
    waiting: str | None = None


class Sender(threading.Thread):
    """Delivers the spool in ``directory`` through ``api`` until stopped.

    ``binary`` sends batches as npz archives (as spooled); else as JSON columns.
    """

    def __init__(self, directory: Path, api: Api, *, binary: bool = True) -> None:
        super().__init__(name="rigclient-sender", daemon=True)
        self.directory = directory
        self.api = api
        self.binary = binary
        self.state = SenderState()
        self.wake = threading.Event()
        self._halt = threading.Event()

    def stop(self, timeout: float | None = None) -> None:
        self._halt.set()
        self.wake.set()
        if self.is_alive():
            self.join(timeout)

    def run(self) -> None:
        spool = Spool(self.directory)
        attempt = 0
        try:
            while not self._halt.is_set():
                self.wake.clear()
                try:
                    answer = deliver_one(spool, self.api, self.binary, self.state)
                except SpoolError as exc:  # the receipt could not be recorded: try again
                    answer = TryLater(str(exc))
                except (ValueError, httpx.HTTPError) as exc:  # e.g. a proxy's page, not JSON
                    answer = TryLater(f"unexpected answer: {type(exc).__name__}: {exc}", None, exc)
                if answer == "idle":
                    self.wake.wait(IDLE_POLL)
                elif isinstance(answer, TryLater):
                    attempt += 1
                    self.state.retries += 1
                    self.state.waiting = answer.reason
                    self._halt.wait(self.api.retry.delay(attempt, self.api.rng, answer.retry_after))
                else:
                    attempt = 0
                    self.state.waiting = None
        finally:
            spool.close()


def deliver_one(spool: Spool, api: Api, binary: bool, state: SenderState) -> Progress | TryLater:
    """Deliver the next thing the spool holds: ``"progress"``, ``"idle"`` when there is
    nothing to deliver, or why the server could not take it now."""
    for run in spool.runs(active=True):
        if run.server_id is None:
            return _open(spool, api, run)
        batch = spool.next_batch(run.local_id)
        if batch is not None:
            return _post(spool, api, batch, binary, state)
        if run.finish_queued:
            return _finish(spool, api, run, run.server_id)
    return "idle"


def _open(spool: Spool, api: Api, run: RunRecord) -> Progress | TryLater:
    body, key = spool.opening(run.local_id)
    try:
        answer = api.attempt("POST", "/runs", **Api.opening(RunCreate.model_validate(body), key))
    except ServerRefused as exc:
        spool.refused(run.local_id, "opening", exc.problem.model_dump(mode="json"))
        return "progress"
    if isinstance(answer, TryLater):
        return answer
    spool.opened(run.local_id, Run.model_validate(answer.json()).id)
    return "progress"


def _post(
    spool: Spool, api: Api, batch: Pending, binary: bool, state: SenderState
) -> Progress | TryLater:
    args = (
        Api.npz_batch(batch.seq, batch.group, batch.payload)
        if binary
        else Api.batch(batch.seq, batch.group, columns_of(batch.payload))
    )
    try:
        answer = api.attempt("POST", f"/runs/{batch.server_id}/readings", **args)
    except ServerRefused as exc:
        spool.refused(batch.local_id, f"batch {batch.seq}", exc.problem.model_dump(mode="json"))
        return "progress"
    if isinstance(answer, TryLater):
        return answer
    receipt = BatchReceipt.model_validate(answer.json())
    state.duplicates += receipt.duplicate
    spool.acknowledged(batch.local_id, batch.seq)
    return "progress"


def _finish(spool: Spool, api: Api, run: RunRecord, server_id: str) -> Progress | TryLater:
    answer: httpx.Response | TryLater
    try:
        answer = api.attempt("POST", f"/runs/{server_id}/finish")
    except ServerRefused as exc:
        if exc.problem.status != 409:  # "not open": finished before the answer was lost?
            spool.refused(run.local_id, "finish", exc.problem.model_dump(mode="json"))
            return "progress"
        answer = api.attempt("GET", f"/runs/{server_id}")
        if (
            isinstance(answer, httpx.Response)
            and Run.model_validate(answer.json()).state is not RunState.FINISHED
        ):
            spool.refused(run.local_id, "finish", exc.problem.model_dump(mode="json"))
            return "progress"
    if isinstance(answer, TryLater):
        return answer
    spool.finished(run.local_id)
    return "progress"
