"""One pipeline per stand: a stored run's readings -> the lab manual's results (via core).

:func:`analyse` picks the stand's pipeline (its kit: :mod:`rigserver.analysis.kits`) and
returns the results with their units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from pydantic import BaseModel

from rigserver.analysis.kits import KITS
from rigserver.analysis.readings import Readings
from rigserver.analysis.references import RunLookup, referenced_profiles
from schemas.quantity import unit_paths
from schemas.runs import Run

__all__ = ["AnalysisResult", "Readings", "RunLookup", "analyse"]


@dataclass(frozen=True)
class AnalysisResult:
    """The results of one run: the wire payload and a few headline figures."""

    values: BaseModel
    key_results: dict[str, float]

    @property
    def payload(self) -> dict[str, Any]:
        return {
            "stand": getattr(self.values, "stand", None),
            "values": self.values.model_dump(mode="json"),
            "units": unit_paths(type(self.values)),
        }


def analyse(run: Run, readings: Readings, lookup: RunLookup | None = None) -> AnalysisResult:
    """The stand's results on the run's readings (what has arrived, for an open run).

    ``lookup`` finds the profilometer runs that the run's specimen names
    (:mod:`rigserver.analysis.references`); without it they are reported as not found.
    """
    kit = KITS[run.stand]
    values = kit.analyse(run, readings, referenced_profiles(run, lookup))
    return AnalysisResult(
        values=values, key_results=_headline(values, kit.headline_paths(run.stand))
    )


def _headline(values: BaseModel, paths: tuple[str, ...]) -> dict[str, float]:
    found: dict[str, float] = {}
    for path in paths:
        node: Any = values
        for part in path.split("."):
            node = getattr(node, part, None)
        if isinstance(node, int | float) and math.isfinite(node):  # a verdict as 1 or 0
            found[path] = float(node)
    return found
