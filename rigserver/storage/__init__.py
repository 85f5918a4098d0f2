"""Run storage: the :class:`RunStore` protocol, the HDF5 store on local disk, the PostgreSQL
store of a cluster, the in-memory store for tests, and the storage error tree.

::

    StorageError
     ├── RunNotFound          no run with that id
     ├── RunDamaged           the run's catalogue entry or file cannot be read
     ├── RunExists            a run with that id is stored already
     ├── KeyReused            an Idempotency-Key that opened a run asks for another
     ├── RunNotOpen           the run is finished or aborted: it takes no more readings
     ├── SequenceConflict     a seq number reused with different content
     ├── StorageFull          the disk is full (the batch was not acknowledged)
     └── StorageUnavailable   any other failure to make a batch durable
"""

from __future__ import annotations

from rigserver.storage.base import BatchCheck, Columns, NewBatch, RunStore
from rigserver.storage.errors import (
    KeyReused,
    RunDamaged,
    RunExists,
    RunNotFound,
    RunNotOpen,
    SequenceConflict,
    StorageError,
    StorageFull,
    StorageUnavailable,
)
from rigserver.storage.hdf5 import HDF5Store
from rigserver.storage.memory import MemoryStore
from rigserver.storage.postgres import PostgresStore

__all__ = [
    "BatchCheck",
    "Columns",
    "HDF5Store",
    "KeyReused",
    "MemoryStore",
    "NewBatch",
    "PostgresStore",
    "RunDamaged",
    "RunExists",
    "RunNotFound",
    "RunNotOpen",
    "RunStore",
    "SequenceConflict",
    "StorageError",
    "StorageFull",
    "StorageUnavailable",
]
