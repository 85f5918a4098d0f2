"""The results of each stand's analysis, declared with units (what `/results` answers).

The wire form is ``{"stand": ..., "values": <one of the models below>, "units": {path: unit}}``
with the units of every quantity, nested paths joined by dots (``rows[].chi``).
"""

from __future__ import annotations

from schemas.results.common import IsoRoughnessResult, Series
from schemas.results.mtos import MtosResults, MtosStep
from schemas.results.profilometer import BearingFitResult, ProfilometerResults
from schemas.results.slide_bearing import AxialPoint, SlideBearingResults, SlideBearingRow
from schemas.results.smts2 import (
    AdequacyResult,
    DiscWearResult,
    ExperimentalWearResult,
    SensitivityPoint,
    Smts2Results,
    TheoreticalWearResult,
    WearValidityResult,
)
from schemas.results.tribometer import (
    FrictionLoop,
    HertzResult,
    LapMapResult,
    MassWear,
    PinOnDiscResults,
    ReciprocatingResults,
    ScarWear,
    StrokeBlock,
    TrackWear,
    TribometerResults,
    TribometerStep,
    WearEstimate,
)

__all__ = [
    "AdequacyResult",
    "AxialPoint",
    "BearingFitResult",
    "DiscWearResult",
    "ExperimentalWearResult",
    "FrictionLoop",
    "HertzResult",
    "IsoRoughnessResult",
    "LapMapResult",
    "MassWear",
    "MtosResults",
    "MtosStep",
    "PinOnDiscResults",
    "ProfilometerResults",
    "ReciprocatingResults",
    "ScarWear",
    "SensitivityPoint",
    "Series",
    "SlideBearingResults",
    "SlideBearingRow",
    "Smts2Results",
    "StrokeBlock",
    "TheoreticalWearResult",
    "TrackWear",
    "TribometerResults",
    "TribometerStep",
    "WearEstimate",
    "WearValidityResult",
]
