"""Lab work 4 on a stored run: tables 4.4-4.6 from the load steps and the zero readings."""

from __future__ import annotations

from typing import Literal

import numpy as np

from rigserver.analysis import uncertainty
from rigserver.analysis.finite_steps import FiniteBearingSteps
from rigserver.analysis.readings import Readings
from rigserver.analysis.references import Profiles
from rigserver.core import bearing, film, stands
from rigserver.core.errors import ModelInputError
from schemas.messages import N_
from schemas.results import MtosResults, MtosStep
from schemas.runs import Run
from schemas.stands import MtosConfig
from schemas.units import UNITS

GROUP = "steps"
REGIMES: dict[int, Literal["fluid", "mixed", "boundary"]] = {1: "fluid", 2: "mixed", 3: "boundary"}
#: The experiment's regime as each criterion names it: (2.104) and the Λ bands.
_AS_FILM = {"fluid": "fluid", "mixed": "mixed", "boundary": "mixed"}
_AS_LAMBDA = {"fluid": "full film", "mixed": "mixed", "boundary": "boundary"}
_M_PER_UM = UNITS["um"].factor
_M_PER_MM = UNITS["mm"].factor
_N_PER_M = UNITS["N/mm"].factor
#: The finite bearing's figures by (χ, B/D), shared by every run's results.
FINITE = FiniteBearingSteps()
#: μ0 = μ at this temperature, °C, and ω0, 1/s, of (4.3) (the note to table 4.4; lab 4).
REFERENCE_T = 50.0
REFERENCE_OMEGA = 100.0
#: The integrals (4.5) table 4.4 lists, by their field names in the results.
INTEGRALS = ("a1_00", "a2_00", "a3_00", "a3_02", "a3_20", "a3_11")
#: Load steps of a run whose finite bearing (3.1) is solved, about 10 ms each (the manual's
#: run has 12): the bound of one results computation; later steps leave it empty, noted.
MAX_FINITE_STEPS = 500


