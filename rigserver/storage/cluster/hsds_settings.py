"""Where a cluster's run arrays live in HSDS (importable without the ``cluster`` extra)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class HsdsSettings:
    """The service endpoint (``http+unix://...`` for a unix socket), its user, the bucket,
    and the folder of the run domains."""

    endpoint: str
    username: str
    password: str
    bucket: str
    folder: str = "/rig/"
