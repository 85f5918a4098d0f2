"""A damaged run (a catalogue row or file written by an older build, or a corrupt file)
never takes the service down: it is listed as damaged, its own routes answer a problem,
the store opens over it after a restart, and ``rigserver check`` names it. A creation that
fails half way leaves nothing behind."""

from __future__ import annotations

import errno
import sqlite3
from collections.abc import Callable
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from rigserver.cli import main
from rigserver.storage.runfile import RunFile
from tests.api.conftest import READER, WRITER, auth
from tests.hardening.conftest import API, hdf5_app, is_problem, json_batch, open_run

# what an older build stored for a NaN (pydantic writes it as null), a NUL character, or a
# row count that is not JSON: SQL on the catalogue row of the run
_ROW_DAMAGE: dict[str, str] = {
    "NaN in the specimen": "UPDATE runs SET run = json_set(run, '$.specimen.pin', json('null'))",
    "Infinity in the test plan": (
        "UPDATE runs SET run = json_set(run, '$.test_plan.steps', json('[1.0, null]'))"
    ),
    "NaN in the configuration": (
        "UPDATE runs SET run = json_set(run, '$.configuration.disc_radius', json('null'))"
    ),
    "NUL in the operator": "UPDATE runs SET run = json_set(run, '$.operator', 'a' || char(0))",
    "NUL in a specimen key": (
        "UPDATE runs SET run = json_set(run, '$.specimen', json('{\"a\\u0000\": 1}'))"
    ),
    "rows not JSON": "UPDATE runs SET rows = '{'",
}


def _finished_run(client: TestClient) -> str:
    run_id = open_run(client)
    r = client.post(f"{API}/runs/{run_id}/readings", json=json_batch(0, 0, 5), headers=auth(WRITER))
    assert r.status_code == 201, r.text
    assert client.post(f"{API}/runs/{run_id}/finish", headers=auth(WRITER)).status_code == 200
    return run_id


def _damage_row(data: Path, run_id: str, sql: str) -> None:
    with sqlite3.connect(data / "journal.sqlite") as db:
        assert db.execute(f"{sql} WHERE id = ?", (run_id,)).rowcount == 1


def _garble_file(data: Path, run_id: str) -> None:
    (data / "runs" / f"{run_id}.h5").write_bytes(b"not an HDF5 file" * 100)


def _remove_file(data: Path, run_id: str) -> None:
    (data / "runs" / f"{run_id}.h5").unlink()


# the routes of one run, as (method, path); {id} is the run's id
_RUN_ROUTES = [
    ("GET", API + "/runs/{id}"),
    ("GET", API + "/runs/{id}/readings"),
    ("GET", API + "/runs/{id}/readings?group=friction&format=csv"),
    ("GET", API + "/runs/{id}/results"),
    ("GET", API + "/runs/{id}/results.csv"),
    ("GET", API + "/runs/{id}/report.html"),
    ("GET", API + "/runs/{id}/export.zip"),
    ("GET", API + "/runs/{id}/profile.x3p"),
    ("GET", API + "/runs/{id}/live"),
    ("GET", "/runs/{id}"),
    ("POST", API + "/runs/{id}/readings"),
    ("POST", API + "/runs/{id}/finish"),
    ("POST", API + "/runs/{id}/abort"),
]


def _answers_without_500(client: TestClient, run_id: str) -> list[int]:
    statuses = []
    for method, path in _RUN_ROUTES:
        r = client.request(
            method, path.format(id=run_id), json=json_batch(1, 5, 1), headers=auth(WRITER)
        )
        assert r.status_code < 500, (method, path, r.status_code, r.text[:300])
        statuses.append(r.status_code)
    return statuses


