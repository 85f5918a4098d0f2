"""The lab-PC client: opens a run, posts its batches at the stand's pace, finishes it.

Everything it says to the server goes through one :class:`httpx.Client`, so a test hands it
an :class:`httpx.MockTransport` (or any transport) and no socket is opened.

Delivery. Batches carry sequence numbers 0, 1, 2, ... in stand order. A batch is posted
until the server acknowledges it: transport errors (refused or dropped connections, timeouts:
a restarting server) and 408 (a body too slow), 429, 502, 503, 504 answers are retried
with exponential backoff and full jitter, honouring ``Retry-After`` when the server sends
one. A retried batch that the server had stored before it went away is answered 200 with
the first receipt (``duplicate``), which counts as delivered, so nothing is stored twice.
Any other error answer stops the run with the server's problem (title, detail, the
offending fields): retrying would not change it. A finish retried after its answer was
lost meets "409 not open"; the client then looks the run up and accepts it if it is finished.

Opening a run is sent with an ``Idempotency-Key`` (a fresh UUID, the same for its
retries): if the answer to ``POST /runs`` is lost, the retry is answered with the run the
first one opened, and no second run is left open and empty.
"""

from __future__ import annotations

import io
import random
import time
import uuid
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from email.utils import parsedate_to_datetime
from typing import Any

import httpx
import numpy as np
from pydantic import ValidationError

from rigsim.batches import Batch, SimulatedRun
from rigsim.errors import ServerRefused, ServerUnavailable
from schemas.problems import Problem
from schemas.readings import NPZ_MEDIA_TYPE, BatchReceipt
from schemas.runs import Run, RunCreate, RunState

API = "/api/v1"
USER_AGENT = "rigsim/0.1"


@dataclass(frozen=True, slots=True)
class RetryPolicy:
    """When and how long to retry a request.

    Attributes
    ----------
    attempts : int
        Tries of one request, the first included.
    base_delay : float
        Backoff before the second try, s; doubles with each try (full jitter).
    max_delay : float
        Largest backoff, s.
    max_retry_after : float
        Largest ``Retry-After`` honoured, s.
    deadline : float
        Time budget of one request over all its tries, s.
    statuses : frozenset of int
        Answers that mean "try again later".
    """

    attempts: int = 40
    base_delay: float = 0.2
    max_delay: float = 5.0
    max_retry_after: float = 60.0
    deadline: float = 120.0
    statuses: frozenset[int] = field(default_factory=lambda: frozenset({408, 429, 502, 503, 504}))

    def backoff(self, attempt: int, rng: random.Random) -> float:
        """Delay after failed try number ``attempt`` (1-based): U(0, min(max, base·2^(k-1)))."""
        return rng.uniform(0.0, min(self.max_delay, self.base_delay * 2.0 ** (attempt - 1)))


def retry_after(response: httpx.Response, now: datetime | None = None) -> float | None:
    """The ``Retry-After`` of an answer in seconds (delta-seconds or an HTTP date), or None."""
    value = response.headers.get("retry-after")
    if value is None:
        return None
    value = value.strip()
    if value.isdigit():
        return float(value)
    try:
        when = parsedate_to_datetime(value)
    except (TypeError, ValueError):
        return None
    if when.tzinfo is None:
        when = when.replace(tzinfo=UTC)
    return max(0.0, (when - (now or datetime.now(UTC))).total_seconds())


def problem_of(response: httpx.Response) -> Problem:
    """The problem+json of an error answer, or one made from its status and text."""
    try:
        return Problem.model_validate(response.json())
    except (ValueError, ValidationError):
        return Problem(
            title=response.reason_phrase or "Error",
            status=response.status_code,
            detail=response.text[:500] or f"HTTP {response.status_code}",
        )


@dataclass(frozen=True, slots=True)
class RunOutcome:
    """What a whole simulated run left on the server.

    Attributes
    ----------
    run : Run
        The finished run.
    results : dict
        ``GET /runs/{id}/results``: ``{"stand", "values", "units"}``.
    receipts : tuple of BatchReceipt
        One per batch, in order.
    retries : int
        Requests tried again (transport errors, 429/5xx).
    """

    run: Run
    results: dict[str, Any]
    receipts: tuple[BatchReceipt, ...]
    retries: int

    @property
    def duplicates(self) -> int:
        """Batches the server had already stored when their retry arrived."""
        return sum(r.duplicate for r in self.receipts)


ProgressCallback = Callable[[int, int, BatchReceipt], None]


