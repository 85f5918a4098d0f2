"""Archives made to hurt the importing server (issue 39, items 2-4): a run.json beyond the
limits of ``POST /runs``, JSON nested deeper than the wire allows, members that declare
or unpack to more than the disk can take, a scope refused; and imports beyond their pool.
Each is refused as the API refuses the same thing, and nothing larger than the import's
limits is written: what an import wrote is looked at as its directory is removed."""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from rigserver.api.import_slots import ImportSlots
from rigserver.api.problems import ApiProblem
from rigserver.reports.eln import METADATA
from schemas.stands import StandKind
from schemas.strict_json import MAX_DEPTH
from tests.api.conftest import MTOS_ONLY, READER, WRITER, auth
from tests.eln.conftest import Lab, import_archive, members, resealed, rezip
from tests.hardening.test_lying_archives import Member, archive

#: Nested deeper than Python's parser recurses (its limit is 1000 frames)
DEEP = 5000


def _count(lab: Lab) -> int:
    return int(lab.target.get("/api/v1/runs", headers=auth(READER)).json()["total"])


def _name(files: dict[str, bytes], suffix: str) -> str:
    return next(name for name in files if name.endswith(suffix))


def _with_run(lab: Lab, change: Callable[[dict[str, Any]], None]) -> bytes:
    """The profilometer archive with its run.json changed (and the metadata resealed)."""
    files = members(lab.archives[StandKind.PROFILOMETER])
    name = _name(files, "/run.json")
    run = json.loads(files[name])
    change(run)
    files[name] = json.dumps(run).encode()
    return rezip(resealed(files))


def _deep(depth: int) -> str:
    return "[" * depth + "]" * depth


@pytest.fixture
def written(monkeypatch: pytest.MonkeyPatch) -> Iterator[dict[str, int]]:
    """The files an import unpacked (name -> bytes, the archive itself left out), as its
    directory is removed: a file only grows, so this is the most it wrote."""
    found: dict[str, int] = {}
    remove = shutil.rmtree

    def spy(path: Any, *args: Any, **kwargs: Any) -> None:
        if Path(path).name.startswith("rig-import-"):
            for f in Path(path).iterdir():
                if f.name != "archive.eln":
                    found[f.name] = f.stat().st_size
        remove(path, *args, **kwargs)

    monkeypatch.setattr(shutil, "rmtree", spy)
    yield found


# --- item 2: run.json passes the models and limits of POST /runs -----------------------


OVERSIZED: dict[str, tuple[str, Any]] = {
    "a title of 10 MiB": ("title", "t" * (10 << 20)),
    "a specimen of 10 000 keys": ("specimen", {f"part {i}": "steel" for i in range(10_000)}),
    "a test plan of 10 000 keys": ("test_plan", {f"step {i}": 1.0 for i in range(10_000)}),
    "notes of 10 000 characters": ("notes", "n" * 10_000),
    "a configuration the stand refuses": ("configuration", {"vertical_magnification": -1.0}),
}


@pytest.mark.parametrize("case", OVERSIZED)
def test_run_json_is_refused_as_post_runs_refuses_it(lab: Lab, case: str) -> None:
    field, value = OVERSIZED[case]
    posted = lab.target.post(
        "/api/v1/runs",
        json={"stand": "profilometer", "operator": "Petrov", field: value},
        headers=auth(WRITER),
    )
    assert posted.status_code == 422, posted.text
    before = _count(lab)
    answer = import_archive(lab.target, _with_run(lab, lambda run: run.update({field: value})))
    assert answer.status_code == 422, answer.text[:500]
    # the same field, the same words and limit, under run.json
    assert answer.json()["errors"][0]["field"] == "run.json." + posted.json()["errors"][0]["field"]
    message = posted.json()["errors"][0]["message"]
    assert answer.json()["errors"][0]["message"] == "run.json." + message
    assert _count(lab) == before


# --- item 3: JSON nested deeper than the wire takes ----------------------------------


