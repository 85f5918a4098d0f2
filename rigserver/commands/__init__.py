"""The commands of ``rigserver`` beyond serving: ``check`` (which runs of a data directory
can be read) and ``migrate`` (an embedded data directory into a cluster's PostgreSQL)."""
