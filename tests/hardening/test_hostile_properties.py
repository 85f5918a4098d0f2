"""Hypothesis sends hostile values across the API: NaN, infinities, literals beyond a
double, whole numbers beyond 64 bits, NUL characters, lone surrogates, duplicated keys,
values as text or flags, arrays nested hundreds of levels deep. Whatever comes, the service
never answers 5xx, stores nothing it refused (no flag or text taken for a configured
number), and every run it stored stays readable, also after a restart of the server
process (a clean stop or a kill) on the same data directory. A user's text is never
evaluated where it is shown: in a plot (mathtext) or a CSV cell (a formula)."""

from __future__ import annotations

import json
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest
from fastapi.testclient import TestClient
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.stateful import (
    Bundle,
    RuleBasedStateMachine,
    consumes,
    initialize,
    invariant,
    rule,
)

from rigserver.api.examples import example_archive
from rigserver.reports.eln import ELN_MEDIA_TYPE
from rigserver.reports.formatting import spreadsheet_text
from rigserver.reports.series_plots import Curve, overlay
from schemas.stands import DECLARATIONS, StandKind
from schemas.strict_json import MAX_DEPTH
from tests.api.conftest import READER, WRITER, Server, auth
from tests.api.test_profile_robustness import posted_profiles
from tests.eln.conftest import members, resealed, rezip
from tests.hardening.conftest import API, keys_file
from tests.hardening.test_lying_archives import Member
from tests.hardening.test_lying_archives import archive as lying_archive

# --- hostile JSON, written as raw text (Python's json cannot write 1e400 or a duplicate) --

_HOSTILE_CHARS = st.one_of(
    st.characters(codec="utf-8"),
    st.sampled_from(["\x00", "\ud800", "\udfff", "\ud83d", "\u0661", "\uff11"]),
)
_TEXT = st.text(_HOSTILE_CHARS, max_size=8)
#: A JSON number, string, flag or null, as JSON text.
_LEAF = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(json.dumps),  # NaN, Infinity literals
    st.integers(min_value=-(2**70), max_value=2**70).map(str),
    st.sampled_from(["1e400", "-1e400", "1E999", "-0", "0.5", "300", "1000", "true", "null"]),
    _TEXT.map(json.dumps),  # lone surrogates as \\ud800 escapes
    _TEXT.map(lambda s: json.dumps(s.lstrip("-") or "1.5")),  # numbers as text
    st.integers(MAX_DEPTH - 2, 1200).map(lambda d: "[" * d + "1" + "]" * d),  # deep nesting
)


