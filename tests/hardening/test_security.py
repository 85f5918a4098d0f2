"""Keys, scopes, logs, CORS, size and rate limits."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import httpx
import pytest
from fastapi.testclient import TestClient

from tests.api.conftest import KEYS, MTOS_ONLY, READER, WRITER, auth
from tests.hardening.conftest import API, hdf5_app, is_problem, json_batch, open_run, serve

UNKNOWN = "unknown-key-aaaaaaaaaaaaaaaa"


def test_no_write_without_a_key_nor_outside_its_scopes(hdf5_client: TestClient) -> None:
    smts2 = open_run(hdf5_client)
    writes = [
        ("POST", f"{API}/runs", {"stand": "smts2", "operator": "x"}),
        ("POST", f"{API}/runs/{smts2}/readings", json_batch(0, 0, 3)),
        ("POST", f"{API}/runs/{smts2}/finish", None),
        ("POST", f"{API}/runs/{smts2}/abort", None),
    ]
    for method, url, body in writes:
        for headers, status in (
            ({}, 401),
            (auth(UNKNOWN), 401),
            ({"Authorization": f"Basic {WRITER}"}, 401),
            (auth(READER), 403),  # read only
            (auth(MTOS_ONLY), 403),  # write:mtos, not write:smts2
        ):
            r = hdf5_client.request(method, url, json=body, headers=headers)
            assert r.status_code == status, (method, url, headers, r.text)
            assert is_problem(r)
            if status == 401:
                assert r.headers["www-authenticate"] == "Bearer"
            else:
                assert "write:smts2" in r.json()["detail"]
    run = hdf5_client.get(f"{API}/runs/{smts2}", headers=auth(READER)).json()
    assert run["state"] == "open"
    assert run["batches"] == 0
    mtos = hdf5_client.post(
        f"{API}/runs", json={"stand": "mtos", "operator": "x"}, headers=auth(MTOS_ONLY)
    )
    assert mtos.status_code == 201  # within its scope


def test_cors_is_closed_by_default_and_opens_to_the_origins_given(tmp_path: Path) -> None:
    preflight = {
        "Origin": "http://evil.example",
        "Access-Control-Request-Method": "POST",
        "Access-Control-Request-Headers": "authorization",
    }
    with TestClient(hdf5_app(tmp_path / "a"), raise_server_exceptions=False) as client:
        r = client.options(f"{API}/runs", headers=preflight)
        assert "access-control-allow-origin" not in r.headers
        r = client.get(f"{API}/stands", headers={**auth(READER), "Origin": "http://evil.example"})
        assert r.status_code == 200
        assert "access-control-allow-origin" not in r.headers
    app = hdf5_app(tmp_path / "b", cors_origins=("http://lab.example",))
    with TestClient(app, raise_server_exceptions=False) as client:
        r = client.options(f"{API}/runs", headers={**preflight, "Origin": "http://lab.example"})
        assert r.headers["access-control-allow-origin"] == "http://lab.example"
        r = client.options(f"{API}/runs", headers=preflight)
        assert "access-control-allow-origin" not in r.headers


def test_rate_limit_per_key_answers_429_with_retry_after(tmp_path: Path) -> None:
    app = hdf5_app(tmp_path / "data", rate_limit=0.5, rate_burst=3)
    with TestClient(app, raise_server_exceptions=False) as client:
        codes = [client.get(f"{API}/stands", headers=auth(READER)).status_code for _ in range(5)]
        assert codes[:3] == [200, 200, 200]  # the burst
        assert codes[3:] == [429, 429]
        r = client.get(f"{API}/stands", headers=auth(READER))
        assert is_problem(r)
        # the next token comes after 1 / 0.5 = 2 s at most
        assert 1 <= int(r.headers["retry-after"]) <= 2
        # another key has its own bucket
        assert client.get(f"{API}/stands", headers=auth(WRITER)).status_code == 200


def test_no_key_in_logs_or_error_messages(tmp_path: Path) -> None:
    """Every kind of error, with good and bad keys, on a server logging at debug level and
    limiting sizes and rates from its command line: no key in any answer or log line."""
    server = serve(
        tmp_path,
        "--log-level",
        "debug",
        "--max-body-bytes",
        "4096",
        "--rate-limit",
        "1",
        "--rate-burst",
        "40",
    )
    answers: list[str] = []
    try:
        with httpx.Client(base_url=server.url, timeout=10) as http:
            run_id = open_run(http)
            requests = [
                ("GET", "/runs", {}, auth(UNKNOWN)),
                ("GET", "/runs", {}, {"Authorization": f"Bearer {UNKNOWN} trailing"}),
                ("POST", "/runs", {"json": {"stand": "smts2"}}, auth(WRITER)),
                ("POST", "/runs", {"json": {"stand": "mtos", "operator": UNKNOWN}}, auth(READER)),
                ("POST", f"/runs/{run_id}/readings", {"content": b"{"}, auth(WRITER)),
                ("POST", f"/runs/{run_id}/readings", {"json": json_batch(0, 0, 200)}, auth(WRITER)),
                ("POST", "/runs/20261122T114026Z-00000000/readings", {}, auth(WRITER)),
                ("GET", f"/runs/{run_id}?key={WRITER}", {}, auth(READER)),
                ("POST", f"/runs/{run_id}/finish", {}, auth(MTOS_ONLY)),
            ]
            for method, url, kwargs, headers in requests:
                r = http.request(method, API + url, headers=headers, **kwargs)  # type: ignore[arg-type]
                assert r.status_code in (200, 401, 403, 404, 413, 422), (url, r.text)
                assert r.status_code == 200 or is_problem(r)
                answers.append(r.text + json.dumps(dict(r.headers)))
            assert (
                http.post(
                    f"/runs/{run_id}/readings", json=json_batch(0, 0, 200), headers=auth(WRITER)
                ).status_code
                == 413
            )  # --max-body-bytes
            codes = [http.get(f"{API}/stands", headers=auth(READER)).status_code for _ in range(45)]
            assert 429 in codes  # --rate-limit
    finally:
        server.stop()
    log = server.log.read_text()
    assert "DEBUG" in log or "debug" in log.lower()
    for key in [k["key"] for k in KEYS] + [UNKNOWN]:
        assert key not in log
        for answer in answers:
            assert key not in answer


def test_a_bad_keys_file_stops_the_start_without_showing_the_keys(tmp_path: Path) -> None:
    secret = "too-short-key"
    path = tmp_path / "keys.json"
    for text in (
        json.dumps([{"key": secret, "scopes": ["read"]}]),
        json.dumps([{"key": secret + "-" * 10, "scopes": "read"}]),
        '[{"key": "' + secret + '"',
    ):
        path.write_text(text)
        cmd = [sys.executable, "-m", "rigserver.cli", "serve", "--port", "1"]
        cmd += ["--data-dir", str(tmp_path / "data"), "--keys-file", str(path)]
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
        assert done.returncode != 0
        assert "keys file" in done.stderr
        assert secret not in done.stdout + done.stderr


@pytest.mark.parametrize("header", ["Bearer", "Bearer ", "bearer  ", "Token abc"])
def test_malformed_authorization_is_401_not_500(hdf5_client: TestClient, header: str) -> None:
    r = hdf5_client.post(
        f"{API}/runs", json={"stand": "smts2", "operator": "x"}, headers={"Authorization": header}
    )
    assert r.status_code == 401
    assert is_problem(r)
