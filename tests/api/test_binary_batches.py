"""The binary form: whatever ``numpy.savez`` and friends write is read back exactly; an
archive that lies about its members is refused (422), never a 500."""

from __future__ import annotations

import io
import json
import zipfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fastapi.testclient import TestClient

from rigserver.api.npz import parse_npz
from rigserver.storage._checks import prepare
from schemas.readings import NPZ_MEDIA_TYPE
from tests.api.conftest import READER, WRITER, auth
from tests.hardening.conftest import API, friction, hdf5_app, is_problem, json_batch, open_run

NPZ = {**auth(WRITER), "content-type": NPZ_MEDIA_TYPE}


@pytest.fixture
def hdf5_client(tmp_path: Path) -> Iterator[TestClient]:
    with TestClient(hdf5_app(tmp_path / "data"), raise_server_exceptions=False) as c:
        yield c


def _archive(columns: dict[str, Any], write: Callable[[io.BytesIO, Any], None]) -> bytes:
    """An archive of one .npy member per channel, each written by ``write``."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as z:
        for name, values in columns.items():
            member = io.BytesIO()
            write(member, values)
            z.writestr(f"{name}.npy", member.getvalue())
    return buffer.getvalue()


def _savez(columns: dict[str, Any]) -> bytes:
    buffer = io.BytesIO()
    np.savez(buffer, **columns)
    return buffer.getvalue()


def _savez_compressed(columns: dict[str, Any]) -> bytes:
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **columns)
    return buffer.getvalue()


def _version_2(columns: dict[str, Any]) -> bytes:
    return _archive(columns, lambda f, v: np.lib.format.write_array(f, v, version=(2, 0)))


def _big_endian(columns: dict[str, Any]) -> bytes:
    return _savez({name: values.astype(">f8") for name, values in columns.items()})


def _float32_and_ints(columns: dict[str, Any]) -> bytes:
    load, speed = columns["load"].astype(np.int32), columns["speed"].astype(np.float32)
    return _savez({**columns, "load": load, "speed": speed})


@pytest.mark.parametrize(
    "make", [_savez, _savez_compressed, _version_2, _big_endian, _float32_and_ints]
)
def test_archives_are_read_back_exactly(
    hdf5_client: TestClient, make: Callable[[dict[str, Any]], bytes]
) -> None:
    run_id = open_run(hdf5_client)
    columns = friction(0, 777)  # 777 rows: member data at odd offsets in the archive
    r = hdf5_client.post(
        f"{API}/runs/{run_id}/readings?seq=0&group=friction", content=make(columns), headers=NPZ
    )
    assert r.status_code == 201, r.text
    back = hdf5_client.get(
        f"{API}/runs/{run_id}/readings?group=friction", headers=auth(READER)
    ).json()["friction"]["columns"]
    for name, values in columns.items():
        np.testing.assert_array_equal(back[name], values, err_msg=name)


@pytest.mark.parametrize(
    ("content_type", "query", "body"),
    [
        ("Application/JSON; charset=UTF-8", "", None),
        (NPZ_MEDIA_TYPE.upper(), "?seq=0&group=friction", _savez(friction(0, 3))),
    ],
    ids=["json", "npz"],
)
def test_the_media_type_is_read_in_any_case_and_without_its_parameters(
    hdf5_client: TestClient, content_type: str, query: str, body: bytes | None
) -> None:
    """RFC 9110, 8.3.1: the type and subtype of a media type are case-insensitive."""
    run_id = open_run(hdf5_client)
    content = body if body is not None else json.dumps(json_batch(0, 0, 3)).encode()
    r = hdf5_client.post(
        f"{API}/runs/{run_id}/readings{query}",
        content=content,
        headers={**auth(WRITER), "content-type": content_type},
    )
    assert r.status_code == 201, r.text


def _short_member() -> bytes:
    """A .npy member whose header promises 10 values and which holds 5."""
    member = io.BytesIO()
    np.save(member, np.arange(10.0))
    return _archive({"time": None}, lambda f, _: f.write(member.getvalue()[:-40]))


@pytest.mark.parametrize(
    "body",
    [
        _short_member(),
        _archive({"time": np.arange(3.0)}, lambda f, v: np.lib.format.write_array(f, v, (3, 0))),
        _savez({"time": np.array([{"a": 1}], dtype=object)}),
    ],
    ids=["cut short", "npy version 3", "objects"],
)
def test_archives_that_lie_or_hold_objects_are_refused(
    hdf5_client: TestClient, body: bytes
) -> None:
    run_id = open_run(hdf5_client)
    r = hdf5_client.post(
        f"{API}/runs/{run_id}/readings?seq=0&group=friction", content=body, headers=NPZ
    )
    assert r.status_code == 422, r.text
    assert is_problem(r)
    assert "time" in r.json()["detail"]


def test_the_ingest_route_is_documented_with_its_parameters(hdf5_client: TestClient) -> None:
    post = hdf5_client.get("/openapi.json").json()["paths"][API + "/runs/{run_id}/readings"]
    assert {p["name"] for p in post["post"]["parameters"]} == {"run_id", "seq", "group"}
    assert set(post["post"]["requestBody"]["content"]) == {"application/json", NPZ_MEDIA_TYPE}


def test_columns_are_views_of_the_body_aligned_or_not() -> None:
    # np.savez puts a member's values 30 + len(name) + 20 (zip64) bytes past its local
    # header plus a 64-byte multiple: a 10-character name (14 with ".npy") lands on 8 bytes
    body = _savez({"abcdefghij": np.arange(5.0), "time": np.arange(5.0)})
    arrays = parse_npz(body, 1 << 20)
    assert arrays["abcdefghij"].base is body and arrays["abcdefghij"].flags.aligned
    assert arrays["time"].base is body and not arrays["time"].flags.aligned
    np.testing.assert_array_equal(arrays["time"], np.arange(5.0))
    # neither can change after it is digested: both read-only, and the store takes them as
    # they are (no second copy of megabytes), while a writable array is copied
    assert not arrays["abcdefghij"].flags.writeable and not arrays["time"].flags.writeable
    batch = prepare("friction", arrays)
    assert batch.columns["time"] is arrays["time"]
    assert batch.columns["abcdefghij"] is arrays["abcdefghij"]
    writable = np.arange(5.0)
    assert prepare("friction", {"time": writable}).columns["time"] is not writable


def test_a_big_endian_member_is_read_by_its_values() -> None:
    # a '>f8' member is a view of its bytes in their order: its values are read as they are
    # and the store converts them to '<f8'
    values = np.linspace(-3.0, 7.5, 1001).astype(">f8")
    body = _savez({"time": values, "abcdefghij": np.arange(1001.0)})
    got = parse_npz(body, 1 << 20)["time"]
    assert got.base is body
    assert got.dtype == np.dtype(">f8")
    np.testing.assert_array_equal(got, np.linspace(-3.0, 7.5, 1001))
    assert prepare("friction", {"time": got}).columns["time"].dtype == np.dtype("<f8")


def test_a_large_batch_is_checked_in_itself_and_from_the_runs_last_values(
    hdf5_client: TestClient,
) -> None:
    # a large batch (stored from a worker thread, not the loop's group commits) is checked
    # in itself and after the run's last stored values: each refusal names its row (the
    # time channel must increase: friction row k has time k)
    run_id = open_run(hdf5_client)
    url = f"{API}/runs/{run_id}/readings"
    rows = 10_000  # 400 kB of values: past the loop's small bodies (64 KiB)

    def post(seq: int, columns: dict[str, Any]) -> Any:
        return hdf5_client.post(
            f"{url}?seq={seq}&group=friction", content=_savez(columns), headers=NPZ
        )

    assert post(0, friction(0, rows)).status_code == 201
    again = post(1, friction(rows - 1, rows))  # starts at the last stored time
    assert again.status_code == 422, again.text
    (first,) = [v for v in again.json()["errors"] if v["field"].startswith("columns.time")]
    assert first["field"] == "columns.time[0]"
    assert f"the value before it is {rows - 1:g} s" in first["message"]
    backwards = friction(rows, rows)
    backwards["time"][5000] = backwards["time"][4999]  # a step of zero inside the batch
    inside = post(1, backwards)
    assert inside.status_code == 422, inside.text
    assert [v["field"] for v in inside.json()["errors"]] == ["columns.time[5000]"]
    assert post(1, friction(rows, rows)).status_code == 201  # nothing of them was stored
    run = hdf5_client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()
    assert run["rows"]["friction"] == 2 * rows