def analyse(run: Run, readings: Readings, profiles: Profiles | None = None) -> MtosResults:
    c = MtosConfig.model_validate(run.configuration)
    profiles = profiles or Profiles()
    journal_rq, bush_rq = profiles.rq("journal"), profiles.rq("bush")
    source = ", ".join(
        f"{role}: profilometer run {run.specimen[f'{role}_profile_run']}"
        for role in ("journal", "bush")
        if role in profiles.found
    )
    radius = c.diameter / 2.0
    crit = film.critical_film_thickness(
        journal_roughness=c.journal_roughness,
        bush_roughness=c.bush_roughness,
        misalignment=c.misalignment,
        deflection=c.deflection,
        shape_error=c.shape_error,
    )
    result = MtosResults(
        rows=readings.rows(GROUP),
        h_crit=crit.total,
        half_width=c.width / c.diameter,
        journal_rq=c.journal_rq if journal_rq is None else journal_rq,
        bush_rq=c.bush_rq if bush_rq is None else bush_rq,
        roughness_source=source or N_("the stand's configuration"),
        notes=list(profiles.problems),
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
        signed=c.signed_sensors,
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
    mu_at = {
        f"t{k}": stands.viscosity(t=rows[f"t{k}"], A=c.viscosity.A, alpha=c.viscosity.alpha)
        for k in (1, 2, 3, 4, 5)
    }
    mu_50 = float(stands.viscosity(t=REFERENCE_T, A=c.viscosity.A, alpha=c.viscosity.alpha))
    acc = c.accuracy
    x_zero = uncertainty.from_limit(m["x_zero"] * _M_PER_UM, acc.displacement * _M_PER_UM)
    y_zero = uncertainty.from_limit(m["y_zero"] * _M_PER_UM, acc.displacement * _M_PER_UM)
    h0 = uncertainty.from_limit(c.clearance, acc.clearance)
    arms = (
        uncertainty.from_limit(c.lever_moment_arm, acc.arms)
        / uncertainty.from_limit(c.friction_arm, acc.arms)
        * uncertainty.from_limit(
            c.spring_rate * _N_PER_M, c.spring_rate * _N_PER_M * acc.spring_rate
        )
    )
    h_min = film.minimum_film_thickness(clearance=c.clearance, chi=np.minimum(ecc.chi, 1.0))
    solved = ecc.chi[:MAX_FINITE_STEPS]
    FINITE.solve_all(solved[(solved >= 0.0) & (solved < 1.0)], c.width / c.diameter)
    if load.size > MAX_FINITE_STEPS:
        result.notes.append(
            f"the finite bearing (3.1) is solved for the first {MAX_FINITE_STEPS} steps only"
        )
    lam = film.film_parameter(h_min=h_min, journal_rq=result.journal_rq, bush_rq=result.bush_rq)
    for i in range(load.size):
        regime = REGIMES[int(rows["regime"][i])]
        try:
            angles = stands.mtos_attitude_angles(e_x=ecc.e_x[i], e_y=ecc.e_y[i])
            angle = float(np.degrees(angles.delta if regime == "fluid" else angles.gamma))
        except ModelInputError:
            angle = 0.0
            result.notes.append(f"step {i}: journal centred, the angle (4.12) is undefined")
        f_theory = f_error = None
        table44: dict[str, float] = {}
        f_finite, load_finite = (
            _finite(c, float(ecc.chi[i]), float(oil.mean[i]), float(load[i]))
            if i < MAX_FINITE_STEPS
            else (None, None)
        )
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
                table44 = _table_4_4(c, float(ecc.chi[i]), float(oil.mean[i]), mu_50)
                f_error = float(
                    stands.relative_error_percent(
                        reference=measured.coefficient[i], other=f_t
                    ).percent
                )
            except ModelInputError as exc:
                result.notes.append(f"step {i}: f_T not computed: {exc}")
        u_chi = uncertainty.estimate(
            uncertainty.mtos_chi(
                x=float(rows["x"][i]) * _M_PER_UM,
                y=float(rows["y"][i]) * _M_PER_UM,
                x_zero=x_zero,
                y_zero=y_zero,
                limit=acc.displacement * _M_PER_UM,
                clearance=h0,
                signed=c.signed_sensors,
            )
        )
        u_f = uncertainty.estimate(
            arms
            * uncertainty.from_limit(
                float(rows["indicator"][i]) * _M_PER_MM, acc.indicator * _M_PER_MM
            )
            / uncertainty.from_limit(float(load[i]), float(load[i]) * acc.dynamometer)
        )
        result.steps.append(
            MtosStep(
                chi_uncertainty=u_chi.standard,
                chi_expanded=u_chi.expanded,
                friction_measured_uncertainty=u_f.standard,
                friction_measured_expanded=u_f.expanded,
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
                viscosity_at={k: float(v[i]) for k, v in mu_at.items()},
                bearing_characteristic_inverse=float(1.0 / s1[i]) if s1[i] > 0 else None,
                **table44,
                friction_theory=f_theory,
                friction_error=None if f_error is None or np.isnan(f_error) else f_error,
                friction_finite=f_finite,
                load_finite=load_finite,
                h_min=float(h_min[i]),
                film=film.film_regime(h_min=float(h_min[i]), h_crit=crit.total),
                film_parameter=float(lam[i]),
                film_lambda=film.lambda_regime(film_parameter=float(lam[i])),
            )
        )
        result.regime_disagreements += _disagreements(i, result.steps[-1])
    fluid = [s.friction_measured for s in result.steps if s.regime == "fluid"]
    result.friction_fluid = float(np.mean(fluid)) if fluid else None
    result.h_min_smallest = float(np.min(h_min))
    return result


def _table_4_4(c: MtosConfig, chi: float, viscosity: float, mu_50: float) -> dict[str, float]:
    """The last part of table 4.4 at one fluid-film step: μ_t/μ0, the integrals (4.5), V
    (4.4) and P_τ = P*·V (4.2)-(4.3), with μ0 = μ at 50 °C and ω0 = 100 1/s (the manual's)."""
    integrals = bearing.short_bearing_integrals(chi=chi)
    moment = bearing.friction_moment_theoretical(
        chi=chi,
        omega=c.omega,
        viscosity=viscosity,
        bearing_radius=c.diameter / 2.0,
        width=c.width,
        clearance=c.clearance,
        reference_viscosity=mu_50,
        reference_omega=REFERENCE_OMEGA,
    )
    return {
        "viscosity_ratio": viscosity / mu_50,
        **{name: float(getattr(integrals, name)) for name in INTEGRALS},
        "v_factor": float(moment.v),
        "tangential_force": float(moment.tangential_force),
    }


def _finite(
    c: MtosConfig, chi: float, viscosity: float, load: float
) -> tuple[float | None, float | None]:
    """Friction coefficient and load of the finite bearing (3.1) at the measured χ.

    The scales of (3.6) with μ0 = μ_t and ω0 = ω: forces in μωR⁴/h0², torques in μωR⁴/h0.
    f = M/(N·R1) with the full-film shear torque, the convention of (4.1) and (4.10).
    Solved once per (χ, B/D): see :mod:`rigserver.analysis.finite_steps`.
    """
    if not 0.0 <= chi < 1.0:
        return None, None
    radius = c.diameter / 2.0
    solution = FINITE.figures(chi=chi, half_width=c.width / c.diameter)
    torque_scale = viscosity * c.omega * radius**4 / c.clearance
    moment = solution.journal_torque_full_film * torque_scale
    return moment / (load * (radius - c.clearance)), solution.load * torque_scale / c.clearance


def _disagreements(index: int, step: MtosStep) -> list[str]:
    """Where a criterion names another regime than the experiment's oil feed declares."""
    out = []
    if step.film != _AS_FILM[step.regime]:
        out.append(
            f"step {index} ({step.regime} experiment, N = {step.load:g} N): h_min against "
            f"h_min^crit says {step.film}"
        )
    if step.film_lambda != _AS_LAMBDA[step.regime]:
        out.append(
            f"step {index} ({step.regime} experiment, N = {step.load:g} N): "
            f"Λ = {step.film_parameter:.2f} says {step.film_lambda}"
        )
    return out
