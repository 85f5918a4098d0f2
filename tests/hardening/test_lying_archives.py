"""Binary batches whose headers lie (issue 14, item 2; duplicate members of item 8).

The archives are packed by hand (struct), header by header, so that each field can say
what numpy and zipfile would never write: every lie is answered 422 naming the member
and the field, nothing of the batch is stored, and the archive's own directory is never
read as readings."""

from __future__ import annotations

import struct
import zlib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient

from rigserver.api.npz import parse_npz
from rigserver.api.problems import ApiProblem
from schemas.readings import NPZ_MEDIA_TYPE
from tests.api.conftest import READER, WRITER, auth
from tests.hardening.conftest import API, hdf5_app, is_problem, open_run

NPZ = {**auth(WRITER), "content-type": NPZ_MEDIA_TYPE}

# The zip format (APPNOTE.TXT 4.3.7, 4.3.12, 4.3.16): local header, central directory
# entry, end of central directory record.
LOCAL = struct.Struct("<4sHHHHHIIIHH")
CENTRAL = struct.Struct("<4sHHHHHHIIIHHHHHII")
END = struct.Struct("<4sHHHHIIH")


def npy(
    descr: str, shape: str, data: bytes, *, version: int = 1, length: int = -1, order: str = "False"
) -> bytes:
    """A .npy file (NEP 1): magic, version, header length, the header dict, the data.
    ``length`` (if given) replaces the header length field."""
    header = f"{{'descr': {descr}, 'fortran_order': {order}, 'shape': {shape}, }}"
    size = struct.Struct("<H" if version == 1 else "<I")
    pad = 64 - (6 + 2 + size.size + len(header) + 1) % 64
    text = (header + " " * pad + "\n").encode("latin1")
    count = len(text) if length < 0 else length
    return b"\x93NUMPY" + bytes([version, 0]) + size.pack(count) + text + data


@dataclass(frozen=True)
class Member:
    """One zip member; the fields other than ``name`` and ``data`` replace what the
    central directory says (None: the truth)."""

    name: str
    data: bytes
    deflate: bool = False
    flags: int = 0
    method: int | None = None
    compress_size: int | None = None
    file_size: int | None = None
    header_offset: int | None = None


def archive(*members: Member) -> bytes:
    """The members' local headers and data, then the central directory saying what they
    ask it to."""
    body, directory = b"", b""
    for m in members:
        name = m.name.encode()
        packed = zlib.compress(m.data)[2:-4] if m.deflate else m.data  # raw deflate
        method = m.method if m.method is not None else (8 if m.deflate else 0)
        crc = zlib.crc32(m.data)
        offset = len(body)
        body += LOCAL.pack(
            b"PK\x03\x04", 20, m.flags, method, 0, 33, crc, len(packed), len(m.data),
            len(name), 0,
        ) + name + packed  # fmt: skip
        directory += CENTRAL.pack(
            b"PK\x01\x02", 20, 20, m.flags, method, 0, 33, crc,
            len(packed) if m.compress_size is None else m.compress_size,
            len(m.data) if m.file_size is None else m.file_size,
            len(name), 0, 0, 0, 0, 0,
            offset if m.header_offset is None else m.header_offset,
        ) + name  # fmt: skip
    end = END.pack(b"PK\x05\x06", 0, 0, len(members), len(members), len(directory), len(body), 0)
    return body + directory + end


F8 = np.arange(3.0).tobytes()  # three little-endian doubles: 0, 1, 2
GOOD = npy("'<f8'", "(3,)", F8)


def test_the_hand_packed_archive_is_read_as_numpy_would() -> None:
    """The packer itself is right: an honest archive of it is read back (stored and
    deflated), so each refusal below is the lie's doing."""
    fortran = npy("'<f8'", "(3,)", F8, order="True")  # the same bytes for a 1-D array
    for member in (GOOD, fortran):
        for deflate in (False, True):
            arrays = parse_npz(archive(Member("time.npy", member, deflate=deflate)), 1 << 20)
            np.testing.assert_array_equal(arrays["time"], [0.0, 1.0, 2.0])


#: .npy headers that lie; each is tried stored and deflated.
NPY_LIES = {
    # a negative count read np.frombuffer(count=-1) to the end: the central directory
    "negative shape": (npy("'<f8'", "(-1,)", F8), "shape"),
    "negative shape, whole values": (npy("'<f8'", "(-2,)", F8 + b"\0" * 6), "shape"),
    "huge shape": (npy("'<f8'", f"({2**62},)", F8), "shape"),
    "shape beyond int64": (npy("'<f8'", f"({2**64 + 3},)", F8), "shape"),
    "overflowing product": (npy("'<f8'", f"({2**32}, {2**32})", F8), "shape"),
    "wrapping product": (npy("'<f8'", f"(3, {(2**64 + 3) // 3})", F8), "shape"),
    "one value more": (npy("'<f8'", "(4,)", F8), "shape"),
    "one value less": (npy("'<f8'", "(2,)", F8), "shape"),
    "scalar": (npy("'<f8'", "()", F8[:8]), "shape"),
    "2-D": (npy("'<f8'", "(3, 1)", F8), "shape"),
    "objects": (npy("'|O'", "(3,)", F8), "descr"),
    "text": (npy("'<U1'", "(6,)", F8), "descr"),
    "records": (npy("[('a', '<f8')]", "(3,)", F8), "descr"),
    "sub-arrays": (npy("('<f8', (3,))", "(1,)", F8), "descr"),
    "not a dtype": (npy("'<q17'", "(3,)", F8), "header"),
    "fortran_order not a bool": (npy("'<f8'", "(3,)", F8, order="'yes'"), "header"),
    "a header of other keys": (npy("'<f8'", "(3,)", F8, order="False, 'x': 1"), "header"),
    "header longer than the member": (npy("'<f8'", "(3,)", F8, length=60_000), "header"),
    "header length beyond the member (v2)": (
        npy("'<f8'", "(3,)", F8, version=2, length=2**31),
        "header",
    ),
    "version 3": (npy("'<f8'", "(3,)", F8, version=3), "version"),
}

