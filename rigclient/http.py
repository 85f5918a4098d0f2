"""The server's API as the lab PC sees it: one request, classified; or retried with backoff.

Everything said to the server goes through one :class:`httpx.Client`, so a test hands it an
:class:`httpx.MockTransport` (or any transport) and no socket is opened.

Each answer is one of three things. A success. A refusal: the API's own problem document
(``application/problem+json``) with a 4xx status other than 408, 425 and 429 -- the API
says the request itself is wrong (:class:`ServerRefused`). Or a failure to try again
(:class:`TryLater`): every other answer -- a transport error (refused or dropped
connections, timeouts), any 5xx, 408/425/429 with the server's ``Retry-After``, and any
answer that is not the API's (a proxy's HTML page, whatever its status) -- described
plainly with the method and the URL (``POST http://rig:8000/api/v1/runs: connection
refused: nothing listens at rig:8000 ...``). :meth:`Api.attempt` makes one try and says
which; :meth:`Api.request` retries with exponential backoff and full jitter within a
:class:`RetryPolicy` (the direct client of rigsim), telling ``report`` what fails; the
spool's sender (:mod:`rigclient.sender`) uses :meth:`Api.attempt`, decides what a refusal
stops (only a 422), and waits by itself, without a deadline.

Every try has a total deadline (``deadline``, s): httpx's timeouts bound each connect,
read and write, not the whole request, so an answer dripping one byte every few seconds
would hold the sender for as long as it drips. A timer shuts the try's socket down at the
deadline (the sockets come from httpx's ``trace`` extension), and the try is a failure
("no complete answer within 60 s").

A batch retried after the server had stored it is answered 200 with the first receipt
(``duplicate``), which counts as delivered. A finish retried after its answer was lost
meets "409 not open"; the run is then looked up and accepted if it is finished. Opening a
run carries an ``Idempotency-Key`` chosen by the caller (the spool keeps it), so a retried
opening is answered with the run the first one opened.
"""

from __future__ import annotations

import contextlib
import html
import io
import random
import re
import socket
import threading
import time
import weakref
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from email.utils import parsedate_to_datetime
from typing import Any

import httpx
import numpy as np
from numpy.typing import ArrayLike
from pydantic import ValidationError

from rigclient.errors import ServerRefused, ServerUnavailable, problem_text
from schemas.corrections import CorrectedRow
from schemas.problems import PROBLEM_MEDIA_TYPE, Problem
from schemas.readings import NPZ_MEDIA_TYPE, BatchReceipt
from schemas.runs import Run, RunCreate, RunState

API = "/api/v1"
USER_AGENT = "rigclient/0.1"
CONNECT_TIMEOUT = 10.0  # s: a host that drops the connection attempt is said at once


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
        4xx answers that mean "try again later" even as the API's problem document. Every
        5xx, and every answer that is not the API's problem document, is tried again too.
    """

    attempts: int = 40
    base_delay: float = 0.2
    max_delay: float = 5.0
    max_retry_after: float = 60.0
    deadline: float = 120.0
    statuses: frozenset[int] = field(default_factory=lambda: frozenset({408, 425, 429}))

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
    return api_problem(response) or Problem(
        title=response.reason_phrase or "Error",
        status=response.status_code,
        detail=_body(response) or f"HTTP {response.status_code}",
    )


def api_problem(response: httpx.Response) -> Problem | None:
    """The API's own problem document in an answer (``application/problem+json``, the
    answer's status), or None: a proxy's page or any other body is not the API speaking."""
    media = response.headers.get("content-type", "").split(";")[0].strip().lower()
    if media != PROBLEM_MEDIA_TYPE:
        return None
    try:
        problem = Problem.model_validate(response.json())
    except (ValueError, ValidationError):
        return None
    return problem if problem.status == response.status_code else None


_TITLE = re.compile(rb"<title[^>]*>(.*?)</title>", re.IGNORECASE | re.DOTALL)


def _body(response: httpx.Response, size: int = 120) -> str:
    """What an answer's body is, in a few words: an HTML page's title, else its start."""
    content = response.content
    media = response.headers.get("content-type", "").split(";")[0].strip().lower()
    if not content.strip():
        return "an empty answer"
    if "html" in media or content.lstrip()[:1] == b"<":
        found = _TITLE.search(content[:65536])
        raw = found[1].decode("utf-8", "replace") if found is not None else ""
        title = " ".join(html.unescape(raw).split())
        return f'an HTML page "{title[:size]}"' if title else "an HTML page"
    text = " ".join(content[:size].decode("utf-8", "replace").split())
    return f"{media or 'an answer'} {text!r}"


def not_the_api(response: httpx.Response, expected: str = "") -> str:
    """Why an answer is not the API's, for a message: its status and what the body is
    (``expected``: what it should have been, e.g. "a receipt")."""
    instead = f", not {expected}" if expected else ""
    return (
        f"{response.status_code} {response.reason_phrase}: {_body(response)}{instead}, not the "
        "API's answer (a proxy between this PC and the server, or the wrong URL?)"
    )


class RequestDeadline(httpx.TimeoutException):
    """A try that had no complete answer within :attr:`Api.deadline` (its socket was shut)."""


@dataclass(frozen=True, slots=True)
class TryLater:
    """One try that failed and is worth trying again: what happened (with the method and
    URL), how long the server asked to wait, the exception if any, the status if the
    server answered, and the API's problem if the answer was one."""

    reason: str
    retry_after: float | None = None
    cause: Exception | None = None
    status: int | None = None
    url: str = ""
    problem: Problem | None = None

    @property
    def kind(self) -> str:
        """What failed, coarsely (a status, or the exception's class): a new kind of
        failure is told at once, the same again only now and then (:class:`Reporter`)."""
        if self.status is not None:
            return str(self.status)
        return type(self.cause).__name__ if self.cause is not None else self.reason


