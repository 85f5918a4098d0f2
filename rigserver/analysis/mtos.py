"""Lab work 4 on a stored run: tables 4.4-4.6 from the load steps and the zero readings."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from uncertainties import UFloat

from rigserver.analysis import uncertainty
from rigserver.analysis.finite_steps import FiniteBearingSteps
from rigserver.analysis.readings import Columns, Readings
from rigserver.analysis.references import Profiles
from rigserver.core import bearing, bearing_readings, film
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
#: N: the least load a step is taken at. The dynamometer reads hundreds of newtons (the
#: manual's steps are 500-3000 N); below this f = F/N and S1 (4.11, 4.21) grow without
#: meaning (a load of 10⁻³⁰⁰ N gives f ~ 10³⁰³), and the step waits for its correction.
LEAST_LOAD = 1.0


def analyse(run: Run, readings: Readings, profiles: Profiles | None = None) -> MtosResults:
    """Tables 4.4-4.6 of lab work 4: each load step's eccentricity (4.6)-(4.9), measured
    friction (4.10)-(4.11), oil viscosity (4.14), S1 (4.13), the theory beside it (4.1)-(4.5)
    and the film (4.15)-(4.18), with their uncertainties (GUM); pending until the steps and
    the zero readings are there."""
    config = MtosConfig.model_validate(run.configuration)
    result = _heading(run, readings, config, profiles or Profiles())
    rows = readings.read(GROUP)
    zeros = readings.measurements()
    if readings.rows(GROUP) == 0:
        result.pending.append(N_("no load steps yet"))
    unloaded = [] if result.pending else np.flatnonzero(~(rows["load"] >= LEAST_LOAD)).tolist()
    if unloaded:  # a typo to correct: the run still finishes, its results wait for it
        result.pending.append(
            f"steps {', '.join(map(str, unloaded))}: the load is below {LEAST_LOAD:g} N; "
            "f = M/(N·r) (4.11) and S1 (4.21) need a load step"
        )
    if "x_zero" not in zeros or "y_zero" not in zeros:
        result.pending.append(N_("needs the measurements x_zero, y_zero"))
    if result.pending:
        return result
    steps = _LoadSteps.of(config, rows, zeros, result)
    spread = _Spread.of(config, zeros)
    solved = steps.eccentricity.chi[:MAX_FINITE_STEPS]
    FINITE.solve_all(solved[(solved >= 0.0) & (solved < 1.0)], config.width / config.diameter)
    if steps.load.size > MAX_FINITE_STEPS:
        result.notes.append(
            f"the finite bearing (3.1) is solved for the first {MAX_FINITE_STEPS} steps only"
        )
    for i in range(steps.load.size):
        result.steps.append(_step(i, config, rows, steps, spread, result.notes))
        result.regime_disagreements += _disagreements(i, result.steps[-1])
    fluid = [s.friction_measured for s in result.steps if s.regime == "fluid"]
    result.friction_fluid = float(np.mean(fluid)) if fluid else None
    result.h_min_smallest = float(np.min(steps.h_min))
    return result


def _heading(run: Run, readings: Readings, config: MtosConfig, profiles: Profiles) -> MtosResults:
    """What the results hold before any step: the critical film (4.16)-(4.17) and the
    surfaces' roughness, from the profilometer runs the specimen names or the stand's."""
    journal_rq, bush_rq = profiles.rq("journal"), profiles.rq("bush")
    source = ", ".join(
        f"{role}: profilometer run {run.specimen[f'{role}_profile_run']}"
        for role in ("journal", "bush")
        if role in profiles.found
    )
    critical = film.critical_film_thickness(
        journal_roughness=config.journal_roughness,
        bush_roughness=config.bush_roughness,
        misalignment=config.misalignment,
        deflection=config.deflection,
        shape_error=config.shape_error,
    )
    return MtosResults(
        rows=readings.rows(GROUP),
        h_crit=critical.total,
        half_width=config.width / config.diameter,
        journal_rq=config.journal_rq if journal_rq is None else journal_rq,
        bush_rq=config.bush_rq if bush_rq is None else bush_rq,
        roughness_source=source or N_("the stand's configuration"),
        notes=list(profiles.problems),
    )


@dataclass(frozen=True, slots=True)
class _LoadSteps:
    """Every step's measured figures at once (arrays, one value a step)."""

    load: NDArray[np.float64]
    eccentricity: bearing_readings.Eccentricity
    friction: bearing_readings.MeasuredFriction
    oil: bearing_readings.FilmViscosity
    s1: NDArray[np.float64]
    rises: dict[str, NDArray[np.float64]]
    viscosity_at: dict[str, NDArray[np.float64]]
    mu_50: float
    h_min: NDArray[np.float64]
    h_crit: float
    film_parameter: NDArray[np.float64]

    @classmethod
    def of(
        cls, config: MtosConfig, rows: Columns, zeros: dict[str, float], result: MtosResults
    ) -> _LoadSteps:
        load = rows["load"]
        viscosity = config.viscosity
        eccentricity = bearing_readings.mtos_eccentricity(
            x=rows["x"] * _M_PER_UM,
            y=rows["y"] * _M_PER_UM,
            x_set=zeros["x_zero"] * _M_PER_UM,
            y_set=zeros["y_zero"] * _M_PER_UM,
            clearance=config.clearance,
            signed=config.signed_sensors,
        )
        oil = bearing_readings.mtos_film_viscosity(
            t3=rows["t3"], t4=rows["t4"], t5=rows["t5"], A=viscosity.A, alpha=viscosity.alpha
        )
        h_min = film.minimum_film_thickness(
            clearance=config.clearance, chi=np.minimum(eccentricity.chi, 1.0)
        )
        return cls(
            load=load,
            eccentricity=eccentricity,
            friction=bearing_readings.mtos_friction(
                indicator_travel=rows["indicator"] * _M_PER_MM,
                spring_rate=config.spring_rate * _N_PER_M,
                spring_arm=config.lever_moment_arm,
                friction_arm=config.friction_arm,
                load=load,
            ),
            oil=oil,
            s1=bearing_readings.bearing_characteristic(
                viscosity=oil.mean,
                omega=config.omega,
                load=load,
                width=config.width,
                diameter=config.diameter,
            ),
            rises={
                f"t{k}": bearing_readings.temperature_rise(t=rows[f"t{k}"], t_in=rows["t1"])
                for k in (2, 3, 4, 5)
            },
            viscosity_at={
                f"t{k}": bearing_readings.viscosity(
                    t=rows[f"t{k}"], A=viscosity.A, alpha=viscosity.alpha
                )
                for k in (1, 2, 3, 4, 5)
            },
            mu_50=float(
                bearing_readings.viscosity(t=REFERENCE_T, A=viscosity.A, alpha=viscosity.alpha)
            ),
            h_min=h_min,
            h_crit=result.h_crit,
            film_parameter=film.film_parameter(
                h_min=h_min, journal_rq=result.journal_rq, bush_rq=result.bush_rq
            ),
        )


