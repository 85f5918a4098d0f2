"""The embedded store: one data directory on local disk, a SQLite journal as the truth
(:mod:`~rigserver.storage.embedded.journal`, its batches' readings in payload files), one
HDF5 run file per run written behind it (:mod:`~rigserver.storage.embedded.backlog` for
large batches), coordinated by :class:`~rigserver.storage.embedded.hdf5.HDF5Store`."""