def _in_chain(
    exc: BaseException, kind: type[BaseException] | tuple[type[BaseException], ...]
) -> bool:
    seen: set[int] = set()
    current: BaseException | None = exc
    while current is not None and id(current) not in seen:
        if isinstance(current, kind):
            return True
        seen.add(id(current))
        current = current.__cause__ or current.__context__
    return False


def transport_failure(exc: httpx.RequestError, url: str, timeout: httpx.Timeout) -> str:
    """A transport error in plain words: what failed and what the operator can check."""
    name = type(exc).__name__
    said = f"[{name}: {exc}]" if str(exc) else f"[{name}]"
    target = httpx.URL(url)
    where = f"{target.host}:{target.port or (443 if target.scheme == 'https' else 80)}"
    if isinstance(exc, RequestDeadline):
        return f"{exc} (a server or a proxy that answers too slowly?)"
    if isinstance(exc, httpx.ConnectTimeout):
        return (
            f"no connection to {where} within {timeout.connect:g} s (is the server up, is the "
            f"URL right, does a firewall drop it?) {said}"
        )
    if isinstance(exc, httpx.ConnectError):
        text = str(exc).lower()
        if _in_chain(exc, ConnectionRefusedError) or "refused" in text:
            return (
                f"connection refused: nothing listens at {where} (is the server up, is the URL "
                f"right?) {said}"
            )
        if _in_chain(exc, socket.gaierror) or ("name" in text and "known" in text):
            return f"the name {target.host!r} is not known (is the URL right?) {said}"
        return f"could not connect to {where} {said}"
    if isinstance(exc, httpx.ReadTimeout):
        return f"no answer within {timeout.read:g} s {said}"
    if isinstance(exc, httpx.WriteTimeout):
        return f"the server took nothing for {timeout.write:g} s {said}"
    if isinstance(exc, httpx.PoolTimeout):
        return f"no free connection within {timeout.pool:g} s {said}"
    if isinstance(exc, httpx.RemoteProtocolError | httpx.ReadError | httpx.WriteError):
        return f"the connection broke before the answer came {said}"
    return f"the request failed {said}"


def answer_failure(response: httpx.Response, problem: Problem | None) -> str:
    """An error answer in plain words: the API's problem, or what the answer was."""
    return not_the_api(response) if problem is None else problem_text(problem)


def _duration(seconds: float) -> str:
    seconds = max(0.0, seconds)
    if seconds < 60:
        return f"{seconds:.0f} s" if seconds >= 10 else f"{seconds:.1f} s"
    minutes, secs = divmod(int(seconds), 60)
    if minutes < 60:
        return f"{minutes} min {secs} s"
    hours, minutes = divmod(minutes, 60)
    return f"{hours} h {minutes} min"


