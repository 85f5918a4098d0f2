"""The students' words through the ``.eln`` round trip: every version exported in the run's
``notes.json``, written anew on import in the same order; words in an archive are checked
as a write through the API is (nothing typed is lost by moving a run to another server)."""

from __future__ import annotations

import json

import pytest

from rigsim.simulators import simulate
from schemas.stands import StandKind
from schemas.student_notes import CONCLUSIONS_LIMIT
from tests.api.conftest import READER, WRITER, auth
from tests.eln.conftest import Lab, export, graph_of, import_archive, members, resealed, rezip
from tests.reports.simulated import post

API = "/api/v1"
#: Two writes of a group's words: the second corrects the first's conclusions.
WRITES = [
    {"group": "MT-31", "students": ["A. Ivanova"], "conclusions": "The wear grows."},
    {
        "group": "MT-31",
        "students": ["A. Ivanova", "B. Petrov"],
        "conclusions": "The wear grows with the load, as table 2.3 shows.",
        "observations": "Brass transferred to the disc in the adhesive run.",
    },
]


@pytest.fixture(scope="module")
def written(lab: Lab) -> tuple[str, bytes]:
    """An SMTs-2 run with two versions of the students' words, and its archive."""
    run_id = post(lab.source, simulate(StandKind.SMTS2, seed=11), WRITER)
    for body in WRITES:
        answer = lab.source.put(f"{API}/runs/{run_id}/notes", json=body, headers=auth(WRITER))
        assert answer.status_code == 200, answer.text
    return run_id, export(lab.source, f"{API}/runs/{run_id}/export.eln")


def test_every_version_of_the_words_survives_the_round_trip(
    lab: Lab, written: tuple[str, bytes]
) -> None:
    run_id, archive = written
    assert graph_of(archive)[f"{run_id}/notes.json"]["encodingFormat"] == "application/json"
    answer = import_archive(lab.target, archive)
    assert answer.status_code == 201, answer.text
    imported = answer.json()["id"]
    got = lab.target.get(f"{API}/runs/{imported}/notes", headers=auth(READER)).json()
    assert got["version"] == len(WRITES)
    assert {k: got[k] for k in WRITES[-1]} == WRITES[-1]
    assert got["analysis"] == "" and got["mismatch"] == ""


def test_words_in_an_archive_are_checked_as_a_write_is(
    lab: Lab, written: tuple[str, bytes]
) -> None:
    files = members(written[1])
    name = next(n for n in files if n.endswith("/notes.json"))
    words = json.loads(files[name])
    words[0]["conclusions"] = "x" * (CONCLUSIONS_LIMIT + 1)  # beyond what the API takes
    files[name] = json.dumps(words).encode()
    before = lab.target.get(f"{API}/runs", headers=auth(READER)).json()["total"]
    answer = import_archive(lab.target, rezip(resealed(files)))
    assert answer.status_code == 422, answer.text
    assert answer.json()["errors"][0]["field"].endswith("notes.json")
    assert "0.conclusions" in answer.json()["detail"]
    assert lab.target.get(f"{API}/runs", headers=auth(READER)).json()["total"] == before