@dataclass(frozen=True, slots=True)
class _Spread:
    """The inputs' uncertainties shared by every step (the stand's accuracy, GUM)."""

    x_zero: UFloat
    y_zero: UFloat
    clearance: UFloat
    arms: UFloat

    @classmethod
    def of(cls, config: MtosConfig, zeros: dict[str, float]) -> _Spread:
        accuracy = config.accuracy
        rate = config.spring_rate * _N_PER_M
        return cls(
            x_zero=uncertainty.from_limit(
                zeros["x_zero"] * _M_PER_UM, accuracy.displacement * _M_PER_UM
            ),
            y_zero=uncertainty.from_limit(
                zeros["y_zero"] * _M_PER_UM, accuracy.displacement * _M_PER_UM
            ),
            clearance=uncertainty.from_limit(config.clearance, accuracy.clearance),
            arms=uncertainty.from_limit(config.lever_moment_arm, accuracy.arms)
            / uncertainty.from_limit(config.friction_arm, accuracy.arms)
            * uncertainty.from_limit(rate, rate * accuracy.spring_rate),
        )


def _step(
    i: int, config: MtosConfig, rows: Columns, steps: _LoadSteps, spread: _Spread, notes: list[str]
) -> MtosStep:
    """Step ``i``'s row of tables 4.4-4.6."""
    regime = REGIMES[int(rows["regime"][i])]
    ecc, friction = steps.eccentricity, steps.friction
    load, chi, viscosity = float(steps.load[i]), float(ecc.chi[i]), float(steps.oil.mean[i])
    try:
        angles = bearing_readings.mtos_attitude_angles(e_x=ecc.e_x[i], e_y=ecc.e_y[i])
        angle = float(np.degrees(angles.delta if regime == "fluid" else angles.gamma))
    except ModelInputError:
        angle = 0.0
        notes.append(f"step {i}: journal centred, the angle (4.12) is undefined")
    f_finite, load_finite = (
        _finite(config, chi, viscosity, load) if i < MAX_FINITE_STEPS else (None, None)
    )
    theory = _Theory()
    if regime == "fluid":
        theory = _fluid_theory(i, config, chi, viscosity, load, steps, notes)
    u_chi, u_f = _uncertainties(i, config, rows, spread, load)
    if u_chi is None:
        notes.append(f"step {i}: journal centred, u(χ) is undefined to first order (GUM 5.1.2)")
    s1 = float(steps.s1[i])
    h_min, lam = float(steps.h_min[i]), float(steps.film_parameter[i])
    return MtosStep(
        chi_uncertainty=None if u_chi is None else u_chi.standard,
        chi_expanded=None if u_chi is None else u_chi.expanded,
        friction_measured_uncertainty=u_f.standard,
        friction_measured_expanded=u_f.expanded,
        load=load,
        regime=regime,
        e_x=float(ecc.e_x[i]),
        e_y=float(ecc.e_y[i]),
        e=float(ecc.e[i]),
        chi=chi,
        angle=angle,
        spring_force=float(friction.spring_force[i]),
        friction_moment=float(friction.moment[i]),
        friction_force=float(friction.friction_force[i]),
        friction_measured=float(friction.coefficient[i]),
        viscosity=viscosity,
        bearing_characteristic=s1,
        temperature_rise={k: float(v[i]) for k, v in steps.rises.items()},
        viscosity_at={k: float(v[i]) for k, v in steps.viscosity_at.items()},
        bearing_characteristic_inverse=1.0 / s1 if s1 > 0 else None,
        **theory.table_4_4,
        friction_theory=theory.friction,
        friction_error=theory.error,
        friction_finite=f_finite,
        load_finite=load_finite,
        h_min=h_min,
        film=film.film_regime(h_min=h_min, h_crit=steps.h_crit),
        film_parameter=lam,
        film_lambda=film.lambda_regime(film_parameter=lam),
    )


