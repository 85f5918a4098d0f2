"""Authenticate first (issue 14, item 4): a request without a key learns nothing; then
parse, then the stand scope; Idempotency-Keys belong to their API key; no header escapes
the rate limit; the login refuses other sites' forms; pages say what a browser may run."""

from __future__ import annotations

import base64
import hashlib
import re
import secrets
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.routing import APIRoute
from fastapi.testclient import TestClient

from rigserver.api.app import API_PREFIX, API_ROUTERS, create_app
from rigserver.api.auth import ApiKey
from rigserver.api.deps import require_key
from rigserver.api.settings import Settings
from rigserver.storage import MemoryStore
from schemas.stands import configure_stands
from tests.api.conftest import KEYS, MTOS_ONLY, READER, WRITER, auth
from tests.hardening.conftest import API, hdf5_app, is_problem, json_batch, open_run

#: A second lab PC that may write on every stand.
OTHER_WRITER = "other-writer-key-00000000"
MADE_UP = "20261122T114026Z-00000000"


def _app(**settings: Any) -> Any:
    keys = [*KEYS, {"key": OTHER_WRITER, "scopes": ["read", "write:*"], "name": "lab PC 2"}]
    return create_app(
        Settings(**settings),
        MemoryStore(),
        [ApiKey.model_validate(k) for k in keys],
        configure_stands(),
    )


@pytest.fixture(params=[False, True], ids=["keyed reads", "public reads"])
def client(request: pytest.FixtureRequest) -> Iterator[TestClient]:
    with TestClient(_app(public_reads=request.param), raise_server_exceptions=False) as c:
        yield c


def _api_routes() -> list[tuple[str, str, bool]]:
    """(method, path, is a write) of every route of the API."""
    found = []
    for route in (route for router in API_ROUTERS for route in router.routes):
        assert isinstance(route, APIRoute)
        calls = {d.call for d in route.dependant.dependencies}
        for method in sorted(route.methods):
            found.append((method, API_PREFIX + route.path, require_key in calls))
    return found


ROUTES = _api_routes()


def test_every_route_of_the_api_is_a_read_or_a_write() -> None:
    writes = {(m, p) for m, p, write in ROUTES if write}
    assert writes == {
        ("POST", f"{API}/runs"),
        ("POST", f"{API}/runs/import"),
        ("POST", f"{API}/runs/{{run_id}}/readings"),
        ("PATCH", f"{API}/runs/{{run_id}}/readings/{{group}}/{{index}}"),
        ("DELETE", f"{API}/runs/{{run_id}}/readings/{{group}}/{{index}}"),
        ("POST", f"{API}/runs/{{run_id}}/finish"),
        ("POST", f"{API}/runs/{{run_id}}/abort"),
        ("PUT", f"{API}/runs/{{run_id}}/notes"),
        ("PUT", f"{API}/runs/{{run_id}}/sketches/{{item}}"),
        ("POST", f"{API}/series"),
        ("POST", f"{API}/series/{{series_id}}/runs"),
        ("DELETE", f"{API}/series/{{series_id}}/runs/{{run_id}}"),
    }
    assert len(ROUTES) > 15


def _without_key(client: TestClient, method: str, path: str, run_id: str, **headers: str) -> Any:
    """The route asked with a malformed body and query, as a client without a key."""
    url = path.replace("{run_id}", run_id).replace("{kind}", "smts2")
    return client.request(
        method,
        url + "?seq=x&limit=-1&group=" + "g" * 500 + "&format=nonsense&from=-3",
        content=b'{"stand": ',
        headers={"content-type": "application/json", **headers},
    )


#: Every route with reads behind a key, and the writes with public reads.
KEYED = [
    pytest.param(public, method, path, id=f"{method} {path}{', public reads' * public}")
    for public in (False, True)
    for method, path, write in ROUTES
    if write or not public
]


@pytest.mark.parametrize(("public", "method", "path"), KEYED)
def test_without_a_key_a_route_says_401_and_nothing_else(
    public: bool, method: str, path: str
) -> None:
    """No validation detail, and the same answer for a real run and a made-up one."""
    with TestClient(_app(public_reads=public), raise_server_exceptions=False) as client:
        _answers_401(client, method, path)


def _answers_401(client: TestClient, method: str, path: str) -> None:
    real = open_run_with(client, WRITER)
    for headers in ({}, {"Authorization": "Basic " + WRITER}, {"Authorization": "Bearer"}):
        answers = [_without_key(client, method, path, run, **headers) for run in (real, MADE_UP)]
        for r in answers:
            assert r.status_code == 401, r.text
            assert is_problem(r)
            assert r.json()["title"] == "API key required"
            assert r.headers["www-authenticate"] == "Bearer"
        assert answers[0].json() == answers[1].json()
    # a key this server does not know: 401 too, whatever the route
    for run in (real, MADE_UP):
        r = _without_key(client, method, path, run, **auth("unknown-key-" + "a" * 20))
        assert r.status_code == 401
        assert r.json()["title"] == "Unknown API key"


