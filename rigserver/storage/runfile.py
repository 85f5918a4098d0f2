"""The run file: one NeXus-flavoured HDF5 file per run, readable with plain h5py.

Layout::

    /                         @NX_class=NXroot @default=entry @creator @file_time @HDF5_Version
    /entry                    @NX_class=NXentry @default=<first NXdata group>
                              @operator @stand @title @state
                              @run            the full Run as JSON (schemas.runs.Run)
                              @configuration  the stand configuration snapshot as JSON
                              @finalized=True written last, when the run ends
      start_time, end_time    ISO 8601 strings (end_time once the run ends)
      title                   string
      <group>/                one per channel group of the stand: @NX_class=NXdata for an
                              aligned group, plotting what the stand measures against what
                              it is measured along (@signal, @auxiliary_signals, @axes: the
                              group's declared signals and axis, e.g. friction_moment against
                              time), NXcollection for the single measurements; @long_name
        <channel>             float64, 1-D, chunked, resizable (maxshape None)
                              @units (symbol of schemas.units, e.g. "N*m") @long_name
      corrections/            NXcollection, once a reading is corrected (the readings above
                              stay as typed): one entry per correction, in order, as
                              datasets of equal length: n, group, row, channel ("" for a
                              row struck out), was, now (NaN for a strike; @units "see
                              unit"), unit, reason, by, at (ISO 8601)
      results/                NXcollection, once results are stored
        json                  the results as JSON text
        values/<path>         float64, @units @long_name (see rigserver.storage._results)

All channels of a group have the same length; in the ``measurements`` group NaN marks a
channel absent from a batch (see :mod:`rigserver.storage._checks`). Chunks are 65 536 rows
(512 KiB) in groups with an increasing axis channel (the long records: SMTs-2 friction,
profiles) and 256 rows in table-like groups, so a ten-row run stays small and a 50-million-
row run has under a thousand chunks per channel. No compression, for write speed and so
that every HDF5 reader opens it.

Appends are buffered per group and written with one HDF5 call per channel once 65 536 rows
or 4096 batches have gathered, at the first append about a second after the oldest (0.5 to
1.5 s, drawn per file, so that runs started together do not all write at once), and before
any read, flush or close: the journal, not this file, makes a batch durable, and per-batch
HDF5 calls would cost ~0.1 ms per channel.
"""

from __future__ import annotations

import json
import os
import random
import shutil
import time
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import h5py
import numpy as np
from h5py import h5s
from numpy.typing import NDArray

from rigserver.storage._checks import channel_group, channel_names, last_finite, stand_groups
from rigserver.storage._results import CheckedResults
from rigserver.storage._time import iso, now
from schemas.channels import ChannelGroup, Order, configured_groups
from schemas.corrections import Correction
from schemas.runs import Run
from schemas.stands import StandKind
from schemas.strict_json import strict_loads

STREAM_CHUNK_ROWS = 65_536
TABLE_CHUNK_ROWS = 256
WRITE_BEHIND_ROWS = 65_536
WRITE_BEHIND_BATCHES = 4096
WRITE_BEHIND_SECONDS = 1.0
_TAIL_ROWS = 4096


@dataclass(slots=True)
class _Pending:
    parts: list[Mapping[str, NDArray[np.float64]]] = field(default_factory=list)
    rows: int = 0
    since: float = 0.0


@dataclass(frozen=True, slots=True)
class FileSummary:
    """What the catalogue needs of a run file: the run (rows from the file), flags, results."""

    run: Run
    finalized: bool
    results: str | None


def _axis(decl: ChannelGroup) -> str | None:
    return next((c.name for c in decl.channels if c.order is Order.INCREASING), None)


def chunk_rows(decl: ChannelGroup) -> int:
    """Rows per chunk of the group's datasets (module docstring)."""
    return STREAM_CHUNK_ROWS if decl.aligned and _axis(decl) is not None else TABLE_CHUNK_ROWS


