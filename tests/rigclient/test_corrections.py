"""rigclient's run.correct and run.strike against the real service (in process): the
server keeps the value as typed and answers with the row as it now reads."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient

from rigclient import Client, InputError, RetryPolicy, ServerRefused
from tests.api.conftest import READER, WRITER, auth, in_process

FAST = RetryPolicy(base_delay=0.01, max_delay=0.05)


@pytest.fixture
def service(tmp_path: Path) -> Iterator[TestClient]:
    with in_process(tmp_path / "server") as c:
        yield c


def test_a_run_corrects_and_strikes_its_rows_on_the_server(
    service: TestClient, tmp_path: Path
) -> None:
    transport = service._transport  # the in-process server as httpx's transport
    with Client(
        "http://testserver", WRITER, spool=tmp_path / "spool", transport=transport, retry=FAST
    ) as client:
        run = client.open_run(stand="profilometer", operator="Petrov")
        with pytest.raises(InputError, match="not on the server yet"):
            run.correct("profile", 0, {"y": 0.5}, "misread")
        x = np.arange(5, dtype=float) * 0.001
        run.post("profile", {"x": x, "y": np.array([0.1, 0.2, 9.0, 0.4, 0.5])})
        assert client.wait(10)
        row = run.correct("profile", 2, {"y": 0.3}, "9 for 0.3: misread")
        assert row.values["y"] == 0.3 and row.original["y"] == 9.0
        assert run.strike("profile", 4, "the stylus slipped").struck
        with pytest.raises(ServerRefused, match="profile has no row 7"):
            run.correct("profile", 7, {"y": 0.3}, "r")
        run_id = run.server_id
    listed = service.get(f"/api/v1/runs/{run_id}/corrections", headers=auth(READER)).json()
    assert [(c["row"], c["channel"], c["was"], c["now"]) for c in listed["corrections"]] == [
        (2, "y", 9.0, 0.3),
        (4, None, None, None),
    ]
