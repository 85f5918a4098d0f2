"""The cluster store, shared by several rigservers: the catalogue, the journal and the
student's words in PostgreSQL (:mod:`~rigserver.storage.cluster.postgres`), live streams
woken by LISTEN/NOTIFY (:mod:`~rigserver.storage.cluster.notify`), and with HSDS the run
arrays materialised there (:mod:`~rigserver.storage.cluster.materialiser`). Importing this
package needs nothing of the ``cluster`` extra; its modules that talk to HSDS do."""
