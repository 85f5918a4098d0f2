"""What a new user met first (issue 39, item 11): one clear line where there was a traceback
or a message that names nothing."""

from __future__ import annotations

import subprocess
import sys

import pytest
from fastapi.testclient import TestClient

from tests.api.conftest import WRITER, Server, auth


def test_a_second_server_on_a_data_directory_in_use_says_so_in_one_line(server: Server) -> None:
    serve = [sys.executable, "-m", "rigserver.cli", "serve", "--port", "1"]
    second = subprocess.run(
        [*serve, "--data-dir", str(server.data_dir)],
        capture_output=True,
        text=True,
        timeout=120,
        stdin=subprocess.DEVNULL,
    )
    assert second.returncode != 0
    assert "Traceback" not in second.stderr
    lines = second.stderr.strip().splitlines()
    assert len(lines) == 1 and "in use" in lines[0] and str(server.data_dir) in lines[0]


@pytest.mark.parametrize("content_type", [None, "text/plain", "application/x-www-form-urlencoded"])
def test_a_json_body_without_its_content_type_names_the_header(
    client: TestClient, content_type: str | None
) -> None:
    headers = auth(WRITER)
    if content_type is not None:
        headers["Content-Type"] = content_type
    r = client.post("/api/v1/runs", content=b'{"stand": "mtos", "operator": "A"}', headers=headers)
    assert r.status_code == 415
    problem = r.json()
    assert "Content-Type: application/json" in problem["detail"]
    assert (content_type or "no Content-Type header") in problem["detail"]
    assert problem["errors"][0]["field"] == "Content-Type"


def test_a_json_body_of_the_wrong_shape_is_still_a_422(client: TestClient) -> None:
    r = client.post("/api/v1/runs", json=[1, 2], headers=auth(WRITER))
    assert r.status_code == 422 and "Content-Type" not in r.json()["detail"]