@dataclass(frozen=True, slots=True)
class _Theory:
    """A fluid-film step's theory: f_T (4.1), its error against the measured f, and the
    rest of table 4.4; nothing for a step in another regime."""

    friction: float | None = None
    error: float | None = None
    table_4_4: dict[str, float] = field(default_factory=dict)


def _fluid_theory(
    i: int,
    config: MtosConfig,
    chi: float,
    viscosity: float,
    load: float,
    steps: _LoadSteps,
    notes: list[str],
) -> _Theory:
    try:
        f_t = bearing.friction_coefficient_theoretical(
            chi=chi,
            omega=config.omega,
            viscosity=viscosity,
            bearing_radius=config.diameter / 2.0,
            width=config.width,
            clearance=config.clearance,
            load=load,
        )
        error = float(
            bearing_readings.relative_error_percent(
                reference=steps.friction.coefficient[i], other=f_t
            ).percent
        )
        return _Theory(
            friction=float(f_t),
            error=None if np.isnan(error) else error,
            table_4_4=_table_4_4(config, chi, viscosity, steps.mu_50),
        )
    except ModelInputError as exc:
        notes.append(f"step {i}: f_T not computed: {exc}")
        return _Theory()


def _uncertainties(
    i: int, config: MtosConfig, rows: Columns, spread: _Spread, load: float
) -> tuple[uncertainty.Estimate | None, uncertainty.Estimate]:
    """The standard and expanded uncertainties of step ``i``'s χ (4.9) and measured f
    (4.11), from the gauges' limits (GUM); none of χ for a centred journal, where χ's
    derivatives are undefined."""
    accuracy = config.accuracy
    u_chi = uncertainty.first_order(
        lambda: uncertainty.mtos_chi(
            x=float(rows["x"][i]) * _M_PER_UM,
            y=float(rows["y"][i]) * _M_PER_UM,
            x_zero=spread.x_zero,
            y_zero=spread.y_zero,
            limit=accuracy.displacement * _M_PER_UM,
            clearance=spread.clearance,
            signed=config.signed_sensors,
        )
    )
    u_f = uncertainty.estimate(
        spread.arms
        * uncertainty.from_limit(
            float(rows["indicator"][i]) * _M_PER_MM, accuracy.indicator * _M_PER_MM
        )
        / uncertainty.from_limit(load, load * accuracy.dynamometer)
    )
    return u_chi, u_f


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