def open_run_with(client: TestClient, key: str, stand: str = "smts2", **headers: str) -> str:
    r = client.post(
        f"{API}/runs",
        json={"stand": stand, "operator": "Sidorov"},
        headers={**auth(key), **headers},
    )
    assert r.status_code in (200, 201), r.text
    return str(r.json()["id"])


#: The header of a JSON body (without it the body is refused 415, naming the header).
JSON = {"Content-Type": "application/json"}


def test_public_reads_need_no_key_but_writes_do() -> None:
    with TestClient(_app(public_reads=True), raise_server_exceptions=False) as client:
        assert client.get(f"{API}/stands").status_code == 200
        assert client.get(f"{API}/runs/{MADE_UP}").status_code == 404
        assert client.post(f"{API}/runs/{MADE_UP}/finish").status_code == 401
        r = client.post(f"{API}/models/bearing/friction", content=b"{", headers=JSON)
        assert r.status_code == 422  # a calculator is a read


def test_then_parse_then_the_stand_scope(client: TestClient) -> None:
    smts2 = open_run_with(client, WRITER)
    # POST /runs: a read-only key gets the body's 422 first, then 403 for a good body
    r = client.post(f"{API}/runs", content=b'{"stand": ', headers={**auth(READER), **JSON})
    assert r.status_code == 422
    r = client.post(f"{API}/runs", json={"stand": "smts2", "operator": "x"}, headers=auth(READER))
    assert (r.status_code, "write:smts2" in r.json()["detail"]) == (403, True)
    # readings: the query of the binary form is parsed, then the run's stand is the scope
    npz = {**auth(MTOS_ONLY), "content-type": "application/x-npz"}
    r = client.post(f"{API}/runs/{smts2}/readings?seq=x&group=friction", headers=npz)
    assert r.status_code == 422
    r = client.post(f"{API}/runs/{smts2}/readings?seq=0&group=friction", headers=npz)
    assert (r.status_code, "write:smts2" in r.json()["detail"]) == (403, True)
    r = client.post(
        f"{API}/runs/{smts2}/readings", json=json_batch(0, 0, 3), headers=auth(MTOS_ONLY)
    )
    assert r.status_code == 403
    for end in ("finish", "abort"):
        assert client.post(f"{API}/runs/{smts2}/{end}", headers=auth(MTOS_ONLY)).status_code == 403
    # a key that may write learns that a made-up run is none
    r = client.post(
        f"{API}/runs/{MADE_UP}/readings", json=json_batch(0, 0, 3), headers=auth(WRITER)
    )
    assert r.status_code == 404


def test_an_idempotency_key_belongs_to_the_api_key_that_sent_it(client: TestClient) -> None:
    """Another lab PC sending the same Idempotency-Key opens a run of its own: it never
    learns the id of the first PC's run, nor that the key was used (no 409)."""
    once = {"Idempotency-Key": "retry-me-1"}
    first = open_run_with(client, WRITER, **once)
    assert open_run_with(client, WRITER, **once) == first  # a retry of the same PC
    other = open_run_with(client, OTHER_WRITER, **once)
    assert other != first
    assert open_run_with(client, OTHER_WRITER, **once) == other  # its own retries hold
    mtos = open_run_with(client, MTOS_ONLY, "mtos", **once)  # other values, other stand
    assert mtos not in (first, other)
    # the same PC asking for other values with its key: 409, naming only its own key
    r = client.post(
        f"{API}/runs", json={"stand": "mtos", "operator": "x"}, headers={**auth(WRITER), **once}
    )
    assert r.status_code == 409
    assert "retry-me-1" in r.json()["detail"]
    assert mtos not in r.text and other not in r.text


@pytest.mark.parametrize(
    "authorization",
    [
        lambda: "Token " + secrets.token_hex(8),
        lambda: "Basic " + secrets.token_hex(8),
        lambda: "Bearer " + secrets.token_hex(16),
        lambda: secrets.token_hex(8),
    ],
    ids=["random scheme", "basic", "random bearer tokens", "no scheme"],
)
def test_no_authorization_header_escapes_the_rate_limit(tmp_path: Path, authorization: Any) -> None:
    """Requests without a key this server knows share their address's bucket."""
    app = hdf5_app(tmp_path / "data", rate_limit=0.5, rate_burst=3)
    with TestClient(app, raise_server_exceptions=False) as client:
        codes = [
            client.get(f"{API}/stands", headers={"Authorization": authorization()}).status_code
            for _ in range(5)
        ]
        assert codes[:3] == [401, 401, 401]  # the burst (answered: they present no key)
        assert codes[3:] == [429, 429]
        # a key has a bucket of its own, whatever the address did
        assert client.get(f"{API}/stands", headers=auth(READER)).status_code == 200


