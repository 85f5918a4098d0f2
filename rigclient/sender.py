"""The sender: a thread that delivers what the spool holds, in order, for as long as it takes.

For each run, oldest first: the opening (with the Idempotency-Key kept in the spool, so a
retried opening after a crash is answered with the same run), then the batches in seq order,
then the finish once it is queued and every batch is acknowledged. A batch is dropped from
the spool only in the transaction that records its receipt; a receipt marked ``duplicate``
(the server had stored that seq before the answer was lost) counts as delivered.

Only an answer that names the request itself as wrong -- a 422 with the API's problem
document -- stops a run: the problem is kept with it, its batches stay in the spool, and
``rigclient retry`` or ``drop`` clears it. Every other failure is tried again: no network, a
timeout or the deadline of a try, any 5xx, a page from a proxy instead of the API's answer,
and a 401/403 (a key changed on the server, or a wrong key: the next start of the agent
with the right ``--key`` applies it to everything pending; the key is never kept in the
spool). A failed run waits for the server's ``Retry-After`` or an exponential backoff with
full jitter, without a deadline, while the other runs go on; what failed is said at once
(with the URL), again now and then while it lasts, and recorded in the spool for
``rigclient status``.

Each batch is checked against the checksum written with it before it is sent: a damaged
batch is named (run, seq, the spool's file), kept, never sent, and its run stops there.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import httpx
from pydantic import ValidationError

from rigclient.errors import (
    ServerRefused,
    SpoolDamaged,
    SpoolError,
    SpoolUnreadable,
    problem_text,
)
from rigclient.http import Api, Reporter, TryLater, not_the_api
from rigclient.spool import Pending, RunRecord, Spool, amount, columns_of
from schemas.readings import BatchReceipt
from schemas.runs import Run, RunCreate, RunState

IDLE_POLL = 0.5  # s between looks at an idle spool (a post wakes the sender at once)


@dataclass(frozen=True, slots=True)
class Failed:
    """A try that failed: the run (None: the spool itself), what was tried, and why."""

    local_id: str | None
    name: str
    what: str
    failure: TryLater


@dataclass(frozen=True, slots=True)
class Sent:
    """A step of a run's delivery done (opened, a batch acknowledged, finished, or stopped
    by a refusal or damage)."""

    local_id: str


Step = Literal["idle"] | Sent | Failed


@dataclass(slots=True)
class SenderState:
    """What the sender last saw: tries retried, the last reason to wait, duplicates."""

    retries: int = 0
    duplicates: int = 0
    waiting: str | None = None


@dataclass(slots=True)
class _Backoff:
    """A run whose last try failed: tries, when the next one is due, what to tell."""

    tries: int = 0
    due: float = 0.0
    reporter: Reporter = field(default_factory=Reporter)


class Sender(threading.Thread):
    """Delivers the spool in ``directory`` through ``api`` until stopped.

    ``binary`` sends batches as npz archives (as spooled); else as JSON columns. ``say`` is
    told, in a line, what fails, what the server refused, what is damaged, and when the
    server answers again.
    """

    def __init__(
        self,
        directory: Path,
        api: Api,
        *,
        binary: bool = True,
        say: Callable[[str], None] | None = None,
    ) -> None:
        super().__init__(name="rigclient-sender", daemon=True)
        self.directory = directory
        self.api = api
        self.binary = binary
        self.say: Callable[[str], None] = say or (lambda text: None)
        self.state = SenderState()
        self.wake = threading.Event()
        self._halt = threading.Event()
        self._waiting: dict[str | None, _Backoff] = {}

    def stop(self, timeout: float | None = None) -> None:
        self._halt.set()
        self.wake.set()
        if self.is_alive():
            self.join(timeout)

    def run(self) -> None:
        try:
            spool = Spool(self.directory)
        except SpoolError as exc:
            self.say(str(exc))
            return
        try:
            while not self._halt.is_set():
                self.wake.clear()
                now = time.monotonic()
                if (spooled := self._waiting.get(None)) is not None and spooled.due > now:
                    self._halt.wait(spooled.due - now)  # the spool itself failed: wait
                    continue
                later = {k for k, b in self._waiting.items() if k is not None and b.due > now}
                try:
                    step = deliver_one(spool, self.api, self.binary, self.state, self.say, later)
                except SpoolUnreadable as exc:  # nothing more can be sent from it
                    self.state.waiting = str(exc)
                    self.say(str(exc))
                    return
                except SpoolError as exc:  # a receipt could not be recorded: try again
                    why = TryLater(f"the spool {spool.path}: {exc}")
                    step = Failed(None, "", "keeping the spool", why)
                if step == "idle":
                    due = [b.due for b in self._waiting.values()]
                    pause = min([IDLE_POLL, *(d - time.monotonic() for d in due)])
                    self.wake.wait(max(pause, 0.0))
                elif isinstance(step, Failed):
                    self._failed(spool, step)
                else:
                    self._progressed(spool, step.local_id)
        finally:
            spool.close()

    def _failed(self, spool: Spool, step: Failed) -> None:
        backoff = self._waiting.setdefault(step.local_id, _Backoff())
        backoff.tries += 1
        failure = step.failure
        backoff.due = time.monotonic() + self.api.retry.delay(
            backoff.tries, self.api.rng, failure.retry_after
        )
        self.state.retries += 1
        self.state.waiting = failure.reason
        said = backoff.reporter.failed(failure)
        if said is not None:
            self.say(f"{step.what} of run {step.name}: {said}; {_next_step(failure)}")
        if step.local_id is not None:
            try:
                spool.failed(step.local_id, failure.reason, failure.status)
            except SpoolError as exc:
                self.say(f"could not record the failed try in the spool: {exc}")

    def _progressed(self, spool: Spool, local_id: str) -> None:
        self.state.waiting = None
        for key in (None, local_id):  # the spool works, and so does the run
            backoff = self._waiting.pop(key, None)
            if backoff is None or key is None:
                continue
            said = backoff.reporter.succeeded()
            if said is not None:
                self.say(f"run {_name(spool, key)}: {said}")
            with contextlib.suppress(SpoolError):  # status shows the old failure meanwhile
                spool.recovered(key)


def _name(spool: Spool, local_id: str) -> str:
    try:
        return spool.runs(local_id)[0].name
    except SpoolError:
        return local_id


def _next_step(failure: TryLater) -> str:
    """What happens next, and what the operator can do about it."""
    if failure.status in (401, 403):
        return (
            "the key is refused: start the agent again with the right --key (or RIG_KEY), it "
            "applies to everything waiting; trying again, the readings wait in the spool"
        )
    return "trying again, the readings wait in the spool"


def deliver_one(
    spool: Spool,
    api: Api,
    binary: bool,
    state: SenderState,
    say: Callable[[str], None] = lambda text: None,
    later: set[str] | frozenset[str] = frozenset(),
) -> Step:
    """Deliver the next thing the spool holds, skipping the runs in ``later`` (waiting for
    their backoff): ``"progress"``, ``"idle"`` when there is nothing to deliver now, or the
    try that failed."""
    for run in spool.runs(active=True):
        if run.local_id in later:
            continue
        try:
            if run.server_id is None:
                return _open(spool, api, run, say)
            batch = spool.next_batch(run.local_id)
            if batch is not None:
                return _post(spool, api, run, batch, binary, state, say)
            if run.finish_queued:
                return _finish(spool, api, run, run.server_id, say)
        except (ValueError, httpx.HTTPError) as exc:  # not foreseen below: tried again
            why = TryLater(f"unexpected: {type(exc).__name__}: {exc}", None, exc)
            return Failed(run.local_id, run.name, "delivering", why)
    return "idle"


def _refusal(exc: ServerRefused) -> TryLater:
    """A refusal that does not stop the run (not a 422) as a failure to try again."""
    reason = f"{exc.method} {exc.url}: {problem_text(exc.problem)}"
    return TryLater(reason, None, exc, status=exc.problem.status, url=exc.url, problem=exc.problem)


def _stop(
    spool: Spool, run: RunRecord, what: str, exc: ServerRefused, say: Callable[[str], None]
) -> Sent:
    """The server's 422: the run stops, with the problem kept."""
    spool.refused(run.local_id, what, exc.problem.model_dump(mode="json"))
    record = spool.runs(run.local_id)[0]
    say(
        f"{what} of run {run.name} refused: {exc}; the run stops there, its "
        f"{amount(record.pending, record.rows_pending)} kept in the spool: "
        "`rigclient status` says what `rigclient retry` or `drop` would do"
    )
    return Sent(run.local_id)


