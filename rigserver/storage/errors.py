"""The storage layer's exceptions; h5py, sqlite3 and OS errors are translated into these.

::

    StorageError
     ├── RunNotFound          no run with that id
     ├── RunDamaged           the run's catalogue entry or file cannot be read
     ├── RunExists            a run with that id is stored already
     ├── KeyReused            an Idempotency-Key that opened a run asks for another
     ├── RunNotOpen           the run is finished or aborted: it takes no more readings
     ├── SequenceConflict     a seq number reused with different content
     ├── StorageFull          the disk is full (the batch was not acknowledged)
     ├── StorageUnavailable   any other failure to make a batch durable
     ├── SeriesNotFound       no series with that id
     ├── MemberExists         the run is in the series already
     ├── MemberNotFound       the run is not in the series
     ├── SeriesFull           the series holds as many runs as a series may
     └── OtherStand           the series holds runs of another stand
"""

from __future__ import annotations


class StorageError(Exception):
    """Base of the storage layer's errors."""


class RunNotFound(StorageError):
    pass


class RunDamaged(StorageError):
    pass


class RunExists(StorageError):
    pass


class KeyReused(StorageError):
    """``run_id``: the run the key opened (its owner may learn it: the key is theirs)."""

    def __init__(self, message: str, run_id: str = "") -> None:
        super().__init__(message, run_id)
        self.run_id = run_id

    def __str__(self) -> str:
        return str(self.args[0])


class RunNotOpen(StorageError):
    pass


class SequenceConflict(StorageError):
    pass


class StorageFull(StorageError):
    pass


class StorageUnavailable(StorageError):
    pass


class SeriesNotFound(StorageError):
    pass


class MemberExists(StorageError):
    pass


class MemberNotFound(StorageError):
    pass


class SeriesFull(StorageError):
    pass


class OtherStand(StorageError):
    pass
