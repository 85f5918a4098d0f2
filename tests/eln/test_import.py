"""POST /runs/import: a run exported by one rig server recreated on another (an HDF5 store)
with the same readings and results, exported again the same; a foreign or damaged archive
refused with a problem naming what is wrong, and nothing of it stored."""

from __future__ import annotations

import hashlib
import io
import json
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
from fastapi.testclient import TestClient

from rigserver.api.app import create_app
from rigserver.api.auth import ApiKey
from rigserver.api.settings import Settings
from rigserver.reports.eln import METADATA, SOFTWARE
from rigserver.storage import MemoryStore
from schemas.stands import StandKind, configure_stands
from tests.api.conftest import KEYS, MTOS_ONLY, READER, WRITER, auth
from tests.eln.conftest import (
    ELN,
    Lab,
    export,
    import_archive,
    members,
    resealed,
    rezip,
)
from tests.hardening.test_lying_archives import Member, archive

KINDS = list(StandKind)


def _run_file(client: TestClient, run_id: str) -> dict[str, np.ndarray]:
    """Every dataset of a run's channel groups, read from its HDF5 file as served."""
    answer = client.get(f"/api/v1/runs/{run_id}/readings?format=hdf5", headers=auth(READER))
    assert answer.status_code == 200, answer.text
    found = {}
    with h5py.File(io.BytesIO(answer.content), "r") as f:
        entry = f["entry"]
        for group in entry:
            if isinstance(entry[group], h5py.Group) and group != "results":
                for channel, data in entry[group].items():
                    found[f"{group}/{channel}"] = np.asarray(data)
    return found


def _results(client: TestClient, run_id: str) -> Any:
    answer = client.get(f"/api/v1/runs/{run_id}/results", headers=auth(READER))
    assert answer.status_code == 200, answer.text
    return answer.json()


def _count(client: TestClient) -> int:
    return int(client.get("/api/v1/runs", headers=auth(READER)).json()["total"])


@pytest.mark.parametrize("kind", KINDS)
def test_round_trip_gives_the_same_readings_and_results(lab: Lab, kind: StandKind) -> None:
    original = lab.runs[kind]
    answer = import_archive(lab.target, lab.archives[kind])
    assert answer.status_code == 201, answer.text
    imported = answer.json()
    assert imported["id"] != original
    assert imported["imported_from"]["run_id"] == original
    assert imported["imported_from"]["server"] == "http://testserver/"
    assert imported["stand"] == kind.value and imported["state"] == "finished"
    source = lab.source.get(f"/api/v1/runs/{original}", headers=auth(READER)).json()
    for same in ("operator", "title", "specimen", "test_plan", "configuration", "rows"):
        assert imported[same] == source[same], same
    assert imported["key_results"] == source["key_results"]
    # every reading and single measurement, NaN where a batch had none, bit for bit
    before, after = _run_file(lab.source, original), _run_file(lab.target, imported["id"])
    assert before.keys() == after.keys()
    for name, values in before.items():
        np.testing.assert_array_equal(after[name], values, err_msg=name)
    # the results computed again here, equal to those computed there
    assert _results(lab.target, imported["id"]) == _results(lab.source, original)
    # exported again: the same readings and results, the new server named
    again = members(export(lab.target, f"/api/v1/runs/{imported['id']}/export.eln"))
    first = members(lab.archives[kind])
    for name in ("results.json", "results.csv", *(f"{g}.csv" for g in source["rows"])):
        assert (
            again[f"{imported['id']}/{imported['id']}/{name}"]
            == (first[f"{original}/{original}/{name}"])
        ), name
    graph = {n["@id"]: n for n in json.loads(again[f"{imported['id']}/{METADATA}"])["@graph"]}
    assert graph["./"]["publisher"] == {"@id": "http://lab-b/"}
    page = lab.target.get(f"/runs/{imported['id']}?lang=ru", headers=auth(READER)).text
    assert f"Импортировано из</th><td>{original}, http://testserver/" in page


def _edit(archive_bytes: bytes, edit: Any) -> bytes:
    files = members(archive_bytes)
    edit(files)
    return rezip(files)


def _member(files: dict[str, bytes], suffix: str) -> str:
    return next(name for name in files if name.endswith(suffix))


def _graph_edit(files: dict[str, bytes], change: Any) -> None:
    name = _member(files, METADATA)
    document = json.loads(files[name])
    change(document)
    files[name] = json.dumps(document).encode()