class Reporter:
    """When to tell the operator about the failed tries of one thing: the first at once, a
    failure of another kind at once, the same again after ``first_repeat`` s, then twice
    as long each time up to every ``max_repeat`` s; and once it works again."""

    def __init__(
        self,
        clock: Callable[[], float] = time.monotonic,
        first_repeat: float = 30.0,
        max_repeat: float = 600.0,
    ) -> None:
        self._clock = clock
        self.first_repeat, self.max_repeat = first_repeat, max_repeat
        self.since: float | None = None
        self.tries = 0
        self._kind: str | None = None
        self._next = 0.0
        self._gap = first_repeat

    def failed(self, failure: TryLater) -> str | None:
        """The text to say about this failed try, or None (said recently)."""
        now = self._clock()
        if self.since is None:
            self.since, self.tries = now, 0
        self.tries += 1
        if failure.kind != self._kind:
            self._kind, self._gap, self._next = (
                failure.kind,
                self.first_repeat,
                now + self.first_repeat,
            )
            if self.tries == 1:
                return failure.reason
            spent = _duration(now - self.since)
            return f"{failure.reason} (failing for {spent}, {self.tries} tries)"
        if now < self._next:
            return None
        self._gap = min(self._gap * 2.0, self.max_repeat)
        self._next = now + self._gap
        spent = _duration(now - self.since)
        return f"still failing after {self.tries} tries in {spent}: {failure.reason}"

    def succeeded(self) -> str | None:
        """The text to say once a try succeeds after failures, or None."""
        if self.since is None:
            return None
        spent = _duration(self._clock() - self.since)
        tries = f"{self.tries} failed tr{'y' if self.tries == 1 else 'ies'}"
        text = f"the server answers again, after {tries} in {spent}"
        self.since, self.tries, self._kind = None, 0, None
        return text


def _is_json(response: httpx.Response) -> bool:
    """An answer of the API has a JSON body (a proxy's welcome page has not)."""
    media = str(response.headers.get("content-type", "")).split(";")[0].strip().lower()
    return media == "application/json" or media.endswith("+json")


def npz_bytes(columns: Mapping[str, ArrayLike]) -> bytes:
    """Columns as the binary batch form: a ``numpy.savez`` archive, one array per channel."""
    buffer = io.BytesIO()
    arrays: dict[str, Any] = {k: np.asarray(v, dtype=np.float64) for k, v in columns.items()}
    np.savez(buffer, **arrays)
    return buffer.getvalue()


