"""Run arrays in HSDS (the HDF REST service) through h5pyd: one domain per run.

Layout of a run's domain ``<folder><run id>.h5``: the run file's (:mod:`.runfile`) arrays
and the attributes that describe them::

    /entry                    @stand @run (the Run as JSON when the domain was made)
      <group>/                one per channel group of the stand
        <channel>             float64, 1-D, resizable, chunks of the run file's size
                              @units @long_name

Rows are written at absolute positions (row ``start`` of the group onwards), so writing
a batch again after a failure stores the same values in the same place. HSDS keeps what
it is sent in memory and writes it to storage lazily: :meth:`HsdsArrays.flush` asks the
service to write the domain's chunks now, and only after it has answered may the rows be
counted as stored. Every failure of the service (down, restarting, refusing) raises
``StorageUnavailable``.
"""

from __future__ import annotations

import socket
from collections.abc import Mapping
from typing import Any
from urllib.parse import unquote

import h5pyd
import numpy as np
from h5pyd.httpconn import HttpConn
from numpy.typing import NDArray

from rigserver.storage._checks import stand_groups
from rigserver.storage._failures import failures_as
from rigserver.storage.cluster.hsds_settings import HsdsSettings
from rigserver.storage.errors import StorageUnavailable
from rigserver.storage.runfile import chunk_rows
from schemas.channels import configured_groups
from schemas.runs import Run

_UNIX = "http+unix://"
#: Seconds a request to HSDS may take before it fails
TIMEOUT_SECONDS = 10
#: What h5pyd raises when the service fails (it raises IOError with the HTTP status, and
#: KeyError for an object missing from a domain)
HSDS_FAILURES: tuple[type[Exception], ...] = (OSError, KeyError, ValueError)


class HsdsArrays:
    """The run domains of one HSDS service (module docstring). Thread-safe: each call
    opens its own connection."""

    def __init__(self, settings: HsdsSettings) -> None:
        self.settings = settings
        self._folder_made = False

    def _answering(self) -> None:
        """``StorageUnavailable`` at once if a unix-socket endpoint takes no connection
        (h5pyd would retry, and leave its socket open)."""
        endpoint = self.settings.endpoint
        if not endpoint.startswith(_UNIX):
            return
        path = unquote(endpoint.removeprefix(_UNIX))
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as probe:
            probe.settimeout(TIMEOUT_SECONDS)
            try:
                probe.connect(path)
            except OSError as exc:
                raise StorageUnavailable(f"HSDS does not answer at {path}: {exc}") from exc

    def domain(self, run_id: str) -> str:
        return f"{self.settings.folder}{run_id}.h5"

    def _access(self) -> dict[str, Any]:
        """h5pyd's arguments naming the service, the user and the bucket."""
        s = self.settings
        return {
            "endpoint": s.endpoint,
            "username": s.username,
            "password": s.password,
            "bucket": s.bucket,
        }

    def _open(self, run_id: str, mode: str) -> Any:
        return h5pyd.File(
            self.domain(run_id), mode, retries=1, timeout=TIMEOUT_SECONDS, **self._access()
        )

    def ready(self) -> None:
        """Make the domains' folder if it is not there (``StorageUnavailable`` if the
        service does not answer)."""
        self._answering()
        with failures_as("opening the HSDS folder of the runs", HSDS_FAILURES):
            self._make_folder()

    def _make_folder(self) -> None:
        if self._folder_made:
            return
        folder_name = self.settings.folder
        try:
            folder = h5pyd.Folder(folder_name, mode="r", **self._access())
        except FileNotFoundError:
            folder = h5pyd.Folder(folder_name, mode="x", **self._access())
        folder.close()
        self._folder_made = True

    def write(
        self, run: Run, group: str, start: int, columns: Mapping[str, NDArray[np.float64]]
    ) -> None:
        """Rows ``start:start + n`` of ``group`` (every channel, each ``n`` long), then the
        server-side flush: once this returns, they are in HSDS's storage."""
        self._answering()
        with failures_as(f"writing run {run.id} to HSDS", HSDS_FAILURES):
            self._make_folder()
            with self._open(run.id, "a") as f:  # made if missing, empty
                if "entry" not in f:
                    _lay_out(f, run)
                g = f["entry"][group]
                for name, values in columns.items():
                    ds = g[name]
                    end = start + len(values)
                    if ds.shape[0] != end:
                        ds.resize((end,))
                    if len(values):
                        ds[start:end] = np.ascontiguousarray(values, np.float64)
                f.flush()
            self._flush_storage(run.id)

    def _flush_storage(self, run_id: str) -> None:
        """Have the service write the domain's chunks to storage (``PUT /?flush=1``)."""
        conn = HttpConn(self.domain(run_id), retries=1, timeout=TIMEOUT_SECONDS, **self._access())
        try:
            conn.open()
            rsp = conn.PUT("/", params={"flush": 1})
        finally:
            conn.close()
        if rsp.status_code not in (200, 204):
            raise StorageUnavailable(
                f"HSDS did not flush the domain of run {run_id}: {rsp.status_code} {rsp.reason}"
            )

    def read(
        self, run_id: str, group: str, names: list[str], start: int, stop: int
    ) -> dict[str, NDArray[np.float64]]:
        """Rows ``start:stop`` of the channels, as stored in the run's domain."""
        self._answering()
        with (
            failures_as(f"reading run {run_id} from HSDS", HSDS_FAILURES),
            self._open(run_id, "r") as f,
        ):
            g = f["entry"][group]
            return {n: np.asarray(g[n][start:stop], np.float64) for n in names}


def _lay_out(f: Any, run: Run) -> None:
    """The run's groups and empty resizable channels in a new domain."""
    entry = f.create_group("entry")
    entry.attrs["stand"] = run.stand.value
    entry.attrs["run"] = run.model_dump_json()
    for decl in configured_groups(stand_groups(run.stand), run.configuration):
        g = entry.create_group(decl.name)
        chunk = chunk_rows(decl)
        for ch in decl.channels:
            ds = g.create_dataset(
                ch.name, shape=(0,), maxshape=(None,), chunks=(chunk,), dtype="f8"
            )
            ds.attrs["units"] = ch.unit
            ds.attrs["long_name"] = ch.long_name