def _open(spool: Spool, api: Api, run: RunRecord, say: Callable[[str], None]) -> Step:
    try:
        body, key = spool.opening(run.local_id)
    except SpoolDamaged as exc:
        spool.damaged(run.local_id, None, str(exc))
        say(f"{exc}: kept, never sent; the run stops there (`rigclient status`)")
        return Sent(run.local_id)
    try:
        answer = api.attempt("POST", "/runs", **Api.opening(RunCreate.model_validate(body), key))
    except ServerRefused as exc:
        if exc.problem.status == 422:
            return _stop(spool, run, "opening", exc, say)
        return Failed(run.local_id, run.name, "the opening", _refusal(exc))
    if isinstance(answer, TryLater):
        return Failed(run.local_id, run.name, "the opening", answer)
    try:
        server_id = Run.model_validate(answer.json()).id
    except ValueError:  # JSON or pydantic's ValidationError: not the API's run
        why = TryLater(f"POST {api.url_of('/runs')}: {not_the_api(answer, 'a run')}")
        return Failed(run.local_id, run.name, "the opening", why)
    spool.opened(run.local_id, server_id)
    return Sent(run.local_id)


def _post(
    spool: Spool,
    api: Api,
    run: RunRecord,
    batch: Pending,
    binary: bool,
    state: SenderState,
    say: Callable[[str], None],
) -> Step:
    what = f"batch {batch.seq}"
    damage = batch.damage()
    if damage is not None:
        where = f"batch {batch.seq} of run {run.name} ({batch.rows} rows) in {spool.path}"
        spool.damaged(batch.local_id, batch.seq, f"{where}: {damage}")
        say(
            f"{where} is damaged: {damage}; kept in the spool, never sent; the run's delivery "
            "stops there (`rigclient status`)"
        )
        return Sent(run.local_id)
    args = (
        Api.npz_batch(batch.seq, batch.group, batch.payload)
        if binary
        else Api.batch(batch.seq, batch.group, columns_of(batch.payload))
    )
    path = f"/runs/{batch.server_id}/readings"
    try:
        answer = api.attempt("POST", path, **args)
    except ServerRefused as exc:
        if exc.problem.status == 422:
            return _stop(spool, run, what, exc, say)
        return Failed(run.local_id, run.name, what, _refusal(exc))
    if isinstance(answer, TryLater):
        return Failed(run.local_id, run.name, what, answer)
    try:
        receipt = BatchReceipt.model_validate(answer.json())
    except (ValueError, ValidationError):
        why = TryLater(f"POST {api.url_of(path)}: {not_the_api(answer, 'a receipt')}")
        return Failed(run.local_id, run.name, what, why)
    state.duplicates += receipt.duplicate
    spool.acknowledged(batch.local_id, batch.seq)
    return Sent(run.local_id)


