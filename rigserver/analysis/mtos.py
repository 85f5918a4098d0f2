"""Lab work 4 on a stored run: tables 4.4-4.6 from the load steps and the zero readings."""

from __future__ import annotations

from typing import Literal

import numpy as np

from rigserver.analysis.readings import Readings
from rigserver.core import bearing, film, reynolds, stands
from rigserver.core.errors import ModelInputError
from schemas.messages import N_
from schemas.results import MtosResults, MtosStep
from schemas.runs import Run
from schemas.stands import MtosConfig
from schemas.units import UNITS

GROUP = "steps"
REGIMES: dict[int, Literal["fluid", "mixed", "boundary"]] = {1: "fluid", 2: "mixed", 3: "boundary"}
_M_PER_UM = UNITS["um"].factor
_M_PER_MM = UNITS["mm"].factor
_N_PER_M = UNITS["N/mm"].factor


def analyse(run: Run, readings: Readings) -> MtosResults:
    c = MtosConfig.model_validate(run.configuration)
    radius = c.diameter / 2.0
    crit = film.critical_film_thickness(
        journal_roughness=c.journal_roughness,
        bush_roughness=c.bush_roughness,
        misalignment=c.misalignment,
        deflection=c.deflection,
        shape_error=c.shape_error,
    )
    result = MtosResults(
        rows=readings.rows(GROUP), h_crit=crit.total, half_width=c.width / c.diameter
    )
    rows = readings.read(GROUP)
    m = readings.measurements()
    if not rows:
        result.pending.append(N_("no load steps yet"))
    if "x_zero" not in m or "y_zero" not in m:
        result.pending.append(N_("needs the measurements x_zero, y_zero"))
    if result.pending:
        return result
    load = rows["load"]
    ecc = stands.mtos_eccentricity(
        x=rows["x"] * _M_PER_UM,
        y=rows["y"] * _M_PER_UM,
        x_set=m["x_zero"] * _M_PER_UM,
        y_set=m["y_zero"] * _M_PER_UM,
        clearance=c.clearance,
    )
    measured = stands.mtos_friction(
        indicator_travel=rows["indicator"] * _M_PER_MM,
        spring_rate=c.spring_rate * _N_PER_M,
        spring_arm=c.lever_moment_arm,
        friction_arm=c.friction_arm,
        load=load,
    )
    oil = stands.mtos_film_viscosity(
        t3=rows["t3"], t4=rows["t4"], t5=rows["t5"], A=c.viscosity.A, alpha=c.viscosity.alpha
    )
    s1 = stands.bearing_characteristic(
        viscosity=oil.mean, omega=c.omega, load=load, width=c.width, diameter=c.diameter
    )
    rises = {
        f"t{k}": stands.temperature_rise(t=rows[f"t{k}"], t_in=rows["t1"]) for k in (2, 3, 4, 5)
    }
    h_min = film.minimum_film_thickness(clearance=c.clearance, chi=np.minimum(ecc.chi, 1.0))
    for i in range(load.size):
        regime = REGIMES[int(rows["regime"][i])]
        try:
            angles = stands.mtos_attitude_angles(e_x=ecc.e_x[i], e_y=ecc.e_y[i])
            angle = float(np.degrees(angles.delta if regime == "fluid" else angles.gamma))
        except ModelInputError:
            angle = 0.0
            result.notes.append(f"step {i}: journal centred, the angle (4.12) is undefined")
        f_theory = f_error = None
        f_finite, load_finite = _finite(c, float(ecc.chi[i]), float(oil.mean[i]), float(load[i]))
        if regime == "fluid":
            try:
                f_t = bearing.friction_coefficient_theoretical(
                    chi=ecc.chi[i],
                    omega=c.omega,
                    viscosity=oil.mean[i],
                    bearing_radius=radius,
                    width=c.width,
                    clearance=c.clearance,
                    load=load[i],
                )
                f_theory = float(f_t)
                f_error = float(
                    stands.relative_error_percent(
                        reference=measured.coefficient[i], other=f_t
                    ).percent
                )
            except ModelInputError as exc:
                result.notes.append(f"step {i}: f_T not computed: {exc}")
        result.steps.append(
            MtosStep(
                load=float(load[i]),
                regime=regime,
                e_x=float(ecc.e_x[i]),
                e_y=float(ecc.e_y[i]),
                e=float(ecc.e[i]),
                chi=float(ecc.chi[i]),
                angle=angle,
                spring_force=float(measured.spring_force[i]),
                friction_moment=float(measured.moment[i]),
                friction_force=float(measured.friction_force[i]),
                friction_measured=float(measured.coefficient[i]),
                viscosity=float(oil.mean[i]),
                bearing_characteristic=float(s1[i]),
                temperature_rise={k: float(v[i]) for k, v in rises.items()},
                friction_theory=f_theory,
                friction_error=None if f_error is None or np.isnan(f_error) else f_error,
                friction_finite=f_finite,
                load_finite=load_finite,
                h_min=float(h_min[i]),
                film=film.film_regime(h_min=float(h_min[i]), h_crit=crit.total),
            )
        )
    fluid = [s.friction_measured for s in result.steps if s.regime == "fluid"]
    result.friction_fluid = float(np.mean(fluid)) if fluid else None
    result.h_min_smallest = float(np.min(h_min))
    return result


def _finite(
    c: MtosConfig, chi: float, viscosity: float, load: float
) -> tuple[float | None, float | None]:
    """Friction coefficient and load of the finite bearing (3.1) at the measured χ.

    The scales of (3.6) with μ0 = μ_t and ω0 = ω: forces in μωR⁴/h0², torques in μωR⁴/h0.
    f = M/(N·R1) with the full-film shear torque, the convention of (4.1) and (4.10).
    """
    if not 0.0 <= chi < 1.0:
        return None, None
    radius = c.diameter / 2.0
    solution = reynolds.solve_reynolds(chi=chi, half_width=c.width / c.diameter)
    torque_scale = viscosity * c.omega * radius**4 / c.clearance
    moment = solution.journal_torque_full_film * torque_scale
    return moment / (load * (radius - c.clearance)), solution.load * torque_scale / c.clearance
