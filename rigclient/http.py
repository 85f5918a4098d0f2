"""The server's API as the lab PC sees it: one request, classified; or retried with backoff.

Everything said to the server goes through one :class:`httpx.Client`, so a test hands it an
:class:`httpx.MockTransport` (or any transport) and no socket is opened.

Each answer is one of three things. A success. A "try again later": transport errors
(refused or dropped connections, timeouts: a restarting server) and 408, 429, 502, 503,
504, with the server's ``Retry-After`` when it sends one. A refusal: any other error answer,
with the server's problem (title, detail, the offending fields); retrying would not change
it. :meth:`Api.attempt` makes one try and says which; :meth:`Api.request` retries with
exponential backoff and full jitter within a :class:`RetryPolicy` (the direct client of
rigsim); the spool's sender (:mod:`rigclient.sender`) uses :meth:`Api.attempt` and waits by
itself, without a deadline.

A batch retried after the server had stored it is answered 200 with the first receipt
(``duplicate``), which counts as delivered. A finish retried after its answer was lost
meets "409 not open"; the run is then looked up and accepted if it is finished. Opening a
run carries an ``Idempotency-Key`` chosen by the caller (the spool keeps it), so a retried
opening is answered with the run the first one opened.
"""

from __future__ import annotations

import io
import random
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from email.utils import parsedate_to_datetime
from typing import Any

import httpx
import numpy as np
from numpy.typing import ArrayLike
from pydantic import ValidationError

from rigclient.errors import ServerRefused, ServerUnavailable
from schemas.problems import Problem
from schemas.readings import NPZ_MEDIA_TYPE, BatchReceipt
from schemas.runs import Run, RunCreate, RunState

API = "/api/v1"
USER_AGENT = "rigclient/0.1"


@dataclass(frozen=True, slots=True)
class RetryPolicy:
    """When and how long to retry a request.

    Attributes
    ----------
    attempts : int
        Tries of one request, the first included (:meth:`Api.request`).
    base_delay : float
        Backoff before the second try, s; doubles with each try (full jitter).
    max_delay : float
        Largest backoff, s.
    max_retry_after : float
        Largest ``Retry-After`` honoured, s.
    deadline : float
        Time budget of one request over all its tries, s (:meth:`Api.request`).
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

    def delay(self, attempt: int, rng: random.Random, told: float | None) -> float:
        """The wait before the next try: the server's ``Retry-After`` (capped), else backoff."""
        if told is not None:
            return min(told, self.max_retry_after)
        return self.backoff(attempt, rng)


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
class TryLater:
    """One try that the server could not take now: why, and how long it asked to wait."""

    reason: str
    retry_after: float | None = None
    cause: Exception | None = None


def npz_bytes(columns: Mapping[str, ArrayLike]) -> bytes:
    """Columns as the binary batch form: a ``numpy.savez`` archive, one array per channel."""
    buffer = io.BytesIO()
    arrays: dict[str, Any] = {k: np.asarray(v, dtype=np.float64) for k, v in columns.items()}
    np.savez(buffer, **arrays)
    return buffer.getvalue()


