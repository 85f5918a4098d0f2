"""The binary form of a batch: a NumPy ``.npz`` archive, one 1-D array per channel.

A stored (uncompressed) member, as ``numpy.savez`` writes it, is read in place: its array
is a view of the request body, found through the zip directory (:mod:`zipfile`) and the
``.npy`` header (:mod:`numpy.lib.format`), once its CRC-32 is checked against the bytes
there (ISA-L's ``crc32`` from :mod:`isal`, over the member: 0.4 ms for 8 MB here against
2 ms for zlib's, and far cheaper than ``numpy.load``'s copy of every value; it lets other
threads run meanwhile: the event loop goes on receiving the next body). ``numpy.savez``
puts the values off 8-byte boundaries; they stay there (NumPy reads them a little slower),
and the store copies a large batch once, into the aligned memory its payload file is
written from (:mod:`rigserver.storage.embedded.payload_files`). A deflated member is
inflated by :mod:`zipfile` (which checks its CRC), at most its declared size. A member whose bytes
do not match its CRC-32 was damaged on its way: it is refused, never stored.

Nothing a header says is believed until it is checked against the bytes there are: the
declared sizes (at most ``max_bytes`` unpacked in all, a zip bomb's defence), where each
member lies (its local header and data inside the archive, before the central directory,
overlapping no other member), and the ``.npy`` header (version, a real-number dtype, a
1-D shape whose values fill the member exactly). A boolean array is no channel of numbers
(``True`` is not a reading of 1.0). A lie is refused with 422 naming the
member and the field; two members of one name are refused too.
"""

from __future__ import annotations

import io
import itertools
import struct
import zipfile
from typing import Any, NoReturn

import numpy as np
from isal import isal_zlib
from numpy.typing import NDArray

from rigserver.api.problems import ApiProblem
from schemas.channels import Violation

#: A zip member's local header: signature, 22 bytes, then the lengths of name and extra.
_LOCAL_HEADER = struct.Struct("<4s22xHH")
#: Room for a .npy file's magic, version, header length and header (NumPy's largest).
_NPY_HEAD = 12 + 10_000
#: Compression methods read: stored, and deflated (numpy.savez_compressed).
_METHODS = (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED)
#: dtype kinds of real numbers taken as readings: signed, unsigned, floating (no booleans).
_REAL_KINDS = "iuf"


def parse_npz(body: bytes, max_bytes: int) -> dict[str, NDArray[Any]]:
    """The archive's arrays by channel name: 1-D and real-valued, at most ``max_bytes``
    once unpacked; :class:`ApiProblem` 413 or 422 otherwise (see the module docstring)."""
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
            starts = _member_starts(body, members, archive.start_dir)
            return {
                info.filename.removesuffix(".npy"): _member_array(body, archive, info, start)
                for info, start in zip(members, starts, strict=True)
            }
    except (ValueError, OSError, zipfile.BadZipFile, EOFError, struct.error) as exc:
        raise ApiProblem(
            422, "Unreadable binary batch", f"the body is not a numpy .npz archive: {exc}"
        ) from None


def _refuse(info: zipfile.ZipInfo, field: str, problem: str) -> NoReturn:
    """422 for the member ``info`` whose header ``field`` lies (or is not taken)."""
    name = info.filename[:40]
    raise ApiProblem(
        422,
        "Invalid binary batch",
        f"member {name!r}: {field} {problem}",
        [
            Violation(
                field=f"columns.{name.removesuffix('.npy')}",
                value=field,
                message=f"{field} {problem}",
            )
        ],
    )