def _drop_software(document: dict[str, Any]) -> None:
    document["@graph"] = [n for n in document["@graph"] if n["@id"] != SOFTWARE]


def _foreign(files: dict[str, bytes]) -> None:
    _graph_edit(files, _drop_software)


def _oversized(files: dict[str, bytes]) -> None:
    name = _member(files, "/results.csv")
    files[name] += b"one more line\n"


def _flipped(files: dict[str, bytes]) -> None:
    name = _member(files, "/results.csv")
    data = bytearray(files[name])
    data[10] ^= 1  # same size, another byte
    files[name] = bytes(data)


def _bomb(archive_bytes: bytes, declared: int) -> bytes:
    """The profilometer archive with its results.csv replaced by a member whose headers
    declare ``declared`` bytes (and whose metadata agrees) while it inflates to more."""
    files = members(archive_bytes)
    name = _member(files, "/results.csv")
    real = b"x" * 5_000_000
    files[name] = real[:declared]
    files = resealed(files)
    return archive(
        *(
            Member(
                n,
                real if n == name else data,
                deflate=True,
                file_size=declared if n == name else None,
            )
            for n, data in files.items()
        )
    )


REFUSALS: dict[str, tuple[Any, str]] = {
    "not a zip": (lambda a: b"PK\x03\x04 this is no archive", "not a zip archive"),
    "no metadata": (
        lambda a: _edit(a, lambda f: f.pop(_member(f, METADATA))),
        "no metadata",
    ),
    "not rig's": (lambda a: _edit(a, _foreign), "not an archive made by rig"),
    "missing member": (
        lambda a: _edit(a, lambda f: f.pop(_member(f, "/results.csv"))),
        "missing member",
    ),
    "oversized member": (lambda a: _edit(a, _oversized), "oversized member"),
    "duplicate member": (
        lambda a: rezip([*members(a).items(), (_member(members(a), "/results.csv"), b"again")]),
        "twice",
    ),
    "path traversal": (
        lambda a: _edit(a, lambda f: f.update({f"{next(iter(f)).split('/')[0]}/../x.csv": b"1"})),
        "path traversal",
    ),
    "absolute path": (lambda a: _edit(a, lambda f: f.update({"/etc/x": b"1"})), "path traversal"),
    "undeclared member": (
        lambda a: _edit(a, lambda f: f.update({f"{next(iter(f)).split('/')[0]}/x.csv": b"1"})),
        "not described",
    ),
    "two root folders": (lambda a: _edit(a, lambda f: f.update({"other/x": b"1"})), "root"),
    "checksum mismatch": (lambda a: _edit(a, _flipped), "checksum mismatch"),
    "zip bomb, declared smaller than real": (lambda a: _bomb(a, 1000), "does not unpack"),
    "zip bomb, declared beyond the limit": (
        # three members of 4 GB (the most a zip32 header says): 12 GB, over the 8 GiB default
        lambda a: archive(*(Member(f"r/{k}.bin", b"", file_size=4_000_000_000) for k in range(3))),
        "zip bomb",
    ),
}


@pytest.mark.parametrize("case", REFUSALS)
def test_a_damaged_or_foreign_archive_is_refused_and_nothing_stored(lab: Lab, case: str) -> None:
    make, words = REFUSALS[case]
    before = _count(lab.target)
    answer = import_archive(lab.target, make(lab.archives[StandKind.PROFILOMETER]))
    assert answer.status_code == 422, answer.text
    problem = answer.json()
    assert answer.headers["content-type"] == "application/problem+json"
    assert words in problem["detail"], problem["detail"]
    assert problem["errors"] and problem["errors"][0]["field"]  # the member named
    assert _count(lab.target) == before


def test_a_series_archive_is_refused_naming_the_run_archive(lab: Lab) -> None:
    answer = import_archive(lab.target, lab.series_archive)
    assert answer.status_code == 422
    assert "holds 2 runs" in answer.json()["detail"]


def test_readings_this_server_would_refuse_leave_nothing_behind(lab: Lab, tmp_path: Path) -> None:
    """A well-formed archive whose run file holds a load beyond the SMTs-2's limit (5250 N):
    refused after the run file was read and partly written, and nothing is left."""
    files = members(lab.archives[StandKind.SMTS2])
    name = _member(files, ".h5")
    path = tmp_path / "run.h5"
    path.write_bytes(files[name])
    with h5py.File(path, "r+") as f:
        load = f["entry/friction/load"]
        load[len(load) - 1] = 1e6
    files[name] = path.read_bytes()
    data_dir = Path(lab.target.app.state.services.store.data_dir)  # type: ignore[attr-defined]
    runs_before = sorted((data_dir / "runs").iterdir())
    before = _count(lab.target)
    answer = import_archive(lab.target, rezip(resealed(files)))
    assert answer.status_code == 422, answer.text
    assert "load" in answer.json()["detail"]
    assert _count(lab.target) == before
    assert sorted((data_dir / "runs").iterdir()) == runs_before  # no file, no temp file


