"""Hypothesis drives a lab PC's client through the faults between it and the server: a
proxy's error pages, an HTML page where the receipt should be, timeouts, answers lost after
the server stored the batch, keys changed on the server, the agent restarted with another
key. Whatever comes, every batch the spool acknowledged reaches the server exactly once, in
order; no run is refused or stranded; once the faults stop, everything drains.

(Header changes and poison lines in a stand's file have their own machine.)
"""

from __future__ import annotations

import io
import json
import shutil
import tempfile
import threading
from pathlib import Path
from typing import Any

import httpx
import numpy as np
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from hypothesis.stateful import Bundle, RuleBasedStateMachine, invariant, rule

from rigclient import Client, RetryPolicy, RunHandle
from tests.rigclient.fake import problem

FAST = RetryPolicy(base_delay=0.005, max_delay=0.02)
KEYS = ("key-one", "key-two")
#: What the path to the server does to a request while the fault lasts.
FAULTS = ("proxy 500", "proxy 502", "html 200", "timeout", "answer lost", "stored, then 500")


def html(status: int, title: str) -> httpx.Response:
    page = f"<html><head><title>{title}</title></head><body>{title}</body></html>"
    return httpx.Response(status, text=page, headers={"content-type": "text/html"})


class LabServer:
    """Enough of rigserver for the client: runs opened once per Idempotency-Key, readings
    stored once per seq (a retry answered as a duplicate), finish; keys; and a fault."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.runs: dict[str, dict[str, Any]] = {}
        self.by_key: dict[str, str] = {}
        self.accepted: set[str] = {KEYS[0]}
        self.fault: str | None = None
        self.misordered: list[str] = []

    def __call__(self, request: httpx.Request) -> httpx.Response:
        with self.lock:
            fault = self.fault
            if fault in ("proxy 500", "proxy 502", "html 200", "timeout"):
                if fault == "timeout":
                    raise httpx.ReadTimeout("no answer", request=request)
                status = {"proxy 500": 500, "proxy 502": 502, "html 200": 200}[fault]
                return html(status, f"{status} from the proxy")
            answer = self._handle(request)
            if fault == "answer lost":
                raise httpx.ReadError("connection reset by peer", request=request)
            if fault == "stored, then 500":
                return html(500, "500 Internal Server Error")
            return answer

    def _run_json(self, run_id: str) -> dict[str, Any]:
        run = self.runs[run_id]
        return {
            "id": run_id,
            "stand": "profilometer",
            "state": run["state"],
            "operator": "test",
            "title": run["title"],
            "configuration": {},
            "created": "2026-11-22T11:40:26Z",
        }

    def _handle(self, request: httpx.Request) -> httpx.Response:
        key = request.headers.get("authorization", "").removeprefix("Bearer ")
        if key not in self.accepted:
            return problem(401, "Unauthorized", "the API key is not known")
        path = request.url.path.removeprefix("/api/v1")
        if path == "/runs" and request.method == "POST":
            opening = request.headers["idempotency-key"]
            if opening not in self.by_key:
                run_id = f"20261122T1140{len(self.runs):02d}Z-1a2b3c4d"
                self.by_key[opening] = run_id
                title = json.loads(request.content)["title"]
                self.runs[run_id] = {"state": "open", "title": title, "stored": []}
            return httpx.Response(201, json=self._run_json(self.by_key[opening]))
        run_id, _, tail = path.removeprefix("/runs/").partition("/")
        run = self.runs.get(run_id)
        if run is None:
            return problem(404, "Not found", f"no run {run_id}")
        if tail == "readings":
            seq = int(request.url.params["seq"])
            with np.load(io.BytesIO(request.content)) as npz:
                x = npz["x"].tolist()
            stored = dict(run["stored"])
            if seq in stored:
                assert stored[seq] == x, "a seq sent again with other readings"
                duplicate = True
            elif run["state"] != "open":
                return problem(409, "Run is not open", f"run {run_id} is {run['state']}")
            else:
                if run["stored"] and seq <= run["stored"][-1][0]:
                    self.misordered.append(f"{run_id}: seq {seq} after {run['stored'][-1][0]}")
                run["stored"].append((seq, x))
                duplicate = False
            receipt = {
                "run_id": run_id,
                "seq": seq,
                "group": "profile",
                "rows": len(x),
                "group_rows": sum(len(v) for _, v in run["stored"]),
                "duplicate": duplicate,
            }
            return httpx.Response(200 if duplicate else 201, json=receipt)
        if tail == "finish":
            if run["state"] != "open":
                return problem(409, "Run is not open", f"run {run_id} is {run['state']}")
            run["state"] = "finished"
            return httpx.Response(200, json=self._run_json(run_id))
        if tail == "":
            return httpx.Response(200, json=self._run_json(run_id))
        return problem(404, "Not found", path)

    def stored(self) -> dict[str, tuple[str, list[float]]]:
        """Title -> (state, the x values stored, in the order they arrived)."""
        with self.lock:
            return {
                run["title"]: (run["state"], [v for _, xs in run["stored"] for v in xs])
                for run in self.runs.values()
            }


class ClientFaults(RuleBasedStateMachine):
    """Runs opened, batches posted and runs finished through a client, while the path to
    the server fails in the ways a lab network does and keys change."""

    runs = Bundle("runs")

    def __init__(self) -> None:
        super().__init__()
        self.tmp = Path(tempfile.mkdtemp(prefix="rig-client-faults-"))
        self.server = LabServer()
        self.key = KEYS[0]
        self.client = self._start()
        #: title -> the x values acknowledged by the spool, in order; finished titles
        self.posted: dict[str, list[float]] = {}
        self.finished: set[str] = set()
        self.handles: dict[str, str] = {}  # title -> local id
        self.next_x = 0.0

    def _start(self) -> Client:
        return Client(
            "http://rig.test",
            self.key,
            spool=self.tmp,
            transport=httpx.MockTransport(self.server),
            retry=FAST,
        )

    def _handle(self, title: str) -> RunHandle:
        return self.client.run(self.handles[title])

    @rule(target=runs)
    def open_run(self) -> str:
        title = f"run {len(self.posted)}"
        self.handles[title] = self.client.open_run(
            stand="profilometer", operator="test", title=title
        ).local_id
        self.posted[title] = []
        return title

    @rule(title=runs, rows=st.integers(1, 5))
    def post(self, title: str, rows: int) -> None:
        if title in self.finished:
            return
        x = self.next_x + np.arange(rows, dtype=float)
        self.next_x += rows
        self._handle(title).post("profile", {"x": x, "y": np.zeros(rows)})
        self.posted[title].extend(x.tolist())  # acknowledged: durable in the spool

    @rule(title=runs)
    def finish(self, title: str) -> None:
        if title not in self.finished:
            self._handle(title).finish()
            self.finished.add(title)

    @rule(fault=st.sampled_from((None, *FAULTS)))
    def the_path_fails(self, fault: str | None) -> None:
        with self.server.lock:
            self.server.fault = fault

    @rule(keys=st.sampled_from([(KEYS[0],), (KEYS[1],), KEYS]))
    def the_server_changes_its_keys(self, keys: tuple[str, ...]) -> None:
        with self.server.lock:
            self.server.accepted = set(keys)

    @rule(key=st.sampled_from(KEYS))
    def the_agent_restarts_with_a_key(self, key: str) -> None:
        self.client.close()
        self.key = key
        self.client = self._start()

    @rule(seconds=st.sampled_from([0.01, 0.05, 0.2]))
    def time_passes(self, seconds: float) -> None:
        threading.Event().wait(seconds)

    @invariant()
    def stored_once_in_order_and_nothing_stranded(self) -> None:
        assert not self.server.misordered, self.server.misordered
        for title, (_, values) in self.server.stored().items():
            posted = self.posted[title]
            assert values == posted[: len(values)], (title, values, posted)
        stopped = self.client.status().stopped
        assert not stopped, [(r.refused, r.damaged) for r in stopped]

    def teardown(self) -> None:
        try:
            with self.server.lock:
                self.server.fault = None
                self.server.accepted = {self.key}
            assert self.client.wait(30), self.client.status()
            stored = self.server.stored()
            for title, posted in self.posted.items():
                state, values = stored[title]
                assert values == posted, title  # every row, once, in order
                assert state == ("finished" if title in self.finished else "open"), title
        finally:
            self.client.close()
            shutil.rmtree(self.tmp, ignore_errors=True)


ClientFaults.TestCase.settings = settings(
    max_examples=12,
    stateful_step_count=25,
    deadline=None,
    suppress_health_check=list(HealthCheck),
)
TestClientFaults = ClientFaults.TestCase
