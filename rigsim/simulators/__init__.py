"""The simulated stands: pure functions ``simulate(settings, seed) -> SimulatedRun``.

:data:`SIMULATORS` maps each stand kind to its settings class and simulator (the one place
in rigsim that names the kinds; a new kind is a module here and one entry);
:func:`simulate` picks one by kind.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from rigsim.batches import SimulatedRun
from rigsim.simulators import mtos, profilometer, slide_bearing, smts2, tribometer
from schemas.stands import StandKind

__all__ = ["SIMULATORS", "Simulator", "simulate"]


@dataclass(frozen=True, slots=True)
class Simulator:
    """A stand's default settings (its settings class, or a maker of them), its
    ``simulate(settings, seed)``, the maker of the settings of a named run mode (the SMTs-2's
    wear, adhesive, oxidative runs) and whether ``rigsim export`` writes its record as a
    commercial tribometer's program does."""

    settings: Callable[[], Any]
    simulate: Callable[[Any, int], SimulatedRun[Any]]
    for_mode: Callable[[Any], Any] | None = None
    vendor_export: bool = False


SIMULATORS: dict[StandKind, Simulator] = {
    StandKind.SMTS2: Simulator(
        smts2.Smts2Settings, smts2.simulate, for_mode=smts2.Smts2Settings.for_mode
    ),
    StandKind.SLIDE_BEARING: Simulator(slide_bearing.SlideBearingSettings, slide_bearing.simulate),
    StandKind.MTOS: Simulator(mtos.MtosSettings, mtos.simulate),
    StandKind.PROFILOMETER: Simulator(profilometer.ProfilometerSettings, profilometer.simulate),
    StandKind.PIN_ON_DISC: Simulator(
        tribometer.TribometerSettings, tribometer.simulate, vendor_export=True
    ),
    StandKind.RECIPROCATING: Simulator(
        tribometer.TribometerSettings.reciprocating,
        tribometer.simulate_reciprocating,
        vendor_export=True,
    ),
}


def simulate(kind: StandKind | str, settings: Any = None, seed: int = 0) -> SimulatedRun[Any]:
    """The simulated run of stand ``kind`` (default settings when ``settings`` is None)."""
    sim = SIMULATORS[StandKind(kind)]
    return sim.simulate(settings if settings is not None else sim.settings(), seed)
