"""The students' sketches through the ``.eln`` round trip (issue 38 item 5): every version
exported as a file of the run's folder, uploaded anew on import in the same order (the same
images, items and versions); a sketch in an archive is checked as an upload is."""

from __future__ import annotations

import pytest
from fastapi.testclient import TestClient

from rigsim.simulators import simulate
from schemas.stands import StandKind
from tests.api.conftest import READER, WRITER, auth
from tests.api.test_sketches import image
from tests.eln.conftest import Lab, export, graph_of, import_archive, members, resealed, rezip
from tests.reports.simulated import post

API = "/api/v1"
#: The SMTs-2 lab's sketch items: 4 the specimens, 5 the loading scheme.
UPLOADS = [
    (4, image("PNG"), "image/png"),
    (4, image("JPEG", (64, 48), "blue"), "image/jpeg"),
    (5, image("PNG", (20, 90), "green"), "image/png"),
]


@pytest.fixture(scope="module")
def sketched(lab: Lab) -> tuple[str, bytes]:
    """An SMTs-2 run with sketches on the exporting server, and its archive."""
    run_id = post(lab.source, simulate(StandKind.SMTS2, seed=9), WRITER)
    for item, data, media in UPLOADS:
        answer = lab.source.put(
            f"{API}/runs/{run_id}/sketches/{item}",
            content=data,
            headers={**auth(WRITER), "Content-Type": media},
        )
        assert answer.status_code == 201, answer.text
    return run_id, export(lab.source, f"{API}/runs/{run_id}/export.eln")


def _listed(client: TestClient, run_id: str) -> list[tuple[int, int, str, str]]:
    answer = client.get(f"{API}/runs/{run_id}/sketches", headers=auth(READER))
    assert answer.status_code == 200, answer.text
    found = answer.json()["sketches"]
    return [(s["item"], s["version"], s["media_type"], s["sha256"]) for s in found]


def test_every_version_of_every_sketch_survives_the_round_trip(
    lab: Lab, sketched: tuple[str, bytes]
) -> None:
    run_id, archive = sketched
    graph = graph_of(archive)
    names = {f"{run_id}/sketches/item-4-v1.png", f"{run_id}/sketches/item-4-v2.jpg"}
    names.add(f"{run_id}/sketches/item-5-v1.png")
    assert names <= set(graph)
    assert graph[f"{run_id}/sketches/item-4-v2.jpg"]["encodingFormat"] == "image/jpeg"
    answer = import_archive(lab.target, archive)
    assert answer.status_code == 201, answer.text
    imported = answer.json()["id"]
    assert _listed(lab.target, imported) == _listed(lab.source, run_id)
    for (item, data, _), version in zip(UPLOADS, (1, 2, 1), strict=True):
        got = lab.target.get(
            f"{API}/runs/{imported}/sketches/{item}?version={version}", headers=auth(READER)
        )
        assert got.content == data


def test_a_sketch_in_an_archive_is_checked_as_an_upload_is(
    lab: Lab, sketched: tuple[str, bytes]
) -> None:
    files = members(sketched[1])
    name = next(n for n in files if n.endswith("/sketches/item-4-v1.png"))
    files[name] = image("JPEG")  # a JPEG named .png: the name lies about the bytes
    before = lab.target.get(f"{API}/runs", headers=auth(READER)).json()["total"]
    answer = import_archive(lab.target, rezip(resealed(files)))
    assert answer.status_code == 422, answer.text
    assert "says image/png, but the bytes are image/jpeg" in answer.json()["detail"]
    assert answer.json()["errors"][0]["field"].endswith("sketches/item-4-v1.png")
    assert lab.target.get(f"{API}/runs", headers=auth(READER)).json()["total"] == before