def _object(keys: st.SearchStrategy[str], values: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    """A JSON object as text; a key may come twice."""
    pairs = st.lists(st.tuples(keys, values), max_size=4)
    return pairs.map(lambda kv: "{" + ",".join(f"{json.dumps(k)}:{v}" for k, v in kv) + "}")


_ARRAY = st.lists(_LEAF, max_size=4).map(lambda items: "[" + ",".join(items) + "]")


@st.composite
def run_bodies(draw: st.DrawFn) -> tuple[str, bytes]:
    """A body of POST /runs: a real stand, hostile values in its free fields and overrides."""
    stand = draw(st.sampled_from(list(StandKind)))
    config_keys = st.sampled_from(sorted(DECLARATIONS[stand].configuration.model_fields)) | _TEXT
    fields = {
        "stand": json.dumps(stand.value),
        "operator": draw(st.just('"Ivanova"') | _LEAF),
        "title": draw(st.just('""') | _LEAF),
        "specimen": draw(_object(st.sampled_from(["pin", "disc"]) | _TEXT, _LEAF)),
        "test_plan": draw(_object(st.sampled_from(["steps", "mode"]) | _TEXT, _LEAF | _ARRAY)),
        "configuration": draw(st.just("{}") | _object(config_keys, _LEAF | _ARRAY)),
    }
    chosen = draw(st.lists(st.sampled_from(sorted(fields)), unique=True))
    keys = ["stand", "operator", *(k for k in chosen if k not in ("stand", "operator"))]
    body = "{" + ",".join(f'"{k}":{fields[k]}' for k in keys) + "}"
    return stand.value, body.encode("utf-8", "surrogatepass")


_CHANNELS = ["time", "load", "speed", "friction_moment", "revolutions"]


@st.composite
def batches(draw: st.DrawFn, seq: int) -> bytes:
    """A JSON batch of the SMTs-2 friction record, good or with hostile values in it."""
    rows = draw(st.integers(1, 3))
    good = {
        "time": [float(seq * 10 + k) for k in range(rows)],
        "load": [300.0] * rows,
        "speed": [1000.0] * rows,
        "friction_moment": [2.5] * rows,
        "revolutions": [float(seq)] * rows,
    }
    columns = [f'"{n}":{json.dumps(v)}' for n, v in good.items()]
    if draw(st.booleans()):  # spoil one value, or add a channel, or a key twice
        i = draw(st.integers(0, len(columns) - 1))
        name = _CHANNELS[i]
        columns[i] = draw(
            st.one_of(
                _ARRAY.map(lambda a, n=name: f'"{n}":{a}'),
                st.just(columns[i] + "," + columns[i]),
                _TEXT.map(lambda t, c=columns[i]: f"{c},{json.dumps(t)}:[1]"),
            )
        )
    seq_text = draw(st.just(str(seq)) | st.sampled_from([f'"{seq}"', "true", f"{seq}.0"]))
    body = f'{{"seq":{seq_text},"group":"friction","columns":{{{",".join(columns)}}}}}'
    return body.encode("utf-8", "surrogatepass")


# --- stateless: in process, over the HDF5 store ---------------------------------------------


@settings(max_examples=80, deadline=None, suppress_health_check=list(HealthCheck))
@given(run_bodies())
def test_opening_runs_with_hostile_values(
    hdf5_client: TestClient, opened: tuple[str, bytes]
) -> None:
    _, body = opened
    before = hdf5_client.get(f"{API}/runs", headers=auth(READER)).json()["total"]
    headers = {**auth(WRITER), "content-type": "application/json"}
    r = hdf5_client.post(f"{API}/runs", content=body, headers=headers)
    assert r.status_code in (201, 422), r.text
    r.json()  # it renders
    listed = hdf5_client.get(f"{API}/runs", headers=auth(READER))
    assert listed.status_code == 200
    assert listed.json()["total"] == before + (r.status_code == 201)
    assert all(run["damage"] is None for run in listed.json()["runs"])
    if r.status_code == 201:
        _no_flag_or_text_for_a_number(opened)
        run_id = r.json()["id"]
        assert hdf5_client.get(f"{API}/runs/{run_id}", headers=auth(READER)).status_code == 200
        assert hdf5_client.get(f"/runs/{run_id}", headers=auth(READER)).status_code == 200
        assert hdf5_client.get("/", headers=auth(READER)).status_code == 200


def _no_flag_or_text_for_a_number(opened: tuple[str, bytes]) -> None:
    """A run taken was sent a number (never ``true`` or ``"20"``) for every number of its
    stand's configuration it overrides."""
    stand, body = opened
    defaults = DECLARATIONS[StandKind(stand)].configuration().model_dump()
    for name, value in json.loads(body).get("configuration", {}).items():
        if isinstance(defaults.get(name), float):
            assert isinstance(value, int | float) and not isinstance(value, bool), (name, value)


@settings(max_examples=60, deadline=None)
@given(st.text(_HOSTILE_CHARS, max_size=30))
def test_a_users_text_is_never_a_formula_in_a_csv_cell(text: str) -> None:
    cell = spreadsheet_text(text)
    assert cell in (text, "'" + text)
    if cell == text and text:  # left alone: no spreadsheet takes it for a formula
        stripped = text.lstrip(" \t\r\n")
        assert text[0] not in "\t\r"
        if stripped.startswith(("=", "+", "-", "@")):  # only a number is left so
            float(text.replace(",", "."))


@pytest.mark.filterwarnings("ignore:Glyph .* missing from font")  # a box is drawn for it
@settings(max_examples=25, deadline=None)
@given(st.lists(st.text(_HOSTILE_CHARS, min_size=1, max_size=12), min_size=1, max_size=3))
def test_any_levels_are_drawn_as_written(levels: list[str]) -> None:
    x = np.linspace(0.0, 1.0, 4)
    curves = [Curve("a", x, x), Curve("b", x, x + 0.1)]
    overlay(dict.fromkeys(levels, curves), xlabel="L, m", ylabel="f", mean_label="mean f_э")


# --- hostile archives: the OpenAPI example's run, spoilt ---------------------------------


def _spoilt_run(change: Callable[[dict[str, Any]], None]) -> Callable[[bytes], bytes]:
    def spoil(archive: bytes) -> bytes:
        files = members(archive)
        name = next(n for n in files if n.endswith("/run.json"))
        run = json.loads(files[name])
        change(run)
        files[name] = json.dumps(run).encode()
        return rezip(resealed(files))

    return spoil


def _deep_metadata(archive: bytes) -> bytes:
    files = members(archive)
    name = next(n for n in files if n.endswith("/ro-crate-metadata.json"))
    deep = "[" * 3000 + "]" * 3000
    graph = f'"@graph": [{{"@id": "#x", "x": {deep}}},'.encode()
    files[name] = files[name].replace(b'"@graph": [', graph)
    return rezip(files)


def _bomb(archive: bytes) -> bytes:
    """The run file declared 1 KB, inflating to 8 MiB (its metadata agreeing with 1 KB)."""
    files = members(archive)
    name = next(n for n in files if n.endswith(".h5"))
    real = files[name] + b"\0" * (8 << 20)
    files[name] = real[:1000]
    files = resealed(files)
    return lying_archive(
        *(
            Member(n, real, deflate=True, file_size=1000) if n == name else Member(n, data)
            for n, data in files.items()
        )
    )


#: What an import is sent: the archive as it is, or spoilt (each refused with 422).
ARCHIVES: dict[str, Callable[[bytes], bytes]] = {
    "honest": lambda a: a,
    "deep run.json": _spoilt_run(lambda r: r.update(deep=json.loads("[" * 200 + "]" * 200))),
    "a title of 1 MiB": _spoilt_run(lambda r: r.update(title="t" * (1 << 20))),
    "a specimen of 10 000 keys": _spoilt_run(
        lambda r: r.update(specimen={f"k{i}": i for i in range(10_000)})
    ),
    "deep metadata": _deep_metadata,
    "a zip bomb": _bomb,
}


# --- stateful: a real server process, restarted on its data directory ------------------------


class HostileClients(RuleBasedStateMachine):
    """Open runs, post, finish, abort, read, restart; the server's answers and what it
    stored are held against what it acknowledged."""

    runs = Bundle("runs")

    def __init__(self) -> None:
        super().__init__()
        self.tmp = Path(tempfile.mkdtemp(prefix="rig-hostile-"))
        self.server = Server(self.tmp / "data", keys_file(self.tmp))
        self.server.start()
        self.http = httpx.Client(base_url=self.server.url, timeout=60)
        #: run id -> rows of the friction record acknowledged; its state
        self.rows: dict[str, int] = {}
        self.state: dict[str, str] = {}
        self.next_seq: dict[str, int] = {}
        #: runs acknowledged, of any stand
        self.opened = 0

    def teardown(self) -> None:
        self.http.close()
        self.server.stop()
        shutil.rmtree(self.tmp, ignore_errors=True)

    def _answer(self, r: httpx.Response) -> httpx.Response:
        assert r.status_code < 500, (r.request.method, r.request.url, r.status_code, r.text)
        return r

    @initialize(target=runs)
    def a_sound_run(self) -> str:
        r = self._answer(
            self.http.post(
                f"{API}/runs", json={"stand": "smts2", "operator": "x"}, headers=auth(WRITER)
            )
        )
        assert r.status_code == 201
        return self._opened(r.json()["id"])

    def _opened(self, run_id: str) -> str:
        self.opened += 1
        self.rows[run_id], self.state[run_id], self.next_seq[run_id] = 0, "open", 0
        return run_id

    @rule(target=runs, opened=run_bodies())
    def open_run(self, opened: tuple[str, bytes]) -> str:
        headers = {**auth(WRITER), "content-type": "application/json"}
        r = self._answer(self.http.post(f"{API}/runs", content=opened[1], headers=headers))
        assert r.status_code in (201, 422), r.text
        if r.status_code == 201 and opened[0] == "smts2":
            return self._opened(r.json()["id"])
        self.opened += r.status_code == 201
        return next(iter(self.rows))  # a run refused adds nothing: post to the first one

    @rule(run_id=runs, data=st.data())
    def post(self, run_id: str, data: st.DataObject) -> None:
        seq = self.next_seq[run_id]
        body = data.draw(batches(seq))
        headers = {**auth(WRITER), "content-type": "application/json"}
        r = self._answer(
            self.http.post(f"{API}/runs/{run_id}/readings", content=body, headers=headers)
        )
        if r.status_code == 201:
            assert self.state[run_id] == "open"
            self.rows[run_id] += r.json()["rows"]
            self.next_seq[run_id] = seq + 1
        else:
            assert r.status_code in (409, 422), r.text

    @rule(run_id=consumes(runs), end=st.sampled_from(["finish", "abort"]))
    def end(self, run_id: str, end: str) -> None:
        r = self._answer(self.http.post(f"{API}/runs/{run_id}/{end}", headers=auth(WRITER)))
        if r.status_code == 200:
            assert self.state[run_id] == "open"
            self.state[run_id] = "finished" if end == "finish" else "aborted"
        else:  # ended before, or too few readings for the results
            assert r.status_code in (409, 422), r.text

    @rule(profile=posted_profiles())
    def a_profile_finishes(self, profile: tuple[list[float], list[float]]) -> None:
        """A profile the post accepts finishes and exports, whatever its heights' magnitude
        or its gaps (issue 39: 1e-300 µm once left its run open for ever, a gap made the
        finish and the X3P grow with the span of x)."""
        opened = self._answer(
            self.http.post(
                f"{API}/runs", json={"stand": "profilometer", "operator": "x"}, headers=auth(WRITER)
            )
        )
        assert opened.status_code == 201
        self.opened += 1
        run_id = opened.json()["id"]
        body = {"seq": 0, "group": "profile", "columns": {"x": profile[0], "y": profile[1]}}
        posted = self.http.post(f"{API}/runs/{run_id}/readings", json=body, headers=auth(WRITER))
        assert self._answer(posted).status_code == 201
        finished = self.http.post(f"{API}/runs/{run_id}/finish", headers=auth(WRITER))
        assert self._answer(finished).status_code == 200, finished.text
        x3p = self.http.get(f"{API}/runs/{run_id}/profile.x3p", headers=auth(READER))
        assert self._answer(x3p).status_code == 200

    @rule(run_id=runs)
    def read(self, run_id: str) -> None:
        for path in ("", "/results", "/readings?group=friction", "/report.html"):
            self._answer(self.http.get(f"{API}/runs/{run_id}{path}", headers=auth(READER)))
        assert (
            self._answer(self.http.get(f"/runs/{run_id}", headers=auth(READER))).status_code == 200
        )

    @rule(
        query=st.sampled_from(
            [
                "since=0001-01-01T00:00:00%2B01:00",
                "limit=%D9%A1",
                "offset=" + "9" * 5000,
                "operator=%00",
                "until=9999-12-31T23:59:59-01:00",
            ]
        )
    )
    def hostile_list(self, query: str) -> None:
        assert (
            self._answer(self.http.get(f"{API}/runs?{query}", headers=auth(READER))).status_code
            == 422
        )

    @rule(kind=st.sampled_from(sorted(ARCHIVES)))
    def import_archive(self, kind: str) -> None:
        body = ARCHIVES[kind](example_archive())
        headers = {**auth(WRITER), "content-type": ELN_MEDIA_TYPE}
        r = self._answer(self.http.post(f"{API}/runs/import", content=body, headers=headers))
        if kind == "honest":
            assert r.status_code == 201, r.text
            self.opened += 1
        else:
            assert r.status_code == 422, r.text[:500]

    @rule(kill=st.booleans())
    def restart(self, kill: bool) -> None:
        (self.server.kill if kill else self.server.stop)()
        self.server.start()

    @invariant()
    def stored_runs_stay_readable(self) -> None:
        listed = self._answer(self.http.get(f"{API}/runs?limit=500", headers=auth(READER)))
        assert listed.status_code == 200
        runs = {run["id"]: run for run in listed.json()["runs"]}
        assert listed.json()["total"] == self.opened  # nothing refused was stored
        for run_id, rows in self.rows.items():
            run = runs[run_id]
            assert run["damage"] is None
            assert run["rows"]["friction"] == rows
            assert run["state"] == self.state[run_id]
        assert self._answer(self.http.get("/", headers=auth(READER))).status_code == 200


HostileClients.TestCase.settings = settings(
    max_examples=3,
    stateful_step_count=10,
    deadline=None,
    suppress_health_check=list(HealthCheck),
)
TestHostileClients = HostileClients.TestCase
