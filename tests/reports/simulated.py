"""Simulated runs (rigsim) as the reports see them, and the tables of a rendered report.

Shared by ``tests/reports`` and ``tests/web``: :func:`simulated` runs a stand's simulator
and the analysis once per stand and seed; :func:`post` sends a simulated run to an app.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from functools import lru_cache
from html.parser import HTMLParser
from typing import Any

import httpx
import numpy as np
from fastapi.testclient import TestClient
from numpy.typing import NDArray

from rigserver.analysis import AnalysisResult, analyse
from rigsim.batches import SimulatedRun
from rigsim.simulators import simulate
from schemas.runs import Run, RunState
from schemas.stands import MEASUREMENTS, Stand, StandKind, default_stands, with_overrides

MADE = datetime(2026, 11, 22, 12, 0, tzinfo=UTC)


class SimulatedReadings:
    """A simulated run's batches as the analysis and the reports read them."""

    def __init__(self, sim: SimulatedRun[Any]) -> None:
        self._sim = sim

    def rows(self, group: str) -> int:
        return self._sim.rows(group)

    def read(self, group: str, channels: list[str] | None = None) -> dict[str, NDArray[np.float64]]:
        columns = self._sim.columns(group) if self.rows(group) else {}
        return {k: v for k, v in columns.items() if channels is None or k in channels}

    def iter_chunks(
        self, group: str, channels: list[str] | None = None, rows: int = 1 << 20
    ) -> Iterator[dict[str, NDArray[np.float64]]]:
        columns = self.read(group, channels)
        for start in range(0, self.rows(group), rows):
            yield {k: v[start : start + rows] for k, v in columns.items()}

    def measurements(self) -> dict[str, float]:
        return {k: float(v[-1]) for k, v in self.read(MEASUREMENTS).items()}


@dataclass(frozen=True)
class Simulated:
    sim: SimulatedRun[Any]
    run: Run
    stand: Stand
    readings: SimulatedReadings
    result: AnalysisResult


@lru_cache
def simulated(kind: StandKind, seed: int = 7) -> Simulated:
    """The finished run of a simulated stand and the analysis of its readings."""
    return analysed(kind, simulate(kind, seed=seed))


def analysed(kind: StandKind, sim: SimulatedRun[Any]) -> Simulated:
    """A simulated run as the store would hold it, finished, and its analysis (no HTTP)."""
    stand = default_stands()[kind]
    body = sim.run_create
    readings = SimulatedReadings(sim)
    run = Run(
        id="20261122T114026Z-0000abcd",
        stand=kind,
        state=RunState.FINISHED,
        operator=body.operator,
        title=body.title,
        specimen=body.specimen,
        test_plan=body.test_plan,
        configuration=with_overrides(stand.configuration, body.configuration).model_dump(
            mode="json"
        ),
        created=MADE,
        ended=MADE,
        rows={g.name: readings.rows(g.name) for g in stand.groups},
    )
    return Simulated(sim, run, stand, readings, analyse(run, readings))


def post(client: TestClient, sim: SimulatedRun[Any], key: str, *, finish: bool = True) -> str:
    """Open the run, post every batch, finish it (unless ``finish`` is false); its id."""
    headers = {"Authorization": f"Bearer {key}"}
    answer = client.post(
        "/api/v1/runs", json=sim.run_create.model_dump(mode="json"), headers=headers
    )
    assert answer.status_code == 201, answer.text
    run_id = str(answer.json()["id"])
    for seq, batch in enumerate(sim.batches):
        body = {"seq": seq, "group": batch.group, "columns": batch.as_json()}
        answer = client.post(f"/api/v1/runs/{run_id}/readings", json=body, headers=headers)
        assert answer.status_code == 201, answer.text
    if finish:
        answer = client.post(f"/api/v1/runs/{run_id}/finish", headers=headers)
        assert answer.status_code == 200, answer.text
    return run_id


def series_of(
    client: httpx.Client,
    key: str,
    runs: Sequence[str],
    levels: Sequence[str] | None = None,
    **body: str,
) -> str:
    """Make the series ``body`` names (name, purpose, factor) and add the ``runs`` to it, each
    at its level of ``levels`` if given; its id."""
    headers = {"Authorization": f"Bearer {key}"}
    answer = client.post("/api/v1/series", json=body, headers=headers)
    assert answer.status_code == 201, answer.text
    series_id = str(answer.json()["id"])
    at: Sequence[str | None] = levels or [None] * len(runs)
    for run_id, level in zip(runs, at, strict=True):
        member = {"run_id": run_id} | ({"level": level} if level else {})
        answer = client.post(f"/api/v1/series/{series_id}/runs", json=member, headers=headers)
        assert answer.status_code == 201, answer.text
    return series_id


@dataclass
class HtmlTable:
    """A table of a report as a reader sees it: caption, header and cell texts."""

    caption: str = ""
    header: list[str] = field(default_factory=list)
    rows: list[list[str]] = field(default_factory=list)

    def column(self, index: int) -> list[str]:
        return [row[index] for row in self.rows]


class _Tables(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.tables: list[HtmlTable] = []
        self._caption: str | None = None
        self._captioned = ""
        self._table: HtmlTable | None = None
        self._row: list[str] | None = None
        self._cell: list[str] | None = None
        self._in_head = False

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "p" and ("class", "caption") in attrs:
            self._caption = ""
        elif tag == "table":
            self._table = HtmlTable(caption=self._captioned.strip())
            self._captioned = ""
        elif tag == "thead":
            self._in_head = True
        elif tag == "tr" and self._table is not None:
            self._row = []
        elif tag in ("td", "th") and self._row is not None:
            self._cell = []
        elif tag == "br" and self._cell is not None:  # a formula under a row's name
            self._cell.append("\n")

    def handle_endtag(self, tag: str) -> None:
        if tag == "p" and self._caption is not None:  # the caption ends with its paragraph
            self._captioned, self._caption = self._caption, None
        elif tag in ("td", "th") and self._row is not None and self._cell is not None:
            self._row.append("".join(self._cell).strip())
            self._cell = None
        elif tag == "tr" and self._table is not None and self._row is not None:
            if self._in_head:
                self._table.header = self._row
            else:
                self._table.rows.append(self._row)
            self._row = None
        elif tag == "thead":
            self._in_head = False
        elif tag == "table" and self._table is not None:
            self.tables.append(self._table)
            self._table = None

    def handle_data(self, data: str) -> None:
        if self._cell is not None:
            self._cell.append(data)
        elif self._caption is not None:
            self._caption += data


def tables(html: str) -> list[HtmlTable]:
    """Every table of a page, in order."""
    parser = _Tables()
    parser.feed(html)
    return parser.tables


def table(html: str, caption_start: str) -> HtmlTable:
    """The one table whose caption starts with ``caption_start``."""
    found = [t for t in tables(html) if t.caption.startswith(caption_start)]
    assert len(found) == 1, f"{len(found)} tables captioned {caption_start!r}"
    return found[0]
