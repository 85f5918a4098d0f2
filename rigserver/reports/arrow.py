"""A channel group's readings as an Apache Arrow IPC stream (``format=arrow``).

Why Arrow: the columnar form that pandas, polars and R read without parsing or copying a
number, with no checksum to compute (an ``.npz`` archive is a zip, CRC-32 over every byte);
it streams in record batches, so the server holds one batch at a time whatever the run's
size. One float64 column per channel, in the declared order; each field carries the
channel's ``unit`` and ``long_name`` as metadata, the schema the group's name. A group of
single measurements (masses, zero readings) is one row of the latest value of each channel
posted.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pyarrow as pa

from rigserver.analysis import Readings
from schemas.channels import ChannelGroup

BATCH_ROWS = 1 << 20
"""Rows of one record batch: 8 MiB a channel."""


class _Pieces:
    """A write-only sink that hands over what was written since it was last asked."""

    def __init__(self) -> None:
        self._pieces: list[bytes] = []
        self.closed = False

    def write(self, data: bytes | memoryview) -> int:
        self._pieces.append(bytes(data))
        return len(data)

    def flush(self) -> None:
        pass

    def close(self) -> None:
        self.closed = True

    def take(self) -> list[bytes]:
        out, self._pieces = self._pieces, []
        return out


def _schema(group: ChannelGroup, names: list[str]) -> pa.Schema:
    channels = {c.name: c for c in group.channels}
    return pa.schema(
        [
            pa.field(
                name,
                pa.float64(),
                metadata={"unit": channels[name].unit, "long_name": channels[name].long_name},
            )
            for name in names
        ],
        metadata={"group": group.name},
    )


def group_arrow(readings: Readings, group: ChannelGroup) -> Iterator[bytes]:
    """The Arrow IPC stream of one channel group, a record batch of at most
    :data:`BATCH_ROWS` rows at a time."""
    sink = _Pieces()
    if not group.aligned:
        latest = readings.measurements()
        names = [c.name for c in group.channels if c.name in latest]
        schema = _schema(group, names)
        with pa.ipc.new_stream(sink, schema) as writer:
            if names:
                writer.write_batch(
                    pa.record_batch([np.array([latest[n]]) for n in names], schema=schema)
                )
        yield from sink.take()
        return
    names = [c.name for c in group.channels]
    schema = _schema(group, names)
    with pa.ipc.new_stream(sink, schema) as writer:
        yield from sink.take()
        for chunk in readings.iter_chunks(group.name, names, rows=BATCH_ROWS):
            writer.write_batch(pa.record_batch([chunk[n] for n in names], schema=schema))
            yield from sink.take()
    yield from sink.take()
