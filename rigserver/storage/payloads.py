"""A batch's readings as bytes: the form in which the embedded journal's payload files
(:mod:`~rigserver.storage.embedded.payload_files`) and the cluster's batches table
(:mod:`~rigserver.storage.cluster.postgres`) hold them, laid out by :func:`encode`.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

_HEADER = struct.Struct("<I")
_COLUMN = struct.Struct("<HQ")


@dataclass(frozen=True, slots=True)
class Payload:
    """A batch as stored: ``size`` bytes in ``parts``. A large batch bound for a direct write
    is one part in aligned memory, and ``padded`` is that memory with zeros after the batch
    up to a whole block (:func:`~rigserver.storage.embedded.payload_files.aligned`)."""

    parts: Sequence[bytes | memoryview]
    size: int
    padded: memoryview | None = None


def encode(columns: dict[str, NDArray[np.float64]]) -> Payload:
    """Channel count, then (name length, row count, name) per channel, then the values
    (raw float64, native order: little-endian on every platform rigserver runs on)."""
    head = [_HEADER.pack(len(columns))]
    for name, values in columns.items():
        raw = name.encode()
        head.append(_COLUMN.pack(len(raw), len(values)))
        head.append(raw)
    parts: list[bytes | memoryview] = [b"".join(head), *(v.data for v in columns.values())]
    return Payload(parts, sum(memoryview(p).nbytes for p in parts))


def decode(data: bytes) -> dict[str, NDArray[np.float64]]:
    """The columns :func:`encode` laid out, as read-only views of ``data``."""
    out: dict[str, NDArray[np.float64]] = {}
    for name, rows, at in layout(data):
        out[name] = np.frombuffer(data, dtype="<f8", count=rows, offset=at)
    return out


def layout(head: bytes) -> list[tuple[str, int, int]]:
    """(name, rows, where its values start) of each column, from the first bytes of an
    encoded batch (``struct.error`` if ``head`` is shorter than the header)."""
    (count,) = _HEADER.unpack_from(head, 0)
    at = _HEADER.size
    names: list[tuple[str, int]] = []
    for _ in range(count):
        size, rows = _COLUMN.unpack_from(head, at)
        at += _COLUMN.size
        names.append((head[at : at + size].decode(), rows))
        at += size
    out = []
    for name, rows in names:
        out.append((name, rows, at))
        at += 8 * rows
    return out
