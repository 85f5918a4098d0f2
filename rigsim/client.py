"""The simulated lab PC: opens a run, posts its batches at the stand's pace, finishes it.

It posts through :class:`rigclient.http.Api` (the one client of the project: retries with
backoff and jitter, ``Retry-After``, duplicate receipts, a lost finish answer, the opening's
``Idempotency-Key``), directly rather than through rigclient's spool: a simulated stand has
nothing to lose when the lab PC dies, and the tests measure the server, not a disk.
"""

from __future__ import annotations

import uuid
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import httpx

from rigclient.errors import ServerUnavailable
from rigclient.http import Api, RetryPolicy, TryLater, problem_of, retry_after
from rigsim.batches import Batch, SimulatedRun
from schemas.readings import BatchReceipt
from schemas.runs import Run, RunCreate

USER_AGENT = "rigsim/0.1"


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


class LabClient(Api):
    """A simulated lab PC talking to a rigserver (the arguments of :class:`Api`)."""

    def __init__(self, url: str, key: str | None = None, **kwargs: Any) -> None:
        kwargs.setdefault("user_agent", USER_AGENT)
        super().__init__(url, key, **kwargs)

    def __enter__(self) -> LabClient:
        return self

    def first_contact(self) -> None:
        """``GET /stands`` once: a server nobody listens for (connection refused, a name
        not known) is said at once, not after two minutes of tries; a server that answers,
        even busy, is left to the retries of what follows."""
        answer = self.attempt("GET", "/stands")
        if isinstance(answer, TryLater) and isinstance(answer.cause, httpx.ConnectError):
            raise ServerUnavailable(answer.reason) from answer.cause

    def create_run(self, body: RunCreate, idempotency_key: str | None = None) -> Run:
        """``POST /runs`` with a fresh Idempotency-Key (not the seeded generator)."""
        return super().create_run(body, idempotency_key or str(uuid.uuid4()))

    def post_batch(
        self, run_id: str, seq: int, batch: Batch, *, binary: bool = False
    ) -> BatchReceipt:
        """``POST /runs/{id}/readings``: one simulated batch."""
        return self.post_columns(run_id, seq, batch.group, batch.columns, binary=binary)

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
