"""``/models``: the model library's calculators on their own, with units."""

from __future__ import annotations

import math

import numpy as np
from fastapi import APIRouter, Request
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import HTMLResponse

from rigserver.api.deps import ReadAccess
from rigserver.api.strict_json import StrictJsonRoute
from rigserver.core import arm, bearing, mechanism, roughness, wear
from rigserver.reports.i18n import Lang, language_headers, negotiate
from rigserver.reports.mechanism import mechanism_report
from schemas.calculators import (
    BearingFrictionInput,
    BearingFrictionResult,
    EquilibriumRoughnessInput,
    EquilibriumRoughnessResult,
    WearTheoryInput,
)
from schemas.mechanism import DynamicErrorsRequest, DynamicErrorsResponse
from schemas.results import TheoreticalWearResult

router = APIRouter(
    prefix="/models", tags=["models"], dependencies=[ReadAccess], route_class=StrictJsonRoute
)


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


def _dynamic_errors(body: DynamicErrorsRequest) -> DynamicErrorsResponse:
    arm_model = arm.AnthropomorphicArm(**body.arm.model_dump(exclude_none=True))
    move = body.move
    program = mechanism.point_to_point(
        q_start=move.q_start, q_end=move.q_end, duration=move.duration, profile=move.profile
    )
    t = np.linspace(0.0, move.duration + body.settle, body.samples)
    r = arm.arm_dynamic_errors(arm=arm_model, program=program, t_eval=t, method=body.method)
    q = np.array([program(float(ti))[0] for ti in r.t]).T
    return DynamicErrorsResponse(
        t=r.t.tolist(),
        q=q.tolist(),
        xi=r.xi.tolist(),
        xi_dot=r.xi_dot.tolist(),
        max_abs=r.max_abs.tolist(),
        success=r.success,
        message=r.message,
        evaluations=r.nfev,
    )


@router.post(
    "/mechanism/dynamic-errors",
    summary="Dynamic errors of the lever mechanism's programmed move (the article, (4)-(18))",
    description="The three-link arm with two ball-screw drives follows a point-to-point move; "
    "the answer is ξ_k(t) of each joint and its largest modulus. Takes a few seconds.",
)
async def dynamic_errors(body: DynamicErrorsRequest) -> DynamicErrorsResponse:
    return await run_in_threadpool(_dynamic_errors, body)


@router.post(
    "/mechanism/report.html",
    summary="The same computation as an HTML report with the plots",
    response_class=HTMLResponse,
)
async def dynamic_errors_report(
    body: DynamicErrorsRequest, request: Request, lang: Lang | None = None
) -> HTMLResponse:
    """In ``?lang=`` or the best language of ``Accept-Language`` (else English)."""
    chosen = negotiate(lang, request.headers.get("accept-language"))
    result = await run_in_threadpool(_dynamic_errors, body)
    page = await run_in_threadpool(mechanism_report, body, result, chosen)
    return HTMLResponse(page, headers=language_headers(chosen))
