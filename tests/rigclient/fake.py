"""A fake rigserver for the client's tests: runs, readings stored once per seq, finish."""

from __future__ import annotations

import io
import json
from collections.abc import Callable

import httpx
import numpy as np

from schemas.readings import NPZ_MEDIA_TYPE

RUN_ID = "20261122T114026Z-1a2b3c4d"


class FakeServer:
    """Just enough of rigserver: runs, readings stored once per seq, finish, results."""

    def __init__(self) -> None:
        self.stored: dict[int, dict[str, list[float]]] = {}
        self.state = "open"
        self.calls: list[str] = []
        self.script: list[Callable[[httpx.Request], httpx.Response | None]] = []
        self.down = False  # True: every request meets a refused connection
        self.keys: list[str] = []  # the Idempotency-Keys of the openings

    def run_json(self) -> dict[str, object]:
        return {
            "id": RUN_ID,
            "stand": "profilometer",
            "state": self.state,
            "operator": "test",
            "configuration": {},
            "created": "2026-11-22T11:40:26Z",
        }

    def __call__(self, request: httpx.Request) -> httpx.Response:
        if self.down:
            raise httpx.ConnectError("connection refused", request=request)
        self.calls.append(f"{request.method} {request.url.path}")
        if self.script:
            answer = self.script.pop(0)(request)
            if answer is not None:
                return answer
        path = request.url.path
        if path == "/api/v1/runs":
            self.keys.append(request.headers.get("idempotency-key", ""))
            return httpx.Response(201, json=self.run_json())
        if path.endswith("/readings"):
            if request.headers["content-type"] == NPZ_MEDIA_TYPE:
                seq = int(request.url.params["seq"])
                group = request.url.params["group"]
                with np.load(io.BytesIO(request.content)) as npz:
                    columns = {k: npz[k].tolist() for k in npz.files}
            else:
                body = json.loads(request.content)
                seq, group, columns = body["seq"], body["group"], body["columns"]
            duplicate = seq in self.stored
            self.stored.setdefault(seq, columns)
            receipt = {
                "run_id": RUN_ID,
                "seq": seq,
                "group": group,
                "rows": len(next(iter(columns.values()))),
                "group_rows": 2 * len(self.stored),
                "duplicate": duplicate,
            }
            return httpx.Response(200 if duplicate else 201, json=receipt)
        if path.endswith("/finish"):
            if self.state != "open":
                return problem(409, "Run is not open", f"run {RUN_ID} is already finished")
            self.state = "finished"
            return httpx.Response(200, json=self.run_json())
        if path.endswith("/results"):
            return httpx.Response(200, json={"stand": "profilometer", "values": {}, "units": {}})
        if path == f"/api/v1/runs/{RUN_ID}":
            return httpx.Response(200, json=self.run_json())
        return problem(404, "Not found", path)


def problem(status: int, title: str, detail: str, **extra: object) -> httpx.Response:
    body = {"title": title, "status": status, "detail": detail, **extra}
    return httpx.Response(status, json=body, headers={"content-type": "application/problem+json"})


class Clock:
    """A clock that only moves when the client sleeps."""

    def __init__(self) -> None:
        self.now = 0.0
        self.sleeps: list[float] = []

    def sleep(self, seconds: float) -> None:
        self.sleeps.append(seconds)
        self.now += seconds

    def __call__(self) -> float:
        return self.now