def _deep_metadata(where: str) -> Callable[[dict[str, bytes]], None]:
    def change(files: dict[str, bytes]) -> None:
        name = _name(files, METADATA)
        text = files[name].decode()
        if where == "root":
            text = text.rstrip().removesuffix("}") + f', "deep": {_deep(DEEP)}}}'
        else:  # a value of the first entity of the @graph
            text = text.replace(
                '"@graph": [', f'"@graph": [{{"@id": "#deep", "x": {_deep(DEEP)}}},'
            )
        files[name] = text.encode()

    return change


@pytest.mark.parametrize("where", ["root", "graph"])
def test_deep_metadata_is_422_naming_the_limit(lab: Lab, where: str) -> None:
    files = members(lab.archives[StandKind.PROFILOMETER])
    _deep_metadata(where)(files)
    answer = import_archive(lab.target, rezip(files))
    assert answer.status_code == 422, answer.text[:500]
    assert f"deeper than {MAX_DEPTH} levels" in answer.json()["detail"]
    assert answer.json()["errors"][0]["field"].endswith(METADATA)


@pytest.mark.parametrize("depth", [MAX_DEPTH + 1, DEEP])
def test_deep_run_json_is_422_naming_the_limit(lab: Lab, depth: int) -> None:
    files = members(lab.archives[StandKind.PROFILOMETER])
    name = _name(files, "/run.json")
    text = files[name].decode()
    files[name] = (text.rstrip().removesuffix("}") + f', "deep": {_deep(depth)}}}').encode()
    answer = import_archive(lab.target, rezip(resealed(files)))
    assert answer.status_code == 422, answer.text[:500]
    assert f"deeper than {MAX_DEPTH} levels" in answer.json()["detail"]
    assert answer.json()["errors"][0]["field"] == "run.json"


def test_the_stands_file_is_read_with_the_same_limit(tmp_path: Path) -> None:
    from rigserver.cli import _stand_overrides

    path = tmp_path / "stands.json"
    path.write_text('{"smts2": ' + _deep(DEEP) + "}")
    with pytest.raises(SystemExit, match=f"deeper than {MAX_DEPTH} levels"):
        _stand_overrides(path)
    path.write_text('{"smts2": {}, "smts2": {}}')
    with pytest.raises(SystemExit, match="'smts2' is given twice"):
        _stand_overrides(path)


# --- item 4: sizes, the disk, the scope, the pool -------------------------------------


def _run_file_replaced(lab: Lab, real: bytes, declared: int) -> bytes:
    """The profilometer archive whose run file is ``real`` while its zip header and its
    metadata declare ``declared`` bytes (the metadata's checksum: the first ``declared``)."""
    files = members(lab.archives[StandKind.PROFILOMETER])
    name = _name(files, ".h5")
    files[name] = real[:declared]
    files = resealed(files)
    meta = _name(files, METADATA)
    document = json.loads(files[meta])
    for node in document["@graph"]:
        if name.endswith("/" + node["@id"]):
            node["contentSize"] = str(declared)
    files[meta] = json.dumps(document).encode()
    return archive(
        *(
            Member(n, real if n == name else data, deflate=True, file_size=declared)
            if n == name
            else Member(n, data, deflate=True)
            for n, data in files.items()
        )
    )


def test_a_run_file_inflating_beyond_its_declared_size_is_cut_there(
    lab: Lab, written: dict[str, int]
) -> None:
    real = b"\x89HDF\r\n\x1a\n" + b"\0" * (8 << 20)  # 8 MiB behind 1 KB declared
    answer = import_archive(lab.target, _run_file_replaced(lab, real, 1000))
    assert answer.status_code == 422, answer.text
    assert written.get("run.h5", 0) <= 1000


def test_a_member_of_zeros_is_refused_before_it_is_written(
    lab: Lab, written: dict[str, int]
) -> None:
    """An honest member (its size and checksum true) of 64 MiB of zeros that deflate to
    64 KB, in place of the run file: not HDF5, refused at its first MiB, nothing written
    (before: all of it written, then refused as no run file)."""
    zeros = b"\0" * (64 << 20)
    answer = import_archive(lab.target, _run_file_replaced(lab, zeros, len(zeros)))
    assert answer.status_code == 422, answer.text
    assert "no HDF5 file" in answer.json()["detail"]
    assert written == {}