def test_authenticate_parse_authorise_act(lab: Lab) -> None:
    body = lab.archives[StandKind.SMTS2]
    anonymous = lab.target.post("/api/v1/runs/import", content=body, headers=ELN)
    assert anonymous.status_code == 401
    # a key for another stand: the archive is read first (its stand is in it), then 403
    assert import_archive(lab.target, b"not a zip", key=MTOS_ONLY).status_code == 422
    other = import_archive(lab.target, body, key=MTOS_ONLY)
    assert other.status_code == 403 and "write:smts2" in other.json()["detail"]
    wrong_type = lab.target.post(
        "/api/v1/runs/import",
        content=body,
        headers={**auth(WRITER), "content-type": "application/zip"},
    )
    assert wrong_type.status_code == 415
    assert import_archive(lab.target, body, key=READER).status_code == 403


def test_the_body_is_bounded_by_the_import_limit(lab: Lab, tmp_path: Path) -> None:
    body = lab.archives[StandKind.PROFILOMETER]
    settings = Settings(data_dir=tmp_path, import_max_bytes=len(body) - 1)
    keys = [ApiKey.model_validate(k) for k in KEYS]
    app = create_app(settings, MemoryStore(), keys, configure_stands())
    with TestClient(app, raise_server_exceptions=False) as small:
        answer = import_archive(small, body)
        assert answer.status_code == 413
        assert str(len(body) - 1) in answer.json()["detail"]
    # larger than the other bodies' limit, within the import's
    settings = Settings(data_dir=tmp_path, max_body_bytes=1000, import_max_bytes=len(body))
    with TestClient(create_app(settings, MemoryStore(), keys, configure_stands())) as client:
        assert import_archive(client, body).status_code == 201


def test_an_aborted_run_comes_over_aborted(lab: Lab) -> None:
    headers = auth(WRITER)
    run = lab.source.post(
        "/api/v1/runs", json={"stand": "profilometer", "operator": "Petrov"}, headers=headers
    ).json()
    batch = {"seq": 0, "group": "measurements", "columns": {"base_length": [0.8]}}
    lab.source.post(f"/api/v1/runs/{run['id']}/readings", json=batch, headers=headers)
    lab.source.post(f"/api/v1/runs/{run['id']}/abort", headers=headers)
    answer = import_archive(lab.target, export(lab.source, f"/api/v1/runs/{run['id']}/export.eln"))
    assert answer.status_code == 201, answer.text
    assert answer.json()["state"] == "aborted" and answer.json()["operator"] == "Petrov"
    assert answer.json()["rows"] == {"profile": 0, "measurements": 1}


def test_an_open_run_is_not_imported(lab: Lab) -> None:
    run = lab.source.post(
        "/api/v1/runs", json={"stand": "profilometer", "operator": "Petrov"}, headers=auth(WRITER)
    ).json()
    answer = import_archive(lab.target, export(lab.source, f"/api/v1/runs/{run['id']}/export.eln"))
    assert answer.status_code == 409
    assert "open" in answer.json()["detail"]


def test_resealed_archive_helper_is_honest(lab: Lab) -> None:
    # the refusals above are the edits' doing: an archive taken apart and put together
    # again, its checksums recomputed, is imported
    files = resealed(members(lab.archives[StandKind.PROFILOMETER]))
    assert hashlib.sha256(rezip(files)).hexdigest()
    assert import_archive(lab.target, rezip(files)).status_code == 201


def test_the_import_path_allows_post_alone(lab: Lab) -> None:
    # /runs/import is a resource of its own, not a run id of /runs/{run_id}
    answer = lab.target.request("OPTIONS", "/api/v1/runs/import", headers=auth(READER))
    assert answer.status_code == 405 and answer.headers["allow"] == "POST"
    other = lab.target.request(
        "OPTIONS", "/api/v1/runs/20261122T114026Z-00000000", headers=auth(READER)
    )
    assert "GET" in other.headers["allow"]