def _finish(
    spool: Spool, api: Api, run: RunRecord, server_id: str, say: Callable[[str], None]
) -> Step:
    answer: httpx.Response | TryLater
    try:
        answer = api.attempt("POST", f"/runs/{server_id}/finish")
    except ServerRefused as exc:
        if exc.problem.status == 422:  # e.g. too few readings for the results
            return _stop(spool, run, "finish", exc, say)
        if exc.problem.status != 409:
            return Failed(run.local_id, run.name, "the finish", _refusal(exc))
        # "not open": finished before the answer was lost?
        answer = api.attempt("GET", f"/runs/{server_id}")
        if isinstance(answer, TryLater):
            return Failed(run.local_id, run.name, "the finish", answer)
        if Run.model_validate(answer.json()).state is not RunState.FINISHED:
            return Failed(run.local_id, run.name, "the finish", _refusal(exc))
    if isinstance(answer, TryLater):
        return Failed(run.local_id, run.name, "the finish", answer)
    try:  # the API's run, finished: a proxy's welcome page is not a finish
        finished = Run.model_validate(answer.json()).state is RunState.FINISHED
    except ValueError:
        finished = False
    if not finished:
        url = api.url_of(f"/runs/{server_id}/finish")
        why = TryLater(f"POST {url}: {not_the_api(answer, 'the finished run')}")
        return Failed(run.local_id, run.name, "the finish", why)
    spool.finished(run.local_id)
    return Sent(run.local_id)
