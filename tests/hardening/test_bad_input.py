"""Garbage from lab PCs: every bad request is answered with problem+json naming what is
wrong, never a 500, and nothing of a refused batch is stored."""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient

from schemas.readings import NPZ_MEDIA_TYPE
from tests.api.conftest import READER, WRITER, auth
from tests.hardening.conftest import (
    API,
    friction,
    hdf5_app,
    is_problem,
    json_batch,
    npz_body,
    open_run,
)

JSON = {**auth(WRITER), "content-type": "application/json"}
NPZ = {**auth(WRITER), "content-type": NPZ_MEDIA_TYPE}


def rows(client: TestClient, run_id: str) -> int:
    return int(client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()["rows"]["friction"])


@pytest.mark.parametrize(
    ("body", "field"),
    [
        (b'{"seq": 0, "group": "friction", "columns": {"time": [1', "body"),  # cut short
        (b"\xff\xfe not json", "body"),
        (b"[1, 2, 3]", "body"),
        (b'{"seq": "zero", "group": "friction", "columns": {}}', "seq"),
        (b'{"seq": 1.5, "group": "friction", "columns": {}}', "seq"),
        (b'{"seq": 0, "group": "friction", "columns": {"time": "1,2"}}', "columns.time"),
        (b'{"seq": 0, "group": "friction", "columns": {"time": [[1]]}}', "columns.time.0"),
        (b'{"seq": 0, "group": "friction", "columns": {"time": [null]}}', "columns.time.0"),
        (b'{"seq": 0, "group": "friction", "columns": {}, "extra": 1}', "extra"),
        (b'{"seq": 4611686018427387905, "group": "friction", "columns": {}}', "seq"),
        (b'{"seq": 0, "group": "' + b"g" * 5000 + b'", "columns": {}}', "group"),
        (b'{"seq": 0, "group": "friction/../../x", "columns": {}}', "group"),
    ],
)
def test_malformed_json_and_wrong_types_are_422(
    hdf5_client: TestClient, body: bytes, field: str
) -> None:
    run_id = open_run(hdf5_client)
    r = hdf5_client.post(f"{API}/runs/{run_id}/readings", content=body, headers=JSON)
    assert r.status_code == 422, r.text
    assert is_problem(r)
    assert r.json()["errors"][0]["field"].startswith(field)
    assert rows(hdf5_client, run_id) == 0


@pytest.mark.parametrize("literal", ["NaN", "Infinity", "-Infinity"])
def test_nan_and_infinities_in_json_name_the_reading(hdf5_client: TestClient, literal: str) -> None:
    run_id = open_run(hdf5_client)
    raw = (
        b'{"seq": 0, "group": "friction", "columns": {"time": [0, 1, 2], "load": [300, '
        + literal.encode()
        + b', 300], "speed": [1000, 1000, 1000], "friction_moment": [2.5, 2.5, 2.5], '
        b'"revolutions": [0, 0, 0]}}'
    )
    r = hdf5_client.post(f"{API}/runs/{run_id}/readings", content=raw, headers=JSON)
    assert r.status_code == 422, r.text
    assert is_problem(r)
    error = r.json()["errors"][0]
    assert error["field"] == "columns.load[1]"
    assert error["limit"] == "a finite number"
    assert rows(hdf5_client, run_id) == 0


def test_nan_and_infinities_in_npz_name_the_reading(hdf5_client: TestClient) -> None:
    run_id = open_run(hdf5_client)
    columns = friction(0, 5)
    columns["friction_moment"][3] = np.inf
    r = hdf5_client.post(
        f"{API}/runs/{run_id}/readings?seq=0&group=friction",
        content=npz_body(columns),
        headers=NPZ,
    )
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["field"] == "columns.friction_moment[3]"
    assert rows(hdf5_client, run_id) == 0


def _zip(members: dict[str, bytes], *, compress: bool = False) -> bytes:
    buffer = io.BytesIO()
    method = zipfile.ZIP_DEFLATED if compress else zipfile.ZIP_STORED
    with zipfile.ZipFile(buffer, "w", method) as z:
        for name, data in members.items():
            z.writestr(name, data)
    return buffer.getvalue()


def _npy(values: object) -> bytes:
    buffer = io.BytesIO()
    np.save(buffer, values)
    return buffer.getvalue()


@pytest.mark.parametrize(
    ("body", "query", "status", "title"),
    [
        (b"not a zip", "seq=0&group=friction", 422, "Unreadable binary batch"),
        # a member that is not a .npy file (found by schemathesis: it was a 500)
        (_zip({"a.txt": b"a"}), "seq=0&group=friction", 422, "Invalid binary batch"),
        (_zip({"time.npy": b"\x93NUMPY junk"}), "seq=0&group=friction", 422, None),
        (npz_body({"time": np.zeros((3, 2))}), "seq=0&group=friction", 422, None),
        (npz_body({"time": np.array(["a", "b"])}), "seq=0&group=friction", 422, None),
        (npz_body({"time": np.array([1 + 2j])}), "seq=0&group=friction", 422, None),
        (npz_body(friction(0, 3)), "group=friction", 422, "seq and group needed"),
        (npz_body(friction(0, 3)), "seq=-1&group=friction", 422, "seq and group needed"),
        (npz_body(friction(0, 3)), "seq=x&group=friction", 422, "seq and group needed"),
        (npz_body(friction(0, 3)), "seq=0&group=" + "g" * 500, 422, "seq and group needed"),
        (npz_body(friction(0, 3)), "seq=0&group=profile", 422, "Unknown channel group"),
        # a zip bomb: 64 MiB of zeros compress to a few hundred kB
        (
            _zip({"time.npy": _npy(np.zeros(8 << 20))}, compress=True),
            "seq=0&group=friction",
            413,
            "Binary batch too large",
        ),
    ],
)
def test_bad_binary_batches(
    tmp_path: Path, body: bytes, query: str, status: int, title: str | None
) -> None:
    app = hdf5_app(tmp_path / "data", max_body_bytes=32 << 20)
    with TestClient(app, raise_server_exceptions=False) as client:
        run_id = open_run(client)
        r = client.post(f"{API}/runs/{run_id}/readings?{query}", content=body, headers=NPZ)
        assert r.status_code == status, r.text
        assert is_problem(r)
        if title is not None:
            assert r.json()["title"] == title
        assert rows(client, run_id) == 0