class RunFile:
    """An open run file; not thread-safe (the store serialises the calls)."""

    def __init__(self, path: Path, f: h5py.File) -> None:
        self.path = path
        self._f = f
        self._entry: h5py.Group = f["entry"]
        self._stand = StandKind(self._entry.attrs["stand"])
        self._pending: dict[str, _Pending] = {}
        #: The channels' datasets, kept open while the file is: HDF5 writes a dataset's
        #: cached chunks when its last handle closes, and h5py ignores an error there (a full
        #: disk would lose readings unseen); written at :meth:`flush` and :meth:`close`, a
        #: failure raises.
        self._datasets: dict[tuple[str, str], h5py.Dataset] = {}
        # runs started together would otherwise all write at the same appends
        self._write_behind_s = WRITE_BEHIND_SECONDS * random.uniform(0.5, 1.5)

    @classmethod
    def create(cls, path: Path, run: Run) -> RunFile:
        """A new file for ``run`` (replacing any file at ``path``), every dataset empty."""
        f = h5py.File(path, "w")
        try:
            f.attrs.update(
                NX_class="NXroot",
                default="entry",
                creator="rigserver",
                file_name=path.name,
                file_time=iso(now()),
                HDF5_Version=h5py.version.hdf5_version,
            )
            entry = f.create_group("entry")
            groups = configured_groups(stand_groups(run.stand), run.configuration)
            first_data = next((g.name for g in groups if g.aligned), groups[0].name)
            entry.attrs.update(
                NX_class="NXentry",
                default=first_data,
                operator=run.operator,
                stand=run.stand.value,
                title=run.title,
                state=run.state.value,
                run=run.model_dump_json(),
                configuration=json.dumps(run.configuration, sort_keys=True),
            )
            entry["start_time"] = iso(run.created)
            entry["title"] = run.title
            for decl in groups:
                _create_group(entry, decl)
        except BaseException:
            f.close()
            raise
        return cls(path, f)

    @classmethod
    def open(cls, path: Path, *, writable: bool) -> RunFile:
        f = h5py.File(path, "r+" if writable else "r")
        try:
            return cls(path, f)
        except BaseException:
            f.close()
            raise

    def __enter__(self) -> RunFile:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # --- readings ---------------------------------------------------------------------

    def append(self, group: str, columns: Mapping[str, NDArray[np.float64]], rows: int) -> None:
        """Add ``rows`` rows to ``group``; ``columns`` has every channel, each ``rows`` long."""
        pending = self._pending.setdefault(group, _Pending())
        if not pending.parts:
            pending.since = time.monotonic()
        pending.parts.append(columns)
        pending.rows += rows
        if (
            pending.rows >= WRITE_BEHIND_ROWS
            or len(pending.parts) >= WRITE_BEHIND_BATCHES
            or time.monotonic() - pending.since >= self._write_behind_s
        ):
            self._write(group)

    def write_pending(self) -> None:
        for group in list(self._pending):
            self._write(group)

    def _write(self, group: str) -> None:
        pending = self._pending.pop(group, None)
        if pending is None or not pending.parts:
            return
        start = self._stored_rows(group)
        for name in pending.parts[0]:
            parts = [p[name] for p in pending.parts]
            values = parts[0] if len(parts) == 1 else np.concatenate(parts)
            _extend(self._dataset(group, name), start, np.ascontiguousarray(values, np.float64))

    def _dataset(self, group: str, name: str) -> h5py.Dataset:
        found = self._datasets.get((group, name))
        if found is None:
            found = self._datasets[(group, name)] = self._entry[group][name]
        return found

    def _stored_rows(self, group: str) -> int:
        decl = channel_group(self._stand, group)
        return int(self._dataset(group, decl.channels[0].name).shape[0])

    def rows(self, group: str) -> int:
        pending = self._pending.get(group)
        return self._stored_rows(group) + (pending.rows if pending else 0)

    def read(
        self, group: str, channels: list[str] | None, start: int, stop: int | None
    ) -> dict[str, NDArray[np.float64]]:
        """Rows ``start:stop`` (slice semantics) of the channels, in the order asked."""
        names = channel_names(channel_group(self._stand, group), channels)
        self._write(group)
        lo, hi, _ = slice(start, stop).indices(self._stored_rows(group))
        g = self._entry[group]
        return {n: np.asarray(g[n][lo:hi] if hi > lo else [], dtype=np.float64) for n in names}

    def last_values(self, group: str) -> dict[str, float]:
        """The last non-NaN value of each channel of ``group`` that has one."""
        decl = channel_group(self._stand, group)
        self._write(group)
        g = self._entry[group]
        found: dict[str, float] = {}
        for ch in decl.channels:
            ds = g[ch.name]
            end = int(ds.shape[0])
            while end > 0:
                value = last_finite(np.asarray(ds[max(0, end - _TAIL_ROWS) : end]))
                if value is not None:
                    found[ch.name] = value
                    break
                end -= _TAIL_ROWS
        return found

    # --- results, end, summary --------------------------------------------------------

    def write_results(self, results: CheckedResults, run: Run) -> None:
        """Replace ``/entry/results`` and the run's metadata (its key results)."""
        if "results" in self._entry:
            del self._entry["results"]
        g = self._entry.create_group("results")
        g.attrs["NX_class"] = "NXcollection"
        g["json"] = results.text
        g["json"].attrs["content_type"] = "application/json"
        for path, quantity in results.arrays.items():
            ds = g.create_dataset(path, data=quantity.values)
            ds.attrs.update(units=quantity.unit, long_name=quantity.path)
        for name, sub in _subgroups(g):
            if "NX_class" not in sub.attrs:
                sub.attrs["NX_class"] = "NXcollection"
                sub.attrs["long_name"] = name
        self._set_run(run)

    def write_corrections(self, corrections: list[Correction], run: Run) -> None:
        """Replace ``/entry/corrections`` with ``corrections`` (all of the run's, in order)
        and the run's metadata (its count of corrections)."""
        if "corrections" in self._entry:
            del self._entry["corrections"]
        if corrections:
            _write_corrections(
                self._entry.create_group("corrections", track_order=True), corrections
            )
        self._set_run(run)

    def apply_corrections(self, group: str, corrections: list[Correction]) -> None:
        """Overwrite ``group``'s cells with the corrections of it, in turn, and leave its
        struck rows out (for :func:`corrected_copy` only: a run's own file keeps the values
        as typed)."""
        self.write_pending()
        g = self._entry[group]
        for c in corrections:
            if c.channel is not None and c.now is not None:
                g[c.channel][c.row] = c.now
        struck = sorted({c.row for c in corrections if c.strikes})
        if not struck:
            return
        decl = channel_group(self._stand, group)
        total = self._stored_rows(group)
        for ch in decl.channels:
            ds = g[ch.name]
            out = 0
            for start in range(0, total, STREAM_CHUNK_ROWS):
                stop = min(start + STREAM_CHUNK_ROWS, total)
                values = np.asarray(ds[start:stop])
                keep = [r - start for r in struck if start <= r < stop]
                values = np.delete(values, keep)
                ds[out : out + len(values)] = values
                out += len(values)
            ds.resize((out,))

    def say_corrected(self) -> None:
        """Mark the readings as corrected (``/entry@readings``): a :func:`corrected_copy`."""
        self._entry.attrs["readings"] = "as corrected (the values as typed: corrections/was)"

    def corrections(self) -> list[Correction]:
        """The corrections the file holds, in order (none: an empty list)."""
        if "corrections" not in self._entry:
            return []
        g = self._entry["corrections"]
        text = {k: [str(v) for v in g[k].asstr()[()]] for k in _TEXT_FIELDS}
        numbers = {k: np.asarray(g[k][()]) for k in ("n", "row", "was", "now")}
        found = []
        for i in range(len(numbers["n"])):
            was, now_ = float(numbers["was"][i]), float(numbers["now"][i])
            found.append(
                Correction(
                    n=int(numbers["n"][i]),
                    group=text["group"][i],
                    row=int(numbers["row"][i]),
                    channel=text["channel"][i] or None,
                    was=None if np.isnan(was) else was,
                    now=None if np.isnan(now_) else now_,
                    unit=text["unit"][i],
                    reason=text["reason"][i],
                    by=text["by"][i],
                    at=text["at"][i],
                )
            )
        return found

    def results(self) -> str | None:
        if "results/json" not in self._entry:
            return None
        return str(self._entry["results/json"].asstr()[()])

    def finalize(self, run: Run) -> None:
        """Write the end time and the final run metadata, then the ``finalized`` flag."""
        if run.ended is None:
            raise ValueError(f"run {run.id} has no end time")
        self.write_pending()
        if "end_time" in self._entry:
            del self._entry["end_time"]
        self._entry["end_time"] = iso(run.ended)
        self._set_run(run)
        self._f.flush()
        self._entry.attrs["finalized"] = True

    @property
    def finalized(self) -> bool:
        return bool(self._entry.attrs.get("finalized", False))

    def summary(self) -> FileSummary:
        run = Run.model_validate(strict_loads(self._entry.attrs["run"]))
        rows = {g.name: self.rows(g.name) for g in stand_groups(self._stand)}
        return FileSummary(
            run=run.model_copy(update={"rows": rows}),
            finalized=self.finalized,
            results=self.results(),
        )

    def _set_run(self, run: Run) -> None:
        self._entry.attrs.update(run=run.model_dump_json(), state=run.state.value)

    def flush(self) -> None:
        """Everything buffered written and handed to the OS (no fsync)."""
        self.write_pending()
        self._f.flush()

    def close(self) -> None:
        """Write what is buffered and close; the handle is closed even if writing fails."""
        try:
            if self._f.id.valid and self._f.mode == "r+":
                self.write_pending()
                self._f.flush()  # the datasets' cached chunks: raises where closing would not
        finally:
            self._pending.clear()
            self._datasets.clear()
            self._f.close()


