"""The binary form of a batch: a NumPy ``.npz`` archive, one 1-D array per channel.

A stored (uncompressed) member, as ``numpy.savez`` writes it, is read in place: its array
is a view of the request body (copied only if misaligned), found through the zip
directory (:mod:`zipfile`) and the ``.npy`` header (:mod:`numpy.lib.format`). Reading it
through ``numpy.load`` would copy every value out of the archive and checksum it, which
costs more than storing it. Compressed members are read by NumPy.
"""

from __future__ import annotations

import io
import struct
import zipfile
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rigserver.api.problems import ApiProblem
from schemas.channels import Violation


def parse_npz(body: bytes, max_bytes: int) -> dict[str, NDArray[Any]]:
    """The archive's arrays by channel name: 1-D and real-valued, at most ``max_bytes``
    once unpacked; :class:`ApiProblem` 413 or 422 otherwise."""
    try:
        with zipfile.ZipFile(io.BytesIO(body)) as archive:
            members = archive.infolist()
            unpacked = sum(info.file_size for info in members)
            if unpacked > max_bytes:
                raise ApiProblem(
                    413,
                    "Binary batch too large",
                    f"the archive unpacks to {unpacked} bytes; the limit is {max_bytes}",
                )
            for info in members:
                if not info.filename.endswith(".npy"):
                    name = info.filename[:40]
                    raise ApiProblem(
                        422,
                        "Invalid binary batch",
                        f"member {name!r} is not a channel: a .npy file per channel",
                        [Violation(field=f"columns.{name}", message="a 1-D array of numbers")],
                    )
            arrays = {
                info.filename.removesuffix(".npy"): (
                    _stored_array(body, info)
                    if info.compress_type == zipfile.ZIP_STORED
                    else np.lib.format.read_array(archive.open(info), allow_pickle=False)
                )
                for info in members
            }
    except (ValueError, OSError, zipfile.BadZipFile, EOFError) as exc:
        raise ApiProblem(
            422, "Unreadable binary batch", f"the body is not a numpy .npz archive: {exc}"
        ) from None
    for name, values in arrays.items():
        if values.ndim != 1 or values.dtype.kind not in "biuf":
            raise ApiProblem(
                422,
                "Invalid binary batch",
                f"channel {name[:40]!r} must be a 1-D array of real numbers, not a "
                f"{values.ndim}-D array of {values.dtype}",
                [Violation(field=f"columns.{name[:40]}", message="a 1-D array of numbers")],
            )
    return arrays


#: A zip member's local header: signature, 22 bytes, then the lengths of name and extra.
_LOCAL_HEADER = struct.Struct("<4s22xHH")
#: Room for a .npy file's magic, version, header length and header (NumPy's largest).
_NPY_HEAD = 12 + 10_000


def _stored_array(body: bytes, info: zipfile.ZipInfo) -> NDArray[Any]:
    """The array of a stored ``.npy`` member of the archive ``body``, as a view of it."""
    signature, name, extra = _LOCAL_HEADER.unpack_from(body, info.header_offset)
    if signature != b"PK\x03\x04":
        raise zipfile.BadZipFile(f"member {info.filename!r} has no local header")
    start = info.header_offset + _LOCAL_HEADER.size + name + extra
    end = start + info.file_size
    if end > len(body):
        raise zipfile.BadZipFile(f"member {info.filename!r} is cut short")
    head = io.BytesIO(body[start : min(end, start + _NPY_HEAD)])
    version = np.lib.format.read_magic(head)
    if version == (1, 0):
        shape, fortran_order, dtype = np.lib.format.read_array_header_1_0(head)
    elif version == (2, 0):
        shape, fortran_order, dtype = np.lib.format.read_array_header_2_0(head)
    else:
        raise ValueError(f"member {info.filename!r} is a .npy file of version {version}")
    if dtype.hasobject:
        raise ValueError(f"member {info.filename!r} holds Python objects")
    count = int(np.prod(shape, dtype=np.int64))
    at = start + head.tell()
    if at + count * dtype.itemsize > end:
        raise ValueError(f"member {info.filename!r} holds fewer values than its shape")
    values = np.frombuffer(body, dtype=dtype, count=count, offset=at)
    if not values.flags.aligned:  # a copy (a new bytes object's values are aligned)
        values = np.frombuffer(body[at : at + count * dtype.itemsize], dtype=dtype)
    if len(shape) == 1:
        return values
    return values.reshape(shape, order="F" if fortran_order else "C")
