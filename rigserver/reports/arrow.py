"""A channel group's readings as an Apache Arrow IPC stream (``format=arrow``).

Why Arrow: the columnar form that pandas, polars and R read without parsing or copying a
number, with no checksum to compute (an ``.npz`` archive is a zip, CRC-32 over every byte).
One float64 column per channel, in the declared order; each field carries the channel's
``unit`` and ``long_name`` as metadata, the schema the group's name. A group of single
measurements (masses, zero readings) is one row of the latest value of each channel posted.

An aligned group is one record batch of the rows the run holds when asked (those arriving
while it is sent are left to the next ask). Its message is laid out before any value is
read, so the stream's length is known (:attr:`ArrowStream.size`, the answer's
``Content-Length``) and a reader takes it into one buffer, each column one piece of memory
that pandas uses as it is. The columns' values then follow one after another as the store
reads them, :data:`CHUNK_ROWS` rows at a time: the service holds one slice of one channel
whatever the run's size, and never copies a value into the stream.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
import pyarrow as pa

from rigserver.analysis import Readings
from schemas.channels import ChannelGroup

CHUNK_ROWS = 1 << 20
"""Rows of one channel read from the store and sent at a time (8 MiB)."""

Piece = bytes | memoryview


@dataclass(frozen=True, slots=True)
class ArrowStream:
    """An Arrow IPC stream of ``size`` bytes, given piece by piece by ``pieces``."""

    size: int
    pieces: Iterator[Piece]


class _Layout:
    """A write-only sink that keeps the stream's framing and metadata as bytes and, where a
    column's values would go, the column's index (found by the address of its buffer)."""

    def __init__(self, columns: list[np.ndarray]) -> None:
        self._index = {c.ctypes.data: i for i, c in enumerate(columns)}
        self.pieces: list[bytes | int] = []
        self.closed = False

    def write(self, data: bytes | pa.Buffer) -> int:
        if isinstance(data, bytes):
            self.pieces.append(data)
        else:
            self.pieces.append(self._index[data.address])
        return len(data)

    def flush(self) -> None:
        pass

    def close(self) -> None:
        self.closed = True


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


def _layout(schema: pa.Schema, rows: int) -> list[bytes | int]:
    """The stream of one batch of ``rows`` rows, each column's values as its index. The
    columns laid out are never read (nor their memory touched): only their buffers' sizes
    and addresses reach the sink."""
    columns = [np.empty(rows) for _ in schema.names]
    sink = _Layout(columns)
    with pa.ipc.new_stream(sink, schema) as writer:
        writer.write_batch(pa.record_batch(columns, schema=schema))
    return sink.pieces


def _values(readings: Readings, group: str, name: str, rows: int) -> Iterator[memoryview]:
    """The first ``rows`` values of one channel as little-endian float64 bytes, a slice of
    the store at a time."""
    left = rows
    for chunk in readings.iter_chunks(group, [name], rows=CHUNK_ROWS):
        if left <= 0:
            break
        values = np.ascontiguousarray(chunk[name][:left], dtype="<f8")
        left -= len(values)
        yield values.data.cast("B")
    if left > 0:  # the stated length cannot be kept: the answer breaks off rather than lie
        raise RuntimeError(f"{group}.{name}: {left} of {rows} rows were not there to send")


def group_arrow(readings: Readings, group: ChannelGroup) -> ArrowStream:
    """The Arrow IPC stream of one channel group: the rows the run holds now in one record
    batch (a group of single measurements: one row of the latest values)."""
    if not group.aligned:
        latest = readings.measurements()
        names = [c.name for c in group.channels if c.name in latest]
        schema = _schema(group, names)
        sink = pa.BufferOutputStream()
        with pa.ipc.new_stream(sink, schema) as writer:
            if names:
                writer.write_batch(
                    pa.record_batch([np.array([latest[n]]) for n in names], schema=schema)
                )
        whole = sink.getvalue().to_pybytes()
        return ArrowStream(len(whole), iter([whole]))
    names = [c.name for c in group.channels]
    schema = _schema(group, names)
    rows = readings.rows(group.name)
    layout = _layout(schema, rows)
    size = sum(len(p) if isinstance(p, bytes) else rows * 8 for p in layout)

    def pieces() -> Iterator[Piece]:
        for piece in layout:
            if isinstance(piece, bytes):
                yield piece
            else:
                yield from _values(readings, group.name, names[piece], rows)

    return ArrowStream(size, pieces())
