"""A bounded number of places for costly work, shared fairly between keys.

At most ``queue`` places are taken at once, and one key (its fingerprint; a caller without
a key by its address) at most its ``share`` of them; one more is answered 503 with
``Retry-After``. The report renders (:mod:`rigserver.api.report_pool`) and the ``.eln``
imports (:mod:`rigserver.api.import_slots`) are admitted so.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from rigserver.api.problems import ApiProblem


@dataclass(frozen=True, slots=True)
class Busy:
    """The words of the 503 answer: its title, its detail when all places are taken and when
    the key's are (``{queue}`` and ``{per_key}`` filled in), a note after the retry time."""

    title: str
    all_taken: str
    key_taken: str
    note: str = ""


class FairPlaces:
    """Places for work under way (see the module docstring)."""

    def __init__(self, *, queue: int, share: float, retry_after: int, busy: Busy) -> None:
        self.queue = queue
        self.per_key = max(1, int(queue * share))
        self.retry_after = retry_after
        self._busy = busy
        self._lock = threading.Lock()
        self._held: dict[str, int] = {}

    @property
    def held(self) -> dict[str, int]:
        """Places taken, by key."""
        with self._lock:
            return dict(self._held)

    def claim(self, key: str) -> ApiProblem | None:
        """Take a place for ``key``; the 503 answer if there is none for it."""
        with self._lock:
            total = sum(self._held.values())
            held = self._held.get(key, 0)
            if total >= self.queue or held >= self.per_key:
                return self._refusal(total >= self.queue)
            self._held[key] = held + 1
            return None

    def release(self, key: str) -> None:
        """Give back a place of ``key``."""
        with self._lock:
            left = self._held.pop(key, 0) - 1
            if left > 0:
                self._held[key] = left

    @contextmanager
    def admitted(self, key: str) -> Iterator[None]:
        """A place for ``key`` while the block runs; 503 beyond the places or the key's share."""
        refusal = self.claim(key)
        if refusal is not None:
            raise refusal
        try:
            yield
        finally:
            self.release(key)

    def _refusal(self, full: bool) -> ApiProblem:
        words = self._busy.all_taken if full else self._busy.key_taken
        detail = words.format(queue=self.queue, per_key=self.per_key)
        return ApiProblem(
            503,
            self._busy.title,
            f"{detail}; retry in {self.retry_after} s{self._busy.note}",
            headers={"Retry-After": str(self.retry_after)},
        )