def _member_starts(body: bytes, members: list[zipfile.ZipInfo], directory: int) -> list[int]:
    """Where each member's data starts in ``body``, once its zip headers are checked: a
    ``.npy`` name of its own, a method read, no encryption, its local header and data
    inside the archive before the central directory (at ``directory``), no overlap."""
    seen: set[str] = set()
    starts: list[int] = []
    spans: list[tuple[int, int, zipfile.ZipInfo]] = []
    for info in members:
        if not info.filename.endswith(".npy"):
            _refuse(info, "name", "is not a channel: a .npy file per channel")
        if info.filename in seen:
            _refuse(info, "name", "is in the archive twice: one member per channel")
        seen.add(info.filename)
        if info.flag_bits & 0x1:
            _refuse(info, "flag_bits", "say the member is encrypted")
        if info.compress_type not in _METHODS:
            _refuse(info, "compress_type", f"{info.compress_type} is neither stored nor deflated")
        if info.compress_type == zipfile.ZIP_STORED and info.compress_size != info.file_size:
            _refuse(
                info,
                "compress_size",
                f"{info.compress_size} differs from file_size {info.file_size} of a stored member",
            )
        at = info.header_offset
        if not 0 <= at <= directory - _LOCAL_HEADER.size:
            _refuse(info, "header_offset", f"{at} is outside the archive's members")
        signature, name, extra = _LOCAL_HEADER.unpack_from(body, at)
        if signature != b"PK\x03\x04":
            _refuse(info, "header_offset", f"{at} holds no local header")
        start = at + _LOCAL_HEADER.size + name + extra
        end = start + info.compress_size
        if end > directory:
            _refuse(
                info,
                "compress_size",
                f"{info.compress_size} from byte {start} runs past the members' end "
                f"(byte {directory})",
            )
        starts.append(start)
        spans.append((at, end, info))
    spans.sort(key=lambda span: span[0])
    for (_, end, _), (at, _, info) in itertools.pairwise(spans):
        if at < end:
            _refuse(info, "header_offset", f"{at} lies inside another member (which ends at {end})")
    return starts


def _member_array(
    body: bytes, archive: zipfile.ZipFile, info: zipfile.ZipInfo, start: int
) -> NDArray[Any]:
    """The array of the ``.npy`` member ``info`` whose data starts at ``start`` in
    ``body``: a read-only view of ``body`` if stored, else of the member inflated."""
    size = info.file_size
    if info.compress_type == zipfile.ZIP_STORED:
        crc = isal_zlib.crc32(memoryview(body)[start : start + size])
        if crc != info.CRC:
            _refuse(
                info,
                "CRC-32",
                f"{info.CRC:08x} does not match the member's bytes ({crc:08x}): the "
                "archive was damaged on its way; send it again",
            )
    else:
        try:
            with archive.open(info) as member:
                body, start = member.read(size), 0
        except zipfile.BadZipFile as exc:  # a bad CRC-32, or a damaged local header
            _refuse(info, "CRC-32" if "CRC" in str(exc) else "data", f"is damaged: {exc}")
        if len(body) != size:
            _refuse(info, "file_size", f"{size} is more than the member inflates to ({len(body)})")
    dtype, length, at = _npy_header(info, body[start : start + min(size, _NPY_HEAD)])
    return np.frombuffer(body, dtype=dtype, count=length, offset=start + at)


def _npy_header(info: zipfile.ZipInfo, head: bytes) -> tuple[np.dtype[Any], int, int]:
    """The dtype and length of the 1-D array of a ``.npy`` member, and where its values
    start, from the member's first bytes ``head``: each field checked against the member's
    size (``info.file_size``)."""
    fp = io.BytesIO(head)
    try:
        version = np.lib.format.read_magic(fp)
        if version == (1, 0):
            shape, _, dtype = np.lib.format.read_array_header_1_0(fp)
        elif version == (2, 0):
            shape, _, dtype = np.lib.format.read_array_header_2_0(fp)
        else:
            _refuse(info, "version", f"{version} of the .npy format is not read (1.0 or 2.0)")
    except (ValueError, TypeError, OverflowError) as exc:
        _refuse(info, "header", f"is not a .npy header: {str(exc)[:200]}")
    if dtype.hasobject or dtype.kind not in _REAL_KINDS or dtype.shape:
        _refuse(info, "descr", f"{dtype.str!r} is not a real number type")
    if len(shape) != 1:
        _refuse(info, "shape", f"{shape} is not 1-D: a channel is a 1-D array of numbers")
    (length,) = shape
    at = fp.tell()
    room = info.file_size - at
    if length < 0 or length * dtype.itemsize != room:
        _refuse(
            info,
            "shape",
            f"({length},) of {dtype.str} takes {length * dtype.itemsize} bytes; the member "
            f"holds {room} after its header",
        )
    return dtype, int(length), at