def test_oversized_bodies_are_413_before_they_are_read(tmp_path: Path) -> None:
    app = hdf5_app(tmp_path / "data", max_body_bytes=10_000)
    with TestClient(app, raise_server_exceptions=False) as client:
        run_id = open_run(client)
        url = f"{API}/runs/{run_id}/readings"
        big = json_batch(0, 0, 1000)  # about 60 kB of JSON
        r = client.post(url, json=big, headers=auth(WRITER))
        assert r.status_code == 413
        assert is_problem(r)
        assert "10000 bytes" in r.json()["detail"]

        def chunks() -> object:  # no Content-Length: counted as it streams
            yield b'{"seq": 0, "group": "friction", "columns": {"time": ['
            for _ in range(3000):
                yield b"1.0, "
            yield b"1.0]}}"

        r = client.post(url, content=chunks(), headers=JSON)  # type: ignore[arg-type]
        assert r.status_code == 413
        assert is_problem(r)
        assert rows(client, run_id) == 0
        assert client.post(url, json=json_batch(0, 0, 10), headers=auth(WRITER)).status_code == 201


def test_unknown_runs_stands_and_path_like_or_huge_identifiers(hdf5_client: TestClient) -> None:
    for run_id in (
        "20261122T114026Z-00000000",  # well-formed, unknown
        "..%2F..%2Fjournal.sqlite",
        "%2E%2E",
        "x" * 10_000,
        "20261122T114026Z-00000000%00",
    ):
        for method, path in (
            ("GET", f"{API}/runs/{run_id}"),
            ("POST", f"{API}/runs/{run_id}/readings"),
            ("GET", f"{API}/runs/{run_id}/readings?format=hdf5"),
            ("POST", f"{API}/runs/{run_id}/finish"),
        ):
            r = hdf5_client.request(method, path, json=json_batch(0, 0, 1), headers=auth(WRITER))
            assert r.status_code == 404, (method, path, r.text)
            assert is_problem(r)
            assert len(r.text) < 1000  # a huge id is not echoed whole
    r = hdf5_client.post(
        f"{API}/runs", json={"stand": "../etc", "operator": "x"}, headers=auth(WRITER)
    )
    assert r.status_code == 422
    assert is_problem(r)
    r = hdf5_client.post(
        f"{API}/runs", json={"stand": "smts2", "operator": "x" * 100_000}, headers=auth(WRITER)
    )
    assert r.status_code in (201, 422)
    assert r.status_code == 201 or is_problem(r)


def test_unknown_channels_and_unequal_lengths_are_refused(hdf5_client: TestClient) -> None:
    run_id = open_run(hdf5_client)
    url = f"{API}/runs/{run_id}/readings"
    batch = json_batch(0, 0, 3)
    batch["columns"]["temperature"] = [1.0, 2.0, 3.0]
    r = hdf5_client.post(url, json=batch, headers=auth(WRITER))
    assert r.status_code == 422
    assert r.json()["errors"][0]["field"] == "columns.temperature"
    batch = json_batch(0, 0, 3)
    batch["columns"]["load"] = [300.0]
    r = hdf5_client.post(url, json=batch, headers=auth(WRITER))
    assert r.status_code == 422
    assert "equal lengths" in r.json()["detail"]
    csv = {**auth(WRITER), "content-type": "text/csv"}
    r = hdf5_client.post(url, content=b"a,b\n1,2", headers=csv)
    assert r.status_code == 415
    assert is_problem(r)
    assert rows(hdf5_client, run_id) == 0


def test_posts_to_a_finished_or_aborted_run_are_409(hdf5_client: TestClient) -> None:
    for end in ("finish", "abort"):
        run_id = open_run(hdf5_client)
        url = f"{API}/runs/{run_id}/readings"
        first = hdf5_client.post(url, json=json_batch(0, 0, 5), headers=auth(WRITER))
        assert first.status_code == 201
        ended = hdf5_client.post(f"{API}/runs/{run_id}/{end}", headers=auth(WRITER))
        assert ended.status_code == 200
        r = hdf5_client.post(url, json=json_batch(1, 5, 5), headers=auth(WRITER))
        assert r.status_code == 409
        assert is_problem(r)
        assert "takes no more readings" in r.json()["detail"]
        r = hdf5_client.post(
            f"{url}?seq=2&group=friction", content=npz_body(friction(10, 5)), headers=NPZ
        )
        assert r.status_code == 409
        # a retry of a batch stored before the end still gets its receipt
        again = hdf5_client.post(url, json=json_batch(0, 0, 5), headers=auth(WRITER))
        assert again.status_code == 200
        assert again.json()["duplicate"] is True
        assert rows(hdf5_client, run_id) == 5


def test_run_list_offsets_past_sqlite_integers(hdf5_client: TestClient) -> None:
    # found by schemathesis: an offset of 2^63 was an OverflowError (500) in the journal
    r = hdf5_client.get(f"{API}/runs?offset={2**63}", headers=auth(READER))
    assert r.status_code == 200, r.text
    assert r.json()["runs"] == []
