"""The ``.eln`` imports of one service: a bounded number at once, shared fairly between keys.

An import writes the archive (up to ``--import-max-bytes``) and the run file it unpacks
(up to ``--import-unpacked-bytes``) to disk and recomputes the run's results: any number at
once would take the disk and the service's threads from everyone. So at most ``queue``
imports run at once, and one key (its fingerprint; a caller without a key by its address)
at most its ``share`` of them (:mod:`rigserver.api.places`, as the report renders);
one more is answered 503 with ``Retry-After`` before its body is read.
"""

from __future__ import annotations

from rigserver.api.places import Busy, FairPlaces


class ImportSlots(FairPlaces):
    """Places for imports under way (see the module docstring)."""

    def __init__(self, *, queue: int, share: float, retry_after: int) -> None:
        super().__init__(
            queue=queue,
            share=share,
            retry_after=retry_after,
            busy=Busy(
                "Imports under way",
                "the server imports at most {queue} archives at once and all places are taken",
                "one key may have at most {per_key} of them under way",
            ),
        )
