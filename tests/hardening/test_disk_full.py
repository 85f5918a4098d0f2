"""The disk filling up: posts fail with 507 and a clear message, nothing acknowledged is
lost, and the service takes readings again once there is space.

In process, the write errors are injected where the journal, SQLite and the run file write;
over HTTP, the data directory is a small tmpfs filled for real (where mounting is allowed:
as root, as in CI)."""

from __future__ import annotations

import errno
import os
import sqlite3
import subprocess
from collections.abc import Callable, Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest
from fastapi.testclient import TestClient

from rigserver.storage.embedded import payload_files as payloads
from rigserver.storage.embedded.journal import Journal
from rigserver.storage.runfile import RunFile
from tests.api.conftest import READER, WRITER, auth
from tests.hardening.conftest import (
    API,
    friction,
    is_problem,
    json_batch,
    npz_body,
    open_run,
    serve,
)

MB = 1 << 20


def stored_times(client: TestClient, run_id: str) -> list[float]:
    r = client.get(f"{API}/runs/{run_id}/readings?group=friction", headers=auth(READER))
    times: list[float] = r.json()["friction"]["columns"]["time"]
    return times


def _full_payload_file(*args: object) -> None:
    raise OSError(errno.ENOSPC, "No space left on device")


def _full_sqlite(self: Journal) -> None:
    raise sqlite3.OperationalError("database or disk is full")


def _full_run_file(*args: object, **kwargs: object) -> None:
    raise OSError(errno.ENOSPC, "No space left on device")


@pytest.mark.parametrize(
    ("target", "name", "fault"),
    [
        (payloads, "_write_all", _full_payload_file),  # the batch's readings
        (Journal, "commit", _full_sqlite),  # the journal's commit
    ],
    ids=["payload", "sqlite"],
)
def test_a_full_journal_is_507_and_loses_nothing(
    hdf5_client: TestClient,
    monkeypatch: pytest.MonkeyPatch,
    target: object,
    name: str,
    fault: Callable[..., None],
) -> None:
    run_id = open_run(hdf5_client)
    url = f"{API}/runs/{run_id}/readings"
    assert hdf5_client.post(url, json=json_batch(0, 0, 10), headers=auth(WRITER)).status_code == 201
    with monkeypatch.context() as m:
        m.setattr(target, name, fault)
        for seq in (1, 2):
            r = hdf5_client.post(url, json=json_batch(seq, 10 * seq, 10), headers=auth(WRITER))
            assert r.status_code == 507, r.text
            assert is_problem(r)
            assert r.json()["title"] == "Storage full"
            assert "disk of the data directory is full" in r.json()["detail"]
            assert "free some space and retry" in r.json()["detail"]
        run = hdf5_client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()
        assert run["rows"]["friction"] == 10
        assert stored_times(hdf5_client, run_id) == list(range(10))
    for seq in (1, 2):  # space is back: the same batches are taken
        r = hdf5_client.post(url, json=json_batch(seq, 10 * seq, 10), headers=auth(WRITER))
        assert r.status_code == 201, r.text
    assert stored_times(hdf5_client, run_id) == list(range(30))


def test_a_full_disk_under_the_run_file_keeps_the_acknowledged_batch(
    hdf5_client: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The journal took the batch, the HDF5 file did not: 507 says the batch is stored, and
    its retry is answered as a duplicate once the file is rebuilt."""
    run_id = open_run(hdf5_client)
    url = f"{API}/runs/{run_id}/readings"
    assert hdf5_client.post(url, json=json_batch(0, 0, 10), headers=auth(WRITER)).status_code == 201
    with monkeypatch.context() as m:
        m.setattr(RunFile, "append", _full_run_file)
        r = hdf5_client.post(url, json=json_batch(1, 10, 10), headers=auth(WRITER))
        assert r.status_code == 507
        assert "the batch is stored: retry with the same seq" in r.json()["detail"]
    again = hdf5_client.post(url, json=json_batch(1, 10, 10), headers=auth(WRITER))
    assert again.status_code == 200
    assert again.json()["duplicate"] is True
    later = hdf5_client.post(url, json=json_batch(2, 20, 10), headers=auth(WRITER))
    assert later.status_code == 201
    assert stored_times(hdf5_client, run_id) == list(range(30))


@pytest.fixture
def small_disk(tmp_path: Path) -> Iterator[Path]:
    """A 64 MB tmpfs, or a skip where mounting is not allowed."""
    mount = tmp_path / "disk"
    mount.mkdir()
    if os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root")
    done = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=64m", "tmpfs", str(mount)],
        capture_output=True,
        text=True,
    )
    if done.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {done.stderr.strip()}")
    try:
        yield mount
    finally:
        subprocess.run(["umount", "-l", str(mount)], check=False)


@pytest.mark.slow
def test_a_really_full_disk_over_http(small_disk: Path, tmp_path: Path) -> None:
    """The data directory on a 64 MB tmpfs with 54 MB of ballast: binary batches of 1.6 MB
    until 507; then the ballast goes and the same batches are taken."""
    server = serve(tmp_path, "--data-dir", str(small_disk / "data"))
    rows = 40_000  # 5 channels x 8 B: 1.6 MB in the journal and again in the run file
    headers = {**auth(WRITER), "content-type": "application/x-npz"}
    try:
        with httpx.Client(base_url=server.url, timeout=60) as http:
            run_id = open_run(http)
            ballast = small_disk / "ballast"
            ballast.write_bytes(b"\0" * (54 * MB))
            seq, refused = 0, None
            while seq < 50:
                r = http.post(
                    f"{API}/runs/{run_id}/readings",
                    params={"seq": seq, "group": "friction"},
                    content=npz_body(friction(seq * rows, rows)),
                    headers=headers,
                )
                if r.status_code == 507:
                    refused = r
                    break
                assert r.status_code == 201, r.text
                seq += 1
            assert refused is not None, "the disk never filled"
            assert is_problem(refused)
            assert "full" in refused.json()["detail"]
            acknowledged = seq
            run = http.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()
            assert run["rows"]["friction"] >= acknowledged * rows
            ballast.unlink()
            for seq in range(acknowledged, acknowledged + 3):
                r = http.post(
                    f"{API}/runs/{run_id}/readings",
                    params={"seq": seq, "group": "friction"},
                    content=npz_body(friction(seq * rows, rows)),
                    headers=headers,
                )
                assert r.status_code in (200, 201), r.text  # 200: stored before its 507
            assert http.post(f"{API}/runs/{run_id}/finish", headers=auth(WRITER)).status_code == 200
        server.stop()
        server.start()  # and it all survives a restart
        with httpx.Client(base_url=server.url, timeout=60) as http:
            data = http.get(
                f"{API}/runs/{run_id}/readings?group=friction", headers=auth(READER)
            ).json()["friction"]["columns"]
        np.testing.assert_array_equal(data["time"], np.arange((acknowledged + 3) * rows))
    finally:
        server.stop()
