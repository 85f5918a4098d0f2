"""Two rig servers in process (an in-memory store exporting, an HDF5 store importing),
every stand's simulated run and a series exported once, and helpers to take an archive
apart and put it back together."""

from __future__ import annotations

import hashlib
import io
import json
import time
import warnings
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from rigserver.api.app import create_app
from rigserver.api.auth import ApiKey
from rigserver.api.settings import Settings
from rigserver.reports.eln import ELN_MEDIA_TYPE, METADATA
from rigserver.storage import HDF5Store, MemoryStore
from rigsim.simulators import simulate
from schemas.stands import StandKind, configure_stands
from tests.api.conftest import KEYS, WRITER, auth
from tests.reports.simulated import post, series_of

LICENCE = "CC-BY-4.0"
ELN = {"content-type": ELN_MEDIA_TYPE}


@dataclass
class Lab:
    """The exporting server, the importing one, and what was exported from the first."""

    source: TestClient
    target: TestClient
    runs: dict[StandKind, str]
    archives: dict[StandKind, bytes]
    series_id: str
    series_archive: bytes


def export(client: TestClient, path: str) -> bytes:
    """An archive: a series' is answered 202 while its reports render (asked again)."""
    answer = client.get(path, headers=auth(WRITER))
    for _ in range(600):
        if answer.status_code != 202:
            break
        time.sleep(0.2)
        answer = client.get(path, headers=auth(WRITER))
    assert answer.status_code == 200, answer.text
    assert answer.headers["content-type"] == ELN_MEDIA_TYPE
    return answer.content


def import_archive(client: TestClient, body: bytes, key: str = WRITER) -> Any:
    return client.post("/api/v1/runs/import", content=body, headers={**auth(key), **ELN})


@pytest.fixture(scope="package")
def lab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Lab]:
    keys = [ApiKey.model_validate(k) for k in KEYS]
    here = tmp_path_factory.mktemp("eln")
    source_app = create_app(
        Settings(data_dir=here / "a", license=LICENCE), MemoryStore(), keys, configure_stands()
    )
    target_app = create_app(
        Settings(data_dir=here / "b"), HDF5Store(here / "b"), keys, configure_stands()
    )
    with (
        TestClient(source_app, raise_server_exceptions=False) as source,
        TestClient(target_app, raise_server_exceptions=False, base_url="http://lab-b") as target,
    ):
        runs = {kind: post(source, simulate(kind, seed=7), WRITER) for kind in StandKind}
        archives = {kind: export(source, f"/api/v1/runs/{runs[kind]}/export.eln") for kind in runs}
        repeat = post(source, simulate(StandKind.PROFILOMETER, seed=8), WRITER)
        traces = [runs[StandKind.PROFILOMETER], repeat]
        series = series_of(
            source, WRITER, traces, name="Roughness, two traces", purpose="repeatability"
        )
        series_archive = export(source, f"/api/v1/series/{series}/export.eln")
        yield Lab(source, target, runs, archives, series, series_archive)


def members(archive: bytes) -> dict[str, bytes]:
    """An archive's members by name, in order."""
    with zipfile.ZipFile(io.BytesIO(archive)) as z:
        return {info.filename: z.read(info) for info in z.infolist()}


def metadata_of(archive: bytes) -> dict[str, Any]:
    found = [v for k, v in members(archive).items() if k.endswith(f"/{METADATA}")]
    assert len(found) == 1
    document: dict[str, Any] = json.loads(found[0])
    return document


def graph_of(archive: bytes) -> dict[str, dict[str, Any]]:
    return {node["@id"]: node for node in metadata_of(archive)["@graph"]}


def rezip(files: dict[str, bytes] | list[tuple[str, bytes]]) -> bytes:
    """An archive of these members (a list may name one twice)."""
    out = io.BytesIO()
    with (
        zipfile.ZipFile(out, "w", compression=zipfile.ZIP_DEFLATED) as z,
        warnings.catch_warnings(),
    ):
        warnings.simplefilter("ignore")  # "Duplicate name": the point of some archives
        for name, data in files.items() if isinstance(files, dict) else files:
            z.writestr(name, data)
    return out.getvalue()


def resealed(files: dict[str, bytes]) -> dict[str, bytes]:
    """The members with the metadata's contentSize and sha256 of every file made true
    again (an archive edited by someone who knows the format)."""
    name = next(k for k in files if k.endswith(f"/{METADATA}"))
    root = name.split("/", 1)[0]
    document = json.loads(files[name])
    for node in document["@graph"]:
        data = files.get(f"{root}/{node['@id']}")
        if node.get("@type") == "File" and data is not None:
            node["contentSize"] = str(len(data))
            node["sha256"] = hashlib.sha256(data).hexdigest()
    return {**files, name: json.dumps(document).encode()}


def unzipped(archive: bytes, into: Path) -> Path:
    """The archive unpacked into ``into``; its root folder (the crate)."""
    with zipfile.ZipFile(io.BytesIO(archive)) as z:
        z.extractall(into)
        (root,) = {name.split("/", 1)[0] for name in z.namelist()}
    return into / root
