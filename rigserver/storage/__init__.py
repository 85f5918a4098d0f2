"""Run storage: the :class:`RunStore` protocol, the HDF5 store on local disk, the PostgreSQL
store of a cluster, the in-memory store for tests, and the storage error tree.

::

    base, errors          the protocols (RunStore, LiveStore) and the storage errors
    waiters               live streams told in process (the embedded and memory stores)
    runfile, payloads     the run file's layout; a batch's bytes, as every store keeps them
    corrections, _checks  what every store checks and shares (_catalogue: a run's entry and
                          a query's filters; _derived: what follows from the others)
    memory                the tests' store, in memory
    archived              a run file from elsewhere (an .eln archive's) as batches
    series, notes,        series of runs, the students' words and sketches: the stores, their
    sketches, _tables     SQL written once for a Database (_tables: SQLite's)
    embedded/             HDF5Store: the SQLite journal and the run files on local disk
    cluster/              PostgresStore: PostgreSQL, LISTEN/NOTIFY, HSDS
    servers/              throwaway local PostgreSQL and HSDS servers (tests, one machine)

The commands over a data directory (``rigserver check``, ``rigserver migrate``) live in
:mod:`rigserver.commands`; the storage error tree (``StorageError`` and below) is drawn in
:mod:`rigserver.storage.errors`.
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
