"""The ingest route handed straight to its endpoint (rigserver.api.ingest_lane)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from starlette.requests import Request
from starlette.responses import JSONResponse, PlainTextResponse, Response
from starlette.routing import Router
from starlette.types import Receive, Scope, Send

from rigserver.api.ingest_lane import IngestLane
from tests.api.conftest import WRITER, auth
from tests.hardening.conftest import API, hdf5_app, json_batch, open_run

PATH = "/api/v1/runs/{run_id}/readings"


class Refused(Exception):
    pass


class RefusedHere(Refused):
    pass


async def endpoint(request: Request) -> Response:
    run_id = request.path_params["run_id"]
    if run_id == "refused":
        raise RefusedHere("no")
    if run_id == "broken":
        raise KeyError("a bug")
    return PlainTextResponse(f"lane {run_id} {(await request.body()).decode()}")


async def inner(scope: Scope, receive: Receive, send: Send) -> None:
    await PlainTextResponse(f"router {scope['method']} {scope['path']}")(scope, receive, send)


def lane_client(handlers: dict[Any, Any]) -> TestClient:
    return TestClient(IngestLane(inner, PATH, endpoint, handlers))


def test_a_post_to_the_ingest_path_goes_to_the_endpoint() -> None:
    http = lane_client({})
    r = http.post("/api/v1/runs/20261127-ab/readings", content=b"body")
    assert r.text == "lane 20261127-ab body"


@pytest.mark.parametrize(
    ("method", "path"),
    [
        ("GET", "/api/v1/runs/r1/readings"),
        ("PUT", "/api/v1/runs/r1/readings"),
        ("POST", "/api/v1/runs/r1/readings/"),
        ("POST", "/api/v1/runs//readings"),
        ("POST", "/api/v1/runs/a/b/readings"),
        ("POST", "/api/v1/runs/r1/readingsx"),
        ("POST", "/api/v2/runs/r1/readings"),
        ("POST", "/api/v1/runs/readings"),
    ],
)
def test_anything_else_goes_to_the_router(method: str, path: str) -> None:
    # as the route's own pattern, run_id is one non-empty path segment
    r = lane_client({}).request(method, path)
    assert r.text == f"router {method} {path}"


def test_an_exception_is_answered_by_the_handler_of_its_nearest_class() -> None:
    async def refused(request: Request, exc: Exception) -> Response:
        return JSONResponse({"refused": str(exc)}, status_code=409)

    def anything(request: Request, exc: Exception) -> Response:  # a plain function too
        return JSONResponse({"anything": str(exc)}, status_code=500)

    r = lane_client({Refused: refused, Exception: anything}).post(PATH.format(run_id="refused"))
    assert (r.status_code, r.json()) == (409, {"refused": "no"})
    r = lane_client({RefusedHere: anything}).post(PATH.format(run_id="refused"))
    assert (r.status_code, r.json()) == (500, {"anything": "no"})


def test_an_exception_without_a_handler_goes_on_to_the_server_error_middleware() -> None:
    # the handler of Exception is the server-error middleware's, outside the lane
    with pytest.raises(KeyError, match="a bug"):
        lane_client({Exception: lambda r, e: None}).post(PATH.format(run_id="broken"))


def test_the_path_needs_one_run_id() -> None:
    with pytest.raises(ValueError, match="exactly one"):
        IngestLane(inner, "/api/v1/runs/readings", endpoint, {})
    with pytest.raises(ValueError, match="exactly one"):
        IngestLane(inner, "/api/v1/runs/{run_id}/{group}", endpoint, {})


def test_the_service_answers_posts_without_its_router(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    routed: list[str] = []
    real = Router.__call__

    async def counted(self: Router, scope: Scope, receive: Receive, send: Send) -> None:
        routed.append(f"{scope['method']} {scope['path']}")
        await real(self, scope, receive, send)

    with TestClient(hdf5_app(tmp_path / "data")) as http:
        run_id = open_run(http)
        monkeypatch.setattr(Router, "__call__", counted)
        path = f"{API}/runs/{run_id}/readings"
        r = http.post(path, json=json_batch(0, 0, 3), headers=auth(WRITER))
        assert r.status_code == 201, r.text
        assert routed == []
        # the lane's errors are the route's: problem+json from the app's handlers
        r = http.post(
            f"{API}/runs/no-such-run/readings", json=json_batch(0, 0, 1), headers=auth(WRITER)
        )
        assert (r.status_code, r.headers["content-type"]) == (404, "application/problem+json")
        r = http.post(path, content=b"x", headers={**auth(WRITER), "Content-Type": "text/csv"})
        assert (r.status_code, r.json()["title"]) == (415, "Unsupported media type")
        assert routed == []
        # the other method of the path is the router's, as is a 405
        read = http.get(path, params={"group": "friction"}, headers=auth(WRITER)).json()
        assert read["friction"]["columns"]["time"] == [0.0, 1.0, 2.0]
        r = http.put(path, headers=auth(WRITER))
        assert (r.status_code, r.headers["allow"]) == (405, "GET, POST")
        assert routed == [f"GET {path}", f"PUT {path}"]
