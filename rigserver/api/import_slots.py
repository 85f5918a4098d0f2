"""The ``.eln`` imports of one service: a bounded number at once, shared fairly between keys.

An import writes the archive (up to ``--import-max-bytes``) and the run file it unpacks
(up to ``--import-unpacked-bytes``) to disk and recomputes the run's results: any number at
once would take the disk and the service's threads from everyone. So at most ``queue``
imports run at once, and one key (its fingerprint; a caller without a key by its address)
at most its ``share`` of them, as the report renders (:mod:`rigserver.api.report_pool`);
one more is answered 503 with ``Retry-After`` before its body is read.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager

from rigserver.api.problems import ApiProblem


class ImportSlots:
    """Places for imports under way (see the module docstring)."""

    def __init__(self, *, queue: int, share: float, retry_after: int) -> None:
        self.queue = queue
        self.per_key = max(1, int(queue * share))
        self.retry_after = retry_after
        self._lock = threading.Lock()
        self._held: dict[str, int] = {}

    @property
    def held(self) -> dict[str, int]:
        """Imports under way, by key."""
        with self._lock:
            return dict(self._held)

    @contextmanager
    def admitted(self, key: str) -> Iterator[None]:
        """A place for an import of ``key`` while the block runs; 503 beyond the places
        or the key's share."""
        with self._lock:
            total = sum(self._held.values())
            held = self._held.get(key, 0)
            if total >= self.queue or held >= self.per_key:
                raise self._busy(total >= self.queue)
            self._held[key] = held + 1
        try:
            yield
        finally:
            with self._lock:
                left = self._held.pop(key) - 1
                if left > 0:
                    self._held[key] = left

    def _busy(self, full: bool) -> ApiProblem:
        detail = (
            f"the server imports at most {self.queue} archives at once and all places are taken"
            if full
            else f"one key may have at most {self.per_key} of them under way"
        )
        return ApiProblem(
            503,
            "Imports under way",
            f"{detail}; retry in {self.retry_after} s",
            headers={"Retry-After": str(self.retry_after)},
        )
