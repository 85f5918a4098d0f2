"""One pipeline per stand: a stored run's readings -> the lab manual's results (via core).

:func:`analyse` picks the stand's pipeline and returns the results with their units.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from pydantic import BaseModel

from rigserver.analysis import mtos, profilometer, slide_bearing, smts2, tribometer
from rigserver.analysis.readings import Readings
from rigserver.analysis.references import Profiles, RunLookup, referenced_profiles
from schemas.quantity import unit_paths
from schemas.runs import Run
from schemas.stands import DECLARATIONS, StandKind

__all__ = ["AnalysisResult", "Readings", "RunLookup", "analyse"]

_PIPELINES: dict[StandKind, Callable[[Run, Readings, Profiles], BaseModel]] = {
    StandKind.SMTS2: smts2.analyse,
    StandKind.SLIDE_BEARING: lambda run, readings, _: slide_bearing.analyse(run, readings),
    StandKind.MTOS: mtos.analyse,
    StandKind.PROFILOMETER: lambda run, readings, _: profilometer.analyse(run, readings),
    StandKind.PIN_ON_DISC: tribometer.analyse,
    StandKind.RECIPROCATING: tribometer.analyse,
}


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


_KEYS: dict[StandKind, tuple[str, ...]] = {
    StandKind.SMTS2: (
        "friction_steady",
        "experimental.intensity",
        "experimental.specific_wear_rate",
        "theoretical.intensity",
        *filter(None, [DECLARATIONS[StandKind.SMTS2].theory_verdict]),
    ),
    StandKind.SLIDE_BEARING: ("chi_mean", "pressure_max", "phi_max"),
    StandKind.MTOS: ("friction_fluid", "h_min_smallest", "h_crit"),
    StandKind.PROFILOMETER: ("ra", "rz", "complex_parameter"),
    StandKind.PIN_ON_DISC: (
        "friction_steady",
        "running_in_distance",
        "disc_track.specific_wear_rate",
        "pin_scar.specific_wear_rate",
    ),
    StandKind.RECIPROCATING: (
        "friction_steady",
        "running_in_distance",
        "disc_track.specific_wear_rate",
        "pin_scar.specific_wear_rate",
    ),
}


def analyse(run: Run, readings: Readings, lookup: RunLookup | None = None) -> AnalysisResult:
    """The stand's results on the run's readings (what has arrived, for an open run).

    ``lookup`` finds the profilometer runs that the run's specimen names
    (:mod:`rigserver.analysis.references`); without it they are reported as not found.
    """
    values = _PIPELINES[run.stand](run, readings, referenced_profiles(run, lookup))
    return AnalysisResult(values=values, key_results=_headline(values, _KEYS[run.stand]))


def _headline(values: BaseModel, paths: tuple[str, ...]) -> dict[str, float]:
    found: dict[str, float] = {}
    for path in paths:
        node: Any = values
        for part in path.split("."):
            node = getattr(node, part, None)
        if isinstance(node, int | float):  # a verdict (bool) as 1 or 0
            found[path] = float(node)
    return found