def _create_group(entry: h5py.Group, decl: ChannelGroup) -> None:
    g = entry.create_group(decl.name, track_order=True)
    g.attrs["long_name"] = decl.long_name
    if decl.aligned and decl.signals:  # the default plot: what the stand measures
        signal, *auxiliary = decl.signals
        g.attrs.update(NX_class="NXdata", signal=signal, axes=decl.axis or ".")
        if auxiliary:
            g.attrs["auxiliary_signals"] = auxiliary
        if decl.axis is not None:
            g.attrs[f"{decl.axis}_indices"] = 0
    else:
        g.attrs["NX_class"] = "NXcollection"
    chunk = chunk_rows(decl)
    for ch in decl.channels:
        ds = g.create_dataset(ch.name, shape=(0,), maxshape=(None,), chunks=(chunk,), dtype="f8")
        ds.attrs.update(units=ch.unit, long_name=ch.long_name)


_TEXT_FIELDS = ("group", "channel", "unit", "reason", "by", "at")
_LONG_NAMES = {
    "n": "its place among the run's corrections",
    "group": "channel group",
    "row": "row index in the group, from 0",
    "channel": "channel corrected (empty: the row struck out)",
    "was": "value before the correction",
    "now": "value after the correction",
    "unit": "unit of was and now",
    "reason": "reason given",
    "by": "API key's name",
    "at": "time stored (UTC)",
}


