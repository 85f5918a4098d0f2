"""One analysis kit per stand kind: its pipeline, the headline figures of a run (its key
results), the results a series compares, and the specimens whose materials the table gives.

The one place in the analysis that names the stand kinds; a new kind is a pipeline module
and one entry in :data:`KITS` (``tests/test_stand_kinds.py`` checks that every kind has one).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from pydantic import BaseModel

from rigserver.analysis import mtos, profilometer, slide_bearing, smts2, tribometer
from rigserver.analysis.readings import Readings
from rigserver.analysis.references import Profiles
from rigserver.analysis.specimens import SMTS2, TRIBOMETER, Roles, Specimens, specimen_materials
from schemas.labels import WEAR_SUBSCRIPTS
from schemas.runs import Run
from schemas.stands import DECLARATIONS, StandKind

Pipeline = Callable[[Run, Readings, Profiles], BaseModel]


@dataclass(frozen=True, slots=True)
class Headline:
    """A result a series compares: its path in the results, its symbol (the manual's), and
    the path of the run's own standard uncertainty of it, where the results hold one."""

    path: str
    symbol: str
    uncertainty: str | None = None


@dataclass(frozen=True, slots=True)
class Kit:
    """A stand kind's analysis: the pipeline, the paths of a run's key results (the stand's
    theory verdict, where it declares one, follows them), the results a series compares
    (:mod:`rigserver.analysis.series`) and the specimens' roles whose materials the table
    gives (none: the configuration's as given)."""

    analyse: Pipeline
    key_results: tuple[str, ...]
    series: tuple[Headline, ...]
    roles: Roles | None = None

    def headline_paths(self, kind: StandKind) -> tuple[str, ...]:
        verdict = DECLARATIONS[kind].theory_verdict
        return self.key_results if verdict is None else (*self.key_results, verdict)


def _without_profiles(analyse: Callable[[Run, Readings], BaseModel]) -> Pipeline:
    return lambda run, readings, _: analyse(run, readings)


_TRIBOMETER = Kit(
    analyse=tribometer.analyse,
    key_results=(
        "friction_steady",
        "running_in_distance",
        "disc_track.specific_wear_rate",
        "pin_scar.specific_wear_rate",
    ),
    series=(
        Headline("friction_steady", "μ", "friction_steady_uncertainty"),
        Headline("friction_static", "μ_s"),
        Headline("running_in_distance", "L_r"),
        *(
            Headline(
                f"{wear}.specific_wear_rate",
                f"k_{{{WEAR_SUBSCRIPTS[wear]}}}",
                f"{wear}.specific_wear_rate_uncertainty",
            )
            for wear in ("disc_track", "pin_scar")
        ),
    ),
    roles=TRIBOMETER,
)

KITS: dict[StandKind, Kit] = {
    StandKind.SMTS2: Kit(
        analyse=smts2.analyse,
        key_results=(
            "friction_steady",
            "experimental.intensity",
            "experimental.specific_wear_rate",
            "theoretical.intensity",
        ),
        series=(
            Headline("friction_steady", "f", "friction_steady_uncertainty"),
            Headline("experimental.intensity", "I_{h,exp}", "experimental.intensity_uncertainty"),
            Headline(
                "experimental.specific_wear_rate",
                "k",
                "experimental.specific_wear_rate_uncertainty",
            ),
            Headline("experimental.volume", "V"),
            Headline("experimental.mass_loss", "Δm"),
        ),
        roles=SMTS2,
    ),
    StandKind.SLIDE_BEARING: Kit(
        analyse=_without_profiles(slide_bearing.analyse),
        key_results=("chi_mean", "pressure_max", "phi_max"),
        series=(
            Headline("chi_mean", "χ_mean", "chi_mean_uncertainty"),
            Headline("pressure_max", "p_max"),
            Headline("phi_max", "φ_{p max}"),
            Headline("attitude_angle", "ψ"),
        ),
    ),
    StandKind.MTOS: Kit(
        analyse=mtos.analyse,
        key_results=("friction_fluid", "h_min_smallest", "h_crit"),
        series=(
            Headline("friction_fluid", "f̄_e"),
            Headline("h_min_smallest", "h_min"),
            Headline("steps[].friction_measured", "f_e", "steps[].friction_measured_uncertainty"),
            Headline("steps[].chi", "χ", "steps[].chi_uncertainty"),
            Headline("steps[].film_parameter", "Λ"),
        ),
    ),
    StandKind.PROFILOMETER: Kit(
        analyse=_without_profiles(profilometer.analyse),
        key_results=("ra", "rz", "complex_parameter"),
        series=(
            Headline("ra", "R_a", "ra_uncertainty"),
            Headline("rz", "R_z", "rz_uncertainty"),
            Headline("rq", "R_q"),
            Headline("rmax", "R_max"),
            Headline("sm", "S_m"),
        ),
    ),
    StandKind.PIN_ON_DISC: _TRIBOMETER,
    StandKind.RECIPROCATING: _TRIBOMETER,
}


def run_materials(run: Run) -> Specimens[BaseModel]:
    """The run's configuration as its stand's analysis reads it: with the table's properties
    of the materials its specimen names (as given, for a stand without such roles)."""
    config = DECLARATIONS[run.stand].configuration.model_validate(run.configuration)
    roles = KITS[run.stand].roles
    return Specimens(config) if roles is None else specimen_materials(run, config, roles)
