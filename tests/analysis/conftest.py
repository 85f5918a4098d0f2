"""An in-memory run's readings, for testing the pipelines without a store."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from datetime import UTC, datetime
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rigserver.analysis import analyse
from schemas.runs import Run
from schemas.stands import StandKind, default_stands


class FakeReadings:
    def __init__(self, groups: dict[str, dict[str, list[float]]], measurements: dict[str, float]):
        self.groups = {
            g: {k: np.asarray(v, float) for k, v in c.items()} for g, c in groups.items()
        }
        self._m = measurements

    def rows(self, group: str) -> int:
        cols = self.groups.get(group)
        return len(next(iter(cols.values()))) if cols else 0

    def read(self, group: str, channels: list[str] | None = None) -> dict[str, NDArray[np.float64]]:
        return dict(self.groups.get(group, {}))

    def iter_chunks(
        self, group: str, channels: list[str] | None = None, rows: int = 1 << 20
    ) -> Iterator[dict[str, NDArray[np.float64]]]:
        cols = self.groups.get(group, {})
        n = self.rows(group)
        for start in range(0, n, rows):
            yield {k: v[start : start + rows] for k, v in cols.items()}

    def measurements(self) -> dict[str, float]:
        return dict(self._m)


def make_run(kind: StandKind, **config: object) -> Run:
    base = default_stands()[kind].configuration.model_dump(mode="json")
    base.update(config)
    return Run(
        id="20261122T114026Z-0000abcd",
        stand=kind,
        operator="test",
        configuration=base,
        created=datetime(2026, 11, 22, tzinfo=UTC),
    )


def mtos_on_the_diagonal(
    load: list[float],
    indicator: list[float],
    x: list[float],
    temperatures: Mapping[str, list[float]],
    zero: float = 0.0,
) -> Any:
    """The results of MTOS steps in regime 1 with the journal on the diagonal: the Y gauge
    reads what the X gauge does, both zeroed at ``zero`` (μm)."""
    rows = {
        "load": load,
        "indicator": indicator,
        "x": x,
        "y": x,
        **temperatures,
        "regime": [1.0] * len(load),
    }
    zeros = {"x_zero": zero, "y_zero": zero}
    return analyse(make_run(StandKind.MTOS), FakeReadings({"steps": rows}, zeros)).values


def friction_record(n: int = 100) -> dict[str, list[float]]:
    """An SMTs-2 friction record: 300 N, 980 rpm, 2.7 N·m, the counter 0 -> 9 hundreds."""
    return {
        "time": [float(i) for i in range(n)],
        "load": [300.0] * n,
        "speed": [980.0] * n,
        "friction_moment": [2.7] * n,
        "revolutions": [float(i // 10) for i in range(n)],
    }