class Api:
    """The lab PC's side of the HTTP API.

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
    user_agent : str
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
        user_agent: str = USER_AGENT,
    ) -> None:
        headers = {"User-Agent": user_agent}
        if key:
            headers["Authorization"] = f"Bearer {key}"
        self._http = httpx.Client(
            base_url=url.rstrip("/") + API, headers=headers, timeout=timeout, transport=transport
        )
        self.retry = retry or RetryPolicy()
        self._sleep = sleep
        self._clock = clock
        self.rng = random.Random(seed)
        self.retries = 0

    def close(self) -> None:
        self._http.close()

    def __enter__(self) -> Api:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # --- one try, and retried -------------------------------------------------------------

    def attempt(
        self,
        method: str,
        path: str,
        *,
        json: Any = None,
        content: bytes | None = None,
        params: Mapping[str, str | int] | None = None,
        headers: Mapping[str, str] | None = None,
    ) -> httpx.Response | TryLater:
        """One try: the answer if it succeeded, :class:`TryLater` if the server could not
        take it now; :class:`ServerRefused` if it never will."""
        try:
            response = self._http.request(
                method, path, json=json, content=content, params=params, headers=headers
            )
        except httpx.TransportError as exc:
            return TryLater(f"{type(exc).__name__}: {exc}", None, exc)
        if response.is_success:
            return response
        problem = problem_of(response)
        if response.status_code not in self.retry.statuses:
            raise ServerRefused(problem)
        reason = f"{problem.status} {problem.title}: {problem.detail}"
        return TryLater(reason, retry_after(response))

    def request(self, method: str, path: str, **kwargs: Any) -> httpx.Response:
        """:meth:`attempt` until it succeeds, within the policy's tries and deadline."""
        policy = self.retry
        start = self._clock()
        for attempt in range(1, policy.attempts + 1):
            answer = self.attempt(method, path, **kwargs)
            if isinstance(answer, httpx.Response):
                return answer
            delay = policy.delay(attempt, self.rng, answer.retry_after)
            if attempt == policy.attempts or self._clock() - start + delay > policy.deadline:
                raise ServerUnavailable(
                    f"{method} {path} failed after {attempt} tries in "
                    f"{self._clock() - start:.1f} s; last: {answer.reason}"
                ) from answer.cause
            self.retries += 1
            self._sleep(delay)
        raise AssertionError("unreachable")  # pragma: no cover

    # --- the API ------------------------------------------------------------------------

    @staticmethod
    def opening(body: RunCreate, idempotency_key: str) -> dict[str, Any]:
        """The arguments of ``POST /runs`` for :meth:`attempt` or :meth:`request`."""
        return {
            "json": body.model_dump(mode="json"),
            "headers": {"Idempotency-Key": idempotency_key},
        }

    def create_run(self, body: RunCreate, idempotency_key: str) -> Run:
        """``POST /runs``: open a run (once, however often it is retried with this key)."""
        response = self.request("POST", "/runs", **self.opening(body, idempotency_key))
        return Run.model_validate(response.json())

    def get_run(self, run_id: str) -> Run:
        """``GET /runs/{id}``."""
        return Run.model_validate(self.request("GET", f"/runs/{run_id}").json())

    @staticmethod
    def batch(
        seq: int, group: str, columns: Mapping[str, ArrayLike], *, binary: bool = False
    ) -> dict[str, Any]:
        """The arguments of ``POST /runs/{id}/readings`` for :meth:`attempt`: JSON columns
        ``{"seq", "group", "columns"}``, or an npz archive with ``?seq=&group=``."""
        if binary:
            return Api.npz_batch(seq, group, npz_bytes(columns))
        lists = {k: np.asarray(v, dtype=np.float64).tolist() for k, v in columns.items()}
        return {"json": {"seq": seq, "group": group, "columns": lists}}

    @staticmethod
    def npz_batch(seq: int, group: str, payload: bytes) -> dict[str, Any]:
        """The arguments of ``POST /runs/{id}/readings`` for a batch already in npz form."""
        return {
            "content": payload,
            "params": {"seq": seq, "group": group},
            "headers": {"Content-Type": NPZ_MEDIA_TYPE},
        }

    def post_columns(
        self,
        run_id: str,
        seq: int,
        group: str,
        columns: Mapping[str, ArrayLike],
        *,
        binary: bool = False,
    ) -> BatchReceipt:
        """``POST /runs/{id}/readings``: one batch, JSON columns or a binary npz archive."""
        path = f"/runs/{run_id}/readings"
        response = self.request("POST", path, **self.batch(seq, group, columns, binary=binary))
        return BatchReceipt.model_validate(response.json())

    def finish(self, run_id: str) -> Run:
        """``POST /runs/{id}/finish``; a finish whose first answer was lost is accepted."""
        try:
            return Run.model_validate(self.request("POST", f"/runs/{run_id}/finish").json())
        except ServerRefused as exc:
            return self.finished_anyway(run_id, exc)

    def finished_anyway(self, run_id: str, refusal: ServerRefused) -> Run:
        """The run if a refused finish was "409 not open" because it is finished already;
        else the refusal."""
        if refusal.problem.status != 409:
            raise refusal
        run = self.get_run(run_id)
        if run.state is not RunState.FINISHED:
            raise refusal
        return run

    def results(self, run_id: str) -> dict[str, Any]:
        """``GET /runs/{id}/results``."""
        found: dict[str, Any] = self.request("GET", f"/runs/{run_id}/results").json()
        return found