#: Zip headers that lie (the .npy inside is honest).
ZIP_LIES = {
    # the stored data "runs" into the central directory
    "stored sizes past the data": (
        archive(Member("time.npy", GOOD, compress_size=len(GOOD) + 46, file_size=len(GOOD) + 46)),
        "compress_size",
    ),
    "stored sizes that differ": (
        archive(Member("time.npy", GOOD, file_size=len(GOOD) - 8)),
        "compress_size",
    ),
    "deflated size past the data": (
        archive(Member("time.npy", GOOD, deflate=True, compress_size=10_000)),
        "compress_size",
    ),
    "deflated file_size over what it inflates to": (
        archive(Member("time.npy", GOOD, deflate=True, file_size=len(GOOD) + 8)),
        "file_size",
    ),
    "header offset past the members": (
        archive(Member("time.npy", GOOD, header_offset=len(GOOD) + 38)),
        "header_offset",
    ),
    "header offset at no local header": (
        archive(Member("time.npy", GOOD, header_offset=8)),
        "header_offset",
    ),
    "two entries, one member": (
        archive(Member("load.npy", GOOD), Member("time.npy", GOOD, header_offset=0)),
        "header_offset",
    ),
    "encrypted": (archive(Member("time.npy", GOOD, flags=1)), "flag_bits"),
    "unknown method": (archive(Member("time.npy", GOOD, method=99)), "compress_type"),
    "bzip2": (archive(Member("time.npy", GOOD, method=12)), "compress_type"),
}


def _cases() -> Iterator[object]:
    for label, (member, field) in NPY_LIES.items():
        for deflate in (False, True):
            body = archive(Member("time.npy", member, deflate=deflate))
            kind = "deflated" if deflate else "stored"
            yield pytest.param(body, field, id=f"{label}, {kind}")
    for label, (body, field) in ZIP_LIES.items():
        yield pytest.param(body, field, id=label)


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    data = tmp_path_factory.mktemp("lies") / "data"
    with TestClient(hdf5_app(Path(data)), raise_server_exceptions=False) as c:
        yield c


def _refused(client: TestClient, body: bytes) -> dict[str, object]:
    run_id = open_run(client)
    r = client.post(f"{API}/runs/{run_id}/readings?seq=0&group=friction", content=body, headers=NPZ)
    assert r.status_code == 422, r.text
    assert is_problem(r)
    stored = client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()
    assert stored["batches"] == 0
    problem: dict[str, object] = r.json()
    return problem


@pytest.mark.parametrize(("body", "field"), list(_cases()))
def test_a_lying_header_is_422_naming_the_member_and_field(
    client: TestClient, body: bytes, field: str
) -> None:
    problem = _refused(client, body)
    assert problem["title"] == "Invalid binary batch"
    assert "'time.npy'" in str(problem["detail"]) and field in str(problem["detail"])
    assert problem["errors"] == [
        {"field": "columns.time", "value": field, "message": str(problem["errors"][0]["message"])}  # type: ignore[index]
    ]


@pytest.mark.parametrize(
    "names",
    [("time.npy", "time.npy"), ("time.npy", "load.npy", "time.npy"), ("time.npy", "time.npy\0x")],
    ids=["twice", "apart", "after a NUL"],
)
def test_duplicate_members_are_422(client: TestClient, names: tuple[str, ...]) -> None:
    """Two members of one channel: which one would be stored? Neither (zipfile cuts a
    name at a NUL, so the third archive names ``time.npy`` twice too)."""
    problem = _refused(client, archive(*(Member(name, GOOD) for name in names)))
    assert "twice" in str(problem["detail"]) and "'time.npy'" in str(problem["detail"])


def test_the_central_directory_is_never_read_as_readings() -> None:
    """The probe of the issue: shape (-1,) over a stored member whose doubles end where
    the central directory begins. Before, every byte to the end of the body was stored."""
    body = archive(Member("time.npy", npy("'<u1'", "(-1,)", b"")))
    with pytest.raises(ApiProblem) as refused:
        parse_npz(body, 1 << 20)
    assert refused.value.problem.status == 422
    assert "shape" in refused.value.problem.detail