def test_a_key_has_one_bucket_whatever_it_says_besides() -> None:
    with TestClient(_app(rate_limit=0.5, rate_burst=3), raise_server_exceptions=False) as client:
        spellings = ["Bearer ", "bearer ", "BEARER ", "Bearer  "]
        codes = [
            client.get(f"{API}/stands", headers={"Authorization": s + READER}).status_code
            for s in spellings
        ]
        assert codes == [200, 200, 200, 429]


@pytest.mark.parametrize(
    "headers",
    [
        {"Origin": "http://evil.example"},
        {"Origin": "null"},
        {"Origin": "http://[broken"},
        {"Origin": "http://testserver.evil.example"},
        {"Sec-Fetch-Site": "cross-site"},
        {"Sec-Fetch-Site": "same-site"},
        {"Sec-Fetch-Site": "cross-site", "Origin": "http://testserver"},
    ],
)
@pytest.mark.parametrize("path", ["/login", "/logout"])
def test_login_and_logout_refuse_other_sites_forms(
    tmp_path: Path, path: str, headers: dict[str, str]
) -> None:
    with TestClient(hdf5_app(tmp_path / "data"), raise_server_exceptions=False) as client:
        r = client.post(path, data={"key": READER, "next": "/"}, headers=headers)
        assert r.status_code == 403, r.text
        assert is_problem(r)
        assert "rig_session" not in r.headers.get("set-cookie", "")


@pytest.mark.parametrize(
    "headers",
    [
        {},  # no browser
        {"Origin": "http://testserver", "Sec-Fetch-Site": "same-origin"},
        {"Sec-Fetch-Site": "none"},  # typed by the user
    ],
)
def test_login_takes_this_sites_own_forms(tmp_path: Path, headers: dict[str, str]) -> None:
    with TestClient(hdf5_app(tmp_path / "data"), raise_server_exceptions=False) as client:
        r = client.post(
            "/login", data={"key": READER, "next": "/"}, headers=headers, follow_redirects=False
        )
        assert r.status_code == 303
        assert "rig_session" in r.headers["set-cookie"]
        r = client.post("/logout", headers=headers, follow_redirects=False)
        assert r.status_code == 303


def _scripts(html: str) -> list[tuple[str, str]]:
    """(attributes, content) of every <script> of a page."""
    return re.findall(r"<script([^>]*)>(.*?)</script>", html, re.DOTALL)


def _directives(policy: str) -> dict[str, list[str]]:
    found = {}
    for part in policy.split(";"):
        name, *values = part.split()
        found[name] = values
    return found


@pytest.fixture
def site(tmp_path: Path) -> Iterator[tuple[TestClient, str]]:
    with TestClient(hdf5_app(tmp_path / "data"), raise_server_exceptions=False) as client:
        run_id = open_run(client)
        client.post(
            f"{API}/runs/{run_id}/readings", json=json_batch(0, 0, 20), headers=auth(WRITER)
        )
        client.post("/login", data={"key": READER, "next": "/"})  # a session for the pages
        yield client, run_id


PAGES = ["/", "/runs/{run_id}", "/login", "/docs", "/redoc", f"{API}/runs/{{run_id}}/report.html"]


@pytest.mark.parametrize("path", PAGES)
def test_pages_say_what_a_browser_may_run(site: tuple[TestClient, str], path: str) -> None:
    """Every script of a page is a file of this server, or an inline script whose hash
    the policy names; no page is framed by another site; nothing is sniffed."""
    client, run_id = site
    r = client.get(path.replace("{run_id}", run_id), headers=auth(READER))
    assert r.status_code == 200, r.text
    assert r.headers["content-type"].startswith("text/html")
    assert r.headers["x-content-type-options"] == "nosniff"
    policy = _directives(r.headers["content-security-policy"])
    assert policy["frame-ancestors"] == ["'none'"]
    assert policy["default-src"] == ["'none'"]
    scripts = policy.get("script-src", [])
    assert "'unsafe-inline'" not in scripts and "'unsafe-eval'" not in scripts
    for attributes, content in _scripts(r.text):
        if "src=" in attributes:
            source = re.search(r'src="(https://[^/"]+)?/', attributes)
            assert source is not None, attributes
            assert (source[1] or "'self'") in scripts, attributes
        elif 'type="application/json"' not in attributes:  # a data block runs nothing
            digest = base64.b64encode(hashlib.sha256(content.encode()).digest()).decode()
            assert f"'sha256-{digest}'" in scripts


@pytest.mark.parametrize(
    "path", [f"{API}/stands", f"{API}/runs/{{run_id}}/readings?format=csv&group=friction", "/x"]
)
def test_every_answer_is_nosniff_and_unframed(site: tuple[TestClient, str], path: str) -> None:
    client, run_id = site
    r = client.get(path.replace("{run_id}", run_id), headers=auth(READER))
    assert r.headers["x-content-type-options"] == "nosniff"
    assert _directives(r.headers["content-security-policy"])["default-src"] == ["'none'"]
    assert "frame-ancestors 'none'" in r.headers["content-security-policy"]
