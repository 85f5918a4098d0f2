"""Run storage: the :class:`RunStore` protocol, the HDF5 store on local disk, the PostgreSQL
store of a cluster, the in-memory store for tests, and the storage error tree.

::

    base, errors          the protocols (RunStore, LiveStore) and the errors below
    waiters               live streams told in process (the embedded and memory stores)
    runfile, payloads     the run file's layout; a batch's bytes, as every store keeps them
    corrections, _checks  what every store checks and shares (_catalogue: a query's filters)
    memory                the tests' store, in memory
    archived              a run file from elsewhere (an .eln archive's) as batches
    series, notes         series of runs and the student's words: protocols, SQLite stores
    embedded/             HDF5Store: the SQLite journal and the run files on local disk
    cluster/              PostgresStore: PostgreSQL, LISTEN/NOTIFY, HSDS
    servers/              throwaway local PostgreSQL and HSDS servers (tests, one machine)

The commands over a data directory (``rigserver check``, ``rigserver migrate``) live in
:mod:`rigserver.commands`.

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
from rigserver.storage.cluster.postgres import PostgresStore
from rigserver.storage.embedded.hdf5 import HDF5Store
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
from rigserver.storage.memory import MemoryStore

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
