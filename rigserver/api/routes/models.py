"""``/models``: the model library's calculators on their own, with units."""

from __future__ import annotations

import math

from fastapi import APIRouter

from rigserver.api.deps import ReadAccess
from rigserver.core import bearing, roughness, wear
from schemas.calculators import (
    BearingFrictionInput,
    BearingFrictionResult,
    EquilibriumRoughnessInput,
    EquilibriumRoughnessResult,
    WearTheoryInput,
)
from schemas.results import TheoreticalWearResult

router = APIRouter(prefix="/models", tags=["models"], dependencies=[ReadAccess])


@router.post("/wear/theoretical", summary="Fatigue wear intensity of the pin (2.1)-(2.7)")
def wear_theoretical(body: WearTheoryInput) -> TheoreticalWearResult:
    r = wear.wear_intensity_theoretical(**body.model_dump())
    fields = set(TheoreticalWearResult.model_fields) - {"fatigue_t"}
    return TheoreticalWearResult(fatigue_t=body.fatigue_t, **{k: getattr(r, k) for k in fields})


@router.post("/bearing/friction", summary="Short-bearing friction moment and f_T (4.1)-(4.10)")
def bearing_friction(body: BearingFrictionInput) -> BearingFrictionResult:
    geometry = body.model_dump(exclude={"load"})
    moment = bearing.friction_moment_theoretical(**geometry)
    force = bearing.short_bearing_load(**geometry)
    f = bearing.friction_coefficient_theoretical(**geometry, load=body.load)
    return BearingFrictionResult(
        friction_moment=float(moment.moment),
        friction_coefficient=float(f),
        film_force=float(force.resultant),
        attitude_angle=math.degrees(float(force.attitude_angle)),
        half_width=float(moment.half_width),
    )


@router.post(
    "/roughness/equilibrium", summary="Equilibrium complex roughness parameter (1.11)-(1.13)"
)
def roughness_equilibrium(body: EquilibriumRoughnessInput) -> EquilibriumRoughnessResult:
    delta = float(roughness.equilibrium_complex_parameter(**body.model_dump()))
    k1, k2 = roughness.k1_k2(nu=body.nu)
    return EquilibriumRoughnessResult(
        complex_parameter=delta,
        ra=float(roughness.ra_from_complex_parameter(delta=delta)),
        k1=float(k1),
        k2=float(k2),
    )