class LabClient:
    """A lab PC talking to a rigserver.

    Parameters
    ----------
    url : str
        The server, e.g. ``http://127.0.0.1:8000``.
    key : str or None
        API key with the scope ``write:<stand>`` (and ``read`` unless reads are public).
    transport : httpx.BaseTransport, optional
        Replaces the network (tests pass an :class:`httpx.MockTransport`).
    timeout : float
        Per-request timeout, s.
    retry : RetryPolicy
    sleep, clock : callables
        ``time.sleep`` and ``time.monotonic`` unless a test replaces them.
    seed : int, optional
        Seed of the backoff jitter.
    """

    def __init__(
        self,
        url: str,
        key: str | None = None,
        *,
        transport: httpx.BaseTransport | None = None,
        timeout: float = 30.0,
        retry: RetryPolicy | None = None,
        sleep: Callable[[float], None] = time.sleep,
        clock: Callable[[], float] = time.monotonic,
        seed: int | None = None,
    ) -> None:
        headers = {"User-Agent": USER_AGENT}
        if key:
            headers["Authorization"] = f"Bearer {key}"
        self._http = httpx.Client(
            base_url=url.rstrip("/") + API, headers=headers, timeout=timeout, transport=transport
        )
        self.retry = retry or RetryPolicy()
        self._sleep = sleep
        self._clock = clock
        self._rng = random.Random(seed)
        self.retries = 0

    def close(self) -> None:
        self._http.close()

    def __enter__(self) -> LabClient:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # --- one request, retried -------------------------------------------------------------

    def _request(
        self,
        method: str,
        path: str,
        *,
        json: Any = None,
        content: bytes | None = None,
        params: Mapping[str, str | int] | None = None,
        headers: Mapping[str, str] | None = None,
    ) -> httpx.Response:
        policy = self.retry
        start = self._clock()
        last: str = ""
        cause: Exception | None = None
        for attempt in range(1, policy.attempts + 1):
            try:
                response = self._http.request(
                    method, path, json=json, content=content, params=params, headers=headers
                )
            except httpx.TransportError as exc:
                cause, last = exc, f"{type(exc).__name__}: {exc}"
                delay = policy.backoff(attempt, self._rng)
            else:
                if response.is_success:
                    return response
                if response.status_code not in policy.statuses:
                    raise ServerRefused(problem_of(response))
                problem = problem_of(response)
                cause, last = None, f"{problem.status} {problem.title}: {problem.detail}"
                told = retry_after(response)
                delay = (
                    min(told, policy.max_retry_after)
                    if told is not None
                    else policy.backoff(attempt, self._rng)
                )
            if attempt == policy.attempts or self._clock() - start + delay > policy.deadline:
                raise ServerUnavailable(
                    f"{method} {path} failed after {attempt} tries in "
                    f"{self._clock() - start:.1f} s; last: {last}"
                ) from cause
            self.retries += 1
            self._sleep(delay)
        raise AssertionError("unreachable")  # pragma: no cover

    # --- the API ------------------------------------------------------------------------

    def create_run(self, body: RunCreate) -> Run:
        """``POST /runs``: open a run (once, however often it is retried)."""
        response = self._request(
            "POST",
            "/runs",
            json=body.model_dump(mode="json"),
            headers={"Idempotency-Key": str(uuid.uuid4())},  # not the seeded generator
        )
        return Run.model_validate(response.json())

    def get_run(self, run_id: str) -> Run:
        """``GET /runs/{id}``."""
        return Run.model_validate(self._request("GET", f"/runs/{run_id}").json())

    def post_batch(
        self, run_id: str, seq: int, batch: Batch, *, binary: bool = False
    ) -> BatchReceipt:
        """``POST /runs/{id}/readings``: one batch, JSON columns or a binary npz archive."""
        path = f"/runs/{run_id}/readings"
        if binary:
            buffer = io.BytesIO()
            arrays: dict[str, Any] = {k: np.asarray(v) for k, v in batch.columns.items()}
            np.savez(buffer, **arrays)
            response = self._request(
                "POST",
                path,
                content=buffer.getvalue(),
                params={"seq": seq, "group": batch.group},
                headers={"Content-Type": NPZ_MEDIA_TYPE},
            )
        else:
            body = {"seq": seq, "group": batch.group, "columns": batch.as_json()}
            response = self._request("POST", path, json=body)
        return BatchReceipt.model_validate(response.json())

    def finish(self, run_id: str) -> Run:
        """``POST /runs/{id}/finish``; a finish whose first answer was lost is accepted."""
        try:
            return Run.model_validate(self._request("POST", f"/runs/{run_id}/finish").json())
        except ServerRefused as exc:
            if exc.problem.status != 409:
                raise
            run = self.get_run(run_id)
            if run.state is not RunState.FINISHED:
                raise
            return run

    def results(self, run_id: str) -> dict[str, Any]:
        """``GET /runs/{id}/results``."""
        found: dict[str, Any] = self._request("GET", f"/runs/{run_id}/results").json()
        return found

    def run(
        self,
        sim: SimulatedRun[Any],
        *,
        speed: float | None = None,
        binary: bool = False,
        on_batch: ProgressCallback | None = None,
    ) -> RunOutcome:
        """Open the run, post every batch at ``speed`` times the stand's pace, finish it.

        ``speed`` None posts as fast as the server takes the batches.
        """
        if speed is not None and speed <= 0:
            raise ValueError(f"speed must be > 0 (or None for as fast as possible), got {speed}")
        run = self.create_run(sim.run_create)
        receipts: list[BatchReceipt] = []
        started = self._clock()
        total = len(sim.batches)
        for seq, batch in enumerate(sim.batches):
            if speed is not None:
                wait = batch.at / speed - (self._clock() - started)
                if wait > 0:
                    self._sleep(wait)
            receipt = self.post_batch(run.id, seq, batch, binary=binary)
            receipts.append(receipt)
            if on_batch is not None:
                on_batch(seq, total, receipt)
        finished = self.finish(run.id)
        return RunOutcome(
            run=finished,
            results=self.results(run.id),
            receipts=tuple(receipts),
            retries=self.retries,
        )


__all__ = ["LabClient", "RetryPolicy", "RunOutcome", "problem_of", "retry_after"]