def test_a_member_declared_beyond_the_free_disk_is_507_before_anything_is_written(
    lab: Lab, written: dict[str, int], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A run file declaring 4 GB (the most a zip32 header says) where, as the server is
    told, 1 GiB is free beyond the reserve: refused before any member is written."""
    services = lab.target.app.state.services  # type: ignore[attr-defined]
    free = shutil.disk_usage(Path(services.settings.data_dir)).free
    settings = services.settings.model_copy(update={"import_disk_reserve": free - (1 << 30)})
    monkeypatch.setattr(services, "settings", settings)
    before = _count(lab)
    answer = import_archive(lab.target, _run_file_replaced(lab, b"\x89HDF", 4_000_000_000))
    assert answer.status_code == 507, answer.text
    assert "would write 4000000000 bytes" in answer.json()["detail"]
    assert written == {}
    assert _count(lab) == before


def test_an_archive_is_not_received_onto_a_full_disk(
    lab: Lab, monkeypatch: pytest.MonkeyPatch
) -> None:
    services = lab.target.app.state.services  # type: ignore[attr-defined]
    free = shutil.disk_usage(Path(services.settings.data_dir)).free
    settings = services.settings.model_copy(update={"import_disk_reserve": free + (1 << 30)})
    monkeypatch.setattr(services, "settings", settings)
    answer = import_archive(lab.target, lab.archives[StandKind.PROFILOMETER])
    assert answer.status_code == 507, answer.text
    assert answer.json()["detail"].startswith("archive: the import would write")


def test_a_scope_is_refused_before_anything_is_unpacked(lab: Lab, written: dict[str, int]) -> None:
    answer = import_archive(lab.target, lab.archives[StandKind.SMTS2], key=MTOS_ONLY)
    assert answer.status_code == 403 and "write:smts2" in answer.json()["detail"]
    assert written == {}


def test_one_key_holds_at_most_its_share_of_the_imports(lab: Lab) -> None:
    """The lab's default pool: 2 imports at once, one key at most half of them."""
    services = lab.target.app.state.services  # type: ignore[attr-defined]
    slots: ImportSlots = services.imports
    assert (slots.queue, slots.per_key) == (2, 1)
    writer = services.keyring.find(WRITER).fingerprint
    mtos = services.keyring.find(MTOS_ONLY).fingerprint
    with slots.admitted(writer):
        busy = import_archive(lab.target, lab.archives[StandKind.MTOS])
        assert busy.status_code == 503 and busy.headers["retry-after"] == "1"
        assert "one key may have at most 1 of them" in busy.json()["detail"]
        # another key has the rest of the pool
        assert (
            import_archive(lab.target, lab.archives[StandKind.MTOS], MTOS_ONLY).status_code == 201
        )
        with slots.admitted(mtos):
            full = import_archive(lab.target, lab.archives[StandKind.MTOS])
            assert full.status_code == 503 and "at most 2 archives" in full.json()["detail"]
    assert slots.held == {}


def test_the_pool_gives_its_places_back_whatever_happens() -> None:
    slots = ImportSlots(queue=3, share=0.5, retry_after=2)
    with pytest.raises(ValueError), slots.admitted("a"):
        raise ValueError
    with slots.admitted("a"), slots.admitted("b"):
        assert slots.held == {"a": 1, "b": 1}
        with pytest.raises(ApiProblem) as busy, slots.admitted("a"):
            pass
    assert busy.value.problem.status == 503
    assert slots.held == {}


def test_the_rebuilt_archive_helper_is_honest(lab: Lab) -> None:
    # the archives above are refused for what they hold: the same rebuilt with the true
    # run file imports
    files = members(lab.archives[StandKind.PROFILOMETER])
    name = _name(files, ".h5")
    body = _run_file_replaced(lab, files[name], len(files[name]))
    assert import_archive(lab.target, body).status_code == 201
