"""The curves a series report overlays, one per run: read from the run's results or its
readings; each stand's report kit (:mod:`rigserver.reports.kits`) says which it plots."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from rigserver.analysis import Readings
from rigserver.reports.downsample import min_max
from rigserver.reports.series_plots import Curve

#: Points of a profile drawn per run (min-max decimation; the statistics use every reading).
PROFILE_POINTS = 800

#: A run's curve from its id, its results' values and its readings.
Extract = Callable[[str, Mapping[str, Any] | None, Readings | None], Curve | None]


@dataclass(frozen=True, slots=True)
class SeriesPlot:
    """One overlay plot of a series report: its caption (a message key), its axes (the
    manual's symbol and unit), the curve of each run, and how :func:`overlay` draws them
    (``markers``, ``paired``)."""

    caption: str
    x: tuple[str, ...]
    y: tuple[str, ...]
    curve: Extract
    markers: bool = False
    paired: bool = False

    def of(
        self, values: Mapping[str, Mapping[str, Any] | None], readings: Mapping[str, Readings]
    ) -> Callable[[str], Curve | None]:
        """The curve of a run of the series, by the run's id."""
        return lambda run: self.curve(run, values[run], readings.get(run))


def friction(run_id: str, values: Mapping[str, Any] | None) -> Curve | None:
    """f against the sliding distance: the block means' times scaled so the last reaches
    the run's L (the disc turns at a constant speed within ±10 %)."""
    if values is None or not values.get("friction") or not values.get("sliding_distance"):
        return None
    x = np.asarray(values["friction"]["x"], dtype=float)
    y = np.asarray(values["friction"]["y"], dtype=float)
    if x.size < 2 or not x[-1] > x[0]:
        return None
    distance = (x - x[0]) / (x[-1] - x[0]) * float(values["sliding_distance"])
    return Curve(run_id, distance, y)


def series(run_id: str, values: Mapping[str, Any] | None, name: str) -> Curve | None:
    """A plot series of the results as it is (the tribometers' μ against L)."""
    found = None if values is None else values.get(name)
    if not found or len(found.get("x") or []) < 2:
        return None
    return Curve(run_id, np.asarray(found["x"], float), np.asarray(found["y"], float))


def rows(run_id: str, values: Mapping[str, Any] | None, table: str, x: str, y: str) -> Curve | None:
    if values is None:
        return None
    rows = [r for r in values.get(table) or [] if r.get(x) is not None and r.get(y) is not None]
    if not rows:
        return None
    return Curve(
        run_id, np.array([r[x] for r in rows], float), np.array([r[y] for r in rows], float)
    )


def pairs(run_id: str, values: Mapping[str, Any] | None, x: str, y: str) -> Curve | None:
    if values is None or not values.get(x) or len(values[x]) != len(values.get(y) or []):
        return None
    return Curve(run_id, np.asarray(values[x], float), np.asarray(values[y], float))


def profile(run_id: str, readings: Readings | None) -> Curve | None:
    if readings is None or readings.rows("profile") < 2:
        return None
    columns = readings.read("profile", ["x", "y"])
    x, y = min_max(columns["x"], columns["y"], buckets=PROFILE_POINTS // 2)
    return Curve(run_id, x, y)