class Api:
    """The lab PC's side of the HTTP API. One request at a time (the deadline of a try
    shuts the sockets of this Api down).

    Parameters
    ----------
    url : str
        The server, e.g. ``http://127.0.0.1:8000``.
    key : str or None
        API key with the scope ``write:<stand>`` (and ``read`` unless reads are public).
    transport : httpx.BaseTransport, optional
        Replaces the network (tests pass an :class:`httpx.MockTransport`).
    timeout : float
        Timeout of each read and write of a try, s (a connection: at most 10 s).
    deadline : float
        Time of a whole try, s: connecting, sending and the complete answer.
    retry : RetryPolicy
    sleep, clock : callables
        ``time.sleep`` and ``time.monotonic`` unless a test replaces them.
    seed : int, optional
        Seed of the backoff jitter.
    user_agent : str
    report : callable, optional
        Told, in a line of text, what fails while :meth:`request` tries again (the first
        failure at once, the same one now and then, the recovery).
    """

    def __init__(
        self,
        url: str,
        key: str | None = None,
        *,
        transport: httpx.BaseTransport | None = None,
        timeout: float = 30.0,
        deadline: float = 60.0,
        retry: RetryPolicy | None = None,
        sleep: Callable[[float], None] = time.sleep,
        clock: Callable[[], float] = time.monotonic,
        seed: int | None = None,
        user_agent: str = USER_AGENT,
        report: Callable[[str], None] | None = None,
    ) -> None:
        if not deadline > 0 or not timeout > 0:
            raise ValueError(f"timeout and deadline must be > 0, got {timeout}, {deadline}")
        headers = {"User-Agent": user_agent}
        if key:
            headers["Authorization"] = f"Bearer {key}"
        self.url = url.rstrip("/")
        self.timeout = httpx.Timeout(timeout, connect=min(timeout, CONNECT_TIMEOUT))
        self.deadline = deadline
        self._http = httpx.Client(
            base_url=self.url + API, headers=headers, timeout=self.timeout, transport=transport
        )
        self.retry = retry or RetryPolicy()
        self._sleep = sleep
        self._clock = clock
        self.rng = random.Random(seed)
        self.retries = 0
        self.report = report
        self._sockets: weakref.WeakSet[socket.socket] = weakref.WeakSet()
        self._guard = threading.Lock()
        self._inflight: object | None = None
        self._expired: object | None = None

    def close(self) -> None:
        self._http.close()

    def __enter__(self) -> Api:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def url_of(self, path: str) -> str:
        """The full URL of an API path, as messages name it."""
        return f"{self.url}{API}{path}"

    # --- the deadline of a try ------------------------------------------------------------

    def _trace(self, event: str, info: Mapping[str, Any]) -> None:
        """httpx's ``trace`` extension: keep the socket of each connection opened."""
        if event in ("connection.connect_tcp.complete", "connection.connect_unix_socket.complete"):
            stream = info.get("return_value")
            sock = stream.get_extra_info("socket") if stream is not None else None
            if isinstance(sock, socket.socket):
                with self._guard:
                    self._sockets.add(sock)

    def _expire(self, token: object) -> None:
        """The try ``token`` is past its deadline: shut its connections down."""
        with self._guard:
            if self._inflight is not token:
                return
            self._expired = token
            sockets = list(self._sockets)
        for sock in sockets:
            with contextlib.suppress(OSError):  # closed already
                sock.shutdown(socket.SHUT_RDWR)

    def _send(self, method: str, path: str, **kwargs: Any) -> httpx.Response:
        """One request with its total deadline; :class:`RequestDeadline` past it."""
        token = object()
        timer = threading.Timer(self.deadline, self._expire, (token,))
        timer.daemon = True
        with self._guard:
            self._inflight = token
        timer.start()
        try:
            return self._http.request(method, path, extensions={"trace": self._trace}, **kwargs)
        except httpx.RequestError as exc:
            if self._expired is token:
                raise RequestDeadline(
                    f"no complete answer within {self.deadline:g} s, the deadline of one request",
                    request=exc.request,
                ) from exc
            raise
        finally:
            timer.cancel()
            with self._guard:
                self._inflight = None
                if self._expired is token:
                    self._expired = None

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
        """One try: the answer if it succeeded, :class:`TryLater` if it failed and is worth
        another; :class:`ServerRefused` if the API says the request itself is wrong."""
        url = self.url_of(path)
        try:
            response = self._send(
                method, path, json=json, content=content, params=params, headers=headers
            )
        except httpx.RequestError as exc:
            text = transport_failure(exc, url, self.timeout)
            return TryLater(f"{method} {url}: {text}", None, exc, url=url)
        if response.is_success:
            return response
        problem = api_problem(response)
        status = response.status_code
        if problem is not None and 400 <= status < 500 and status not in self.retry.statuses:
            raise ServerRefused(problem, method=method, url=url)
        return TryLater(
            f"{method} {url}: {answer_failure(response, problem)}",
            retry_after(response),
            status=status,
            url=url,
            problem=problem,
        )

    def request(self, method: str, path: str, **kwargs: Any) -> httpx.Response:
        """:meth:`attempt` until it succeeds with a JSON answer, within the policy's tries
        and deadline; what fails meanwhile is told to :attr:`report`."""
        policy = self.retry
        start = self._clock()
        reporter = Reporter(self._clock)
        for attempt in range(1, policy.attempts + 1):
            answer = self.attempt(method, path, **kwargs)
            if isinstance(answer, httpx.Response) and not _is_json(answer):
                url = self.url_of(path)
                answer = TryLater(f"{method} {url}: {not_the_api(answer)}", url=url)
            if isinstance(answer, httpx.Response):
                said = reporter.succeeded()
                if said is not None and self.report is not None:
                    self.report(said)
                return answer
            delay = policy.delay(attempt, self.rng, answer.retry_after)
            spent = self._clock() - start
            if attempt == policy.attempts or spent + delay > policy.deadline:
                raise ServerUnavailable(
                    f"{method} {path} failed after {attempt} tries in {spent:.1f} s; "
                    f"last: {answer.reason}"
                ) from answer.cause
            said = reporter.failed(answer)
            if said is not None and self.report is not None:
                left = policy.deadline - spent
                self.report(f"{said}; trying again for up to {_duration(left)}")
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

    def correct(
        self, run_id: str, group: str, index: int, values: Mapping[str, float], reason: str
    ) -> CorrectedRow:
        """``PATCH /runs/{id}/readings/{group}/{index}``: cells of a stored row corrected,
        the values as typed kept; the row as it now reads. A retry stores nothing twice."""
        body = {"values": dict(values), "reason": reason}
        path = f"/runs/{run_id}/readings/{group}/{index}"
        return CorrectedRow.model_validate(self.request("PATCH", path, json=body).json())

    def strike(self, run_id: str, group: str, index: int, reason: str) -> CorrectedRow:
        """``DELETE /runs/{id}/readings/{group}/{index}``: a stored row struck out (kept as
        typed, left out of the results)."""
        path = f"/runs/{run_id}/readings/{group}/{index}"
        return CorrectedRow.model_validate(
            self.request("DELETE", path, json={"reason": reason}).json()
        )

    def results(self, run_id: str) -> dict[str, Any]:
        """``GET /runs/{id}/results``."""
        found: dict[str, Any] = self.request("GET", f"/runs/{run_id}/results").json()
        return found