def _write_corrections(g: h5py.Group, corrections: list[Correction]) -> None:
    g.attrs.update(NX_class="NXcollection", long_name="corrections of the readings")
    text = h5py.string_dtype()
    columns: dict[str, Any] = {
        "n": np.array([c.n for c in corrections], dtype=np.int64),
        "group": [c.group for c in corrections],
        "row": np.array([c.row for c in corrections], dtype=np.int64),
        "channel": [c.channel or "" for c in corrections],
        "was": np.array([np.nan if c.was is None else c.was for c in corrections]),
        "now": np.array([np.nan if c.now is None else c.now for c in corrections]),
        "unit": [c.unit for c in corrections],
        "reason": [c.reason for c in corrections],
        "by": [c.by for c in corrections],
        "at": [iso(c.at) for c in corrections],
    }
    for name, values in columns.items():
        ds = g.create_dataset(name, data=values, dtype=text if name in _TEXT_FIELDS else None)
        ds.attrs["long_name"] = _LONG_NAMES[name]
        if name in ("was", "now"):
            ds.attrs["units"] = "see unit"


def _subgroups(g: h5py.Group) -> list[tuple[str, h5py.Group]]:
    found: list[tuple[str, h5py.Group]] = []

    def visit(name: str, obj: Any) -> None:
        if isinstance(obj, h5py.Group):
            found.append((name, obj))

    g.visititems(visit)
    return found


def _extend(ds: h5py.Dataset, start: int, values: NDArray[np.float64]) -> None:
    """Grow ``ds`` to ``start + len(values)`` and write ``values`` there (low-level: fast)."""
    n = len(values)
    ds.id.set_extent((start + n,))
    if n:
        space = ds.id.get_space()
        space.select_hyperslab((start,), (n,))
        ds.id.write(h5s.create_simple((n,)), space, values)


def fsync_path(path: Path) -> None:
    """fsync a file or a directory (directories: so that a rename or create is durable)."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


@contextmanager
def replacing(path: Path) -> Iterator[Path]:
    """A temporary file beside ``path`` to write in the block; then fsynced and renamed over
    ``path``, the directory fsynced (durable), or removed if the block fails."""
    tmp = path.with_name(path.name + ".tmp")
    try:
        yield tmp
        fsync_path(tmp)
        os.replace(tmp, path)
        fsync_path(path.parent)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_file(
    path: Path,
    run: Run,
    batches: Iterable[tuple[str, Mapping[str, NDArray[np.float64]], int]],
    results: CheckedResults | None,
    *,
    final: bool,
    corrections: list[Correction] | None = None,
) -> None:
    """Write a whole run file atomically: to a temp file, fsync, rename over ``path``.

    ``batches`` are ``(group, columns with every channel, rows)`` in the order stored;
    ``corrections`` the run's corrections of them.
    """
    with replacing(path) as tmp, RunFile.create(tmp, run) as rf:
        for group, columns, rows in batches:
            rf.append(group, columns, rows)
        if corrections:
            rf.write_corrections(corrections, run)
        if results is not None:
            rf.write_results(results, run)
        if final:
            rf.finalize(run)


def corrected_copy(source: Path, target: Path) -> None:
    """Write ``target``: the run file ``source`` with its readings as corrected (each of
    its corrections applied in turn, the struck rows left out, ``/entry@readings`` saying
    so); its ``/entry/corrections`` stays, with every value as typed."""
    shutil.copyfile(source, target)
    with RunFile.open(target, writable=True) as rf:
        corrections = rf.corrections()
        for group in sorted({c.group for c in corrections}):
            rf.apply_corrections(group, [c for c in corrections if c.group == group])
        rf.say_corrected()


def read_summary(path: Path) -> FileSummary:
    with RunFile.open(path, writable=False) as rf:
        return rf.summary()