@pytest.mark.parametrize(("what", "sql"), list(_ROW_DAMAGE.items()), ids=list(_ROW_DAMAGE))
@pytest.mark.parametrize("finished", [False, True], ids=["open", "finished"])
def test_a_damaged_catalogue_row_is_listed_as_damaged(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], what: str, sql: str, finished: bool
) -> None:
    data = tmp_path / "data"
    with TestClient(hdf5_app(data), raise_server_exceptions=False) as client:
        sound = _finished_run(client)
        damaged = _finished_run(client) if finished else open_run(client)
    _damage_row(data, damaged, sql)
    # a restart: the store opens over the damaged row
    with TestClient(hdf5_app(data), raise_server_exceptions=False) as client:
        page = client.get(f"{API}/runs", headers=auth(READER))
        assert page.status_code == 200, page.text
        runs = {run["id"]: run for run in page.json()["runs"]}
        assert runs[sound]["damage"] is None
        assert runs[damaged]["damage"].startswith(f"run {damaged} is damaged")
        home = client.get("/", headers=auth(READER))
        assert home.status_code == 200
        assert "damaged" in home.text and damaged in home.text
        statuses = _answers_without_500(client, damaged)
        assert set(statuses) == {409}, statuses
        r = client.get(f"{API}/runs/{damaged}", headers=auth(READER))
        assert is_problem(r)
        assert r.json()["title"] == "Run damaged"
        assert client.get(f"{API}/runs/{sound}/results", headers=auth(READER)).status_code == 200
    assert main(["check", "--data-dir", str(data)]) == 1
    out = capsys.readouterr().out
    assert out.startswith(f"{damaged}: ") and sound not in out


@pytest.mark.parametrize("damage", [_garble_file, _remove_file], ids=["corrupt", "missing"])
def test_a_damaged_run_file_answers_a_problem(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], damage: Callable[[Path, str], None]
) -> None:
    data = tmp_path / "data"
    with TestClient(hdf5_app(data), raise_server_exceptions=False) as client:
        run_id = _finished_run(client)
    damage(data, run_id)
    with TestClient(hdf5_app(data), raise_server_exceptions=False) as client:
        assert client.get(f"{API}/runs", headers=auth(READER)).status_code == 200
        assert client.get("/", headers=auth(READER)).status_code == 200
        r = client.get(f"{API}/runs/{run_id}/readings", headers=auth(READER))
        assert r.status_code == 409, r.text
        assert r.json()["title"] == "Run damaged"
        _answers_without_500(client, run_id)
    assert main(["check", "--data-dir", str(data)]) == 1
    assert capsys.readouterr().out.startswith(f"{run_id}: its file {run_id}.h5")


def test_check_says_a_clean_directory_is_clean_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    data = tmp_path / "data"
    with TestClient(hdf5_app(data), raise_server_exceptions=False) as client:
        _finished_run(client)
        open_run(client)
    assert main(["check", "--data-dir", str(data)]) == 0
    out = capsys.readouterr().out
    assert out.count("\n") == 1 and "2 runs, none damaged" in out
    assert main(["check", "--data-dir", str(tmp_path / "nowhere")]) == 2


@pytest.mark.parametrize(
    ("failure", "status"),
    [(OSError(errno.ENOSPC, "No space left on device"), 507), (ValueError("refused"), 500)],
    ids=["disk full", "a bug"],
)
def test_a_creation_that_fails_half_way_leaves_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, failure: Exception, status: int
) -> None:
    data = tmp_path / "data"
    with TestClient(hdf5_app(data), raise_server_exceptions=False) as client:
        ok = open_run(client)

        def fail(path: Path, run: object) -> RunFile:
            path.write_bytes(b"half a file")
            raise failure

        monkeypatch.setattr(RunFile, "create", fail)
        body = {"stand": "smts2", "operator": "Sidorov"}
        key = {**auth(WRITER), "Idempotency-Key": "key-1"}
        r = client.post(f"{API}/runs", json=body, headers=key)
        assert r.status_code == status, r.text
        monkeypatch.undo()
        assert [
            run["id"] for run in client.get(f"{API}/runs", headers=auth(READER)).json()["runs"]
        ] == [ok]
        assert sorted(p.stem for p in (data / "runs").iterdir()) == [ok]
        # the key opened nothing: it opens a run now
        again = client.post(f"{API}/runs", json=body, headers=key)
        assert again.status_code == 201, again.text
    with sqlite3.connect(data / "journal.sqlite") as db:
        assert db.execute("SELECT COUNT(*) FROM runs").fetchone()[0] == 2
        assert db.execute("SELECT COUNT(*) FROM run_keys").fetchone()[0] == 1
