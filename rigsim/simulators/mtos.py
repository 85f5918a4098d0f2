"""The MTOS stand (lab work 4): a journal bearing's friction moment, position and temperatures.

For each load step the journal runs where the bearing model puts it
(:mod:`rigsim.bearing_model`, finite-length by default), at the film temperature of a steady
heat balance closed through the viscosity law (:mod:`rigsim.thermal`). The stand's
instruments then show:

- the indicator travel Δl = M/(k·l1) of the flat spring (inverse of (4.13)-(4.14));
- the displacement sensors X, Y (inverse of (4.11), below);
- the thermocouples t1 (inlet), t2 (outlet), t3-t5 (near the loaded film);
- the dynamometer's load N, and the experiment's code (1 fluid, 2 mixed, 3 boundary).

Lubrication regimes. Experiment 1 (full oil feed) runs on the film of the bearing model;
experiments 2 and 3 (50-60 and 3-4 drops/min) starve it, and the simulator sets the minimum
film thickness by the film parameter, h_min = Λ·√(Rq_journal² + Rq_bush²) with Λ = 2.5 (mixed,
1 <= Λ <= 3) and Λ = 0.5 (boundary, Λ < 1) by default (Hamrock, Schmid and Jacobson's bands;
the manual gives only the drop rates, the Λ are this simulator's choice). Below
h_min^crit, in any experiment, the friction coefficient blends the film's and the boundary
one (0.1-0.15, seed 000) by the film thickness: f = f_b + (f_film - f_b)·h_min/h_min^crit.

Position and (4.11). The zero readings X_уст, Y_уст are taken at 2 kN without oil, the
journal resting on the bush on the load line, which is the 45° line between the sensors: there
e_x = e_y = h0·cos45°. Each sensor reads more as the journal lifts off that point:
X = X_уст + (h0·cos45° - e_x), Y = Y_уст + (h0·cos45° - e_y), so (4.11)
e_x = h0·cos45° - |X_уст - X| gives back e_x wherever e_x <= h0·cos45° (likewise e_y). The
line of centres is at 45° + ψ from the X axis in the fluid film (ψ the attitude angle, so
δ of (4.12) is ψ), and at 45° - γ with tg γ = f in mixed and boundary friction (fig. 4.2, a).
Near the bush a component can exceed h0·cos45°: (4.11)'s |·| then folds it back, and the
stand's χ is wrong; :attr:`MtosStepTruth.representable` says where.

The friction moment is M = f·N·R1 on the journal; the simulated stand's friction arm l2 is
the journal radius R1 = D/2 - h0, so f_э = M/(l2·N) of (4.15)-(4.16) is f.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from rigserver.core import bearing_readings as processing
from rigserver.core import film as film_criterion
from rigsim.batches import Batch, SimulatedRun, split
from rigsim.bearing_model import DEFAULT_MODEL, BearingModel, Geometry
from rigsim.bearing_model import film as bearing_film
from rigsim.errors import SettingsError
from rigsim.instruments import Fault, Instrument, apply_faults
from rigsim.thermal import DROP_VOLUME, HeatBalance, steady_film_temperature
from schemas.runs import RunCreate
from schemas.stands import MEASUREMENTS, MTOS_GROUPS, MtosConfig, StandKind

Regime = Literal[1, 2, 3]
FilmState = Literal["fluid", "mixed", "boundary"]
_COS45 = float(np.cos(np.pi / 4.0))
#: Thermocouples t3, t4, t5 sit at, above and below the film's mean temperature rise.
_THERMOCOUPLE_SPREAD = (-0.05, 0.08, -0.03)
#: The outlet oil carries this share of the film's rise (it mixes with the side leakage).
_OUTLET_SHARE = 0.8
_LITRE_PER_MIN = 1e-3 / 60.0


def simulated_configuration() -> MtosConfig:
    """The simulated stand's configuration (the schema's defaults are placeholders).

    D = B = 50 mm, h0 = 30 μm (ψ = 0.0012), ω = 52.4 rad/s (500 rpm); a flat spring of
    4 N/mm on an arm of 0.25 m (Δl = 1 mm per N·m: 0.2 mm at the lightest fluid step, 6 mm
    at the heaviest boundary one); friction arm l2 = R1. The sensors read more as the journal
    lifts off the zero contact, and the stand says so (``signed_sensors``), so the analysis
    reads the starved steps, rolled up the bush by γ, without the fold of (4.11)'s |·|.
    """
    diameter, clearance = 0.050, 30e-6
    return MtosConfig(
        spring_rate=4.0,
        lever_moment_arm=0.25,
        friction_arm=diameter / 2.0 - clearance,
        diameter=diameter,
        width=0.050,
        clearance=clearance,
        omega=52.4,
        signed_sensors=True,
    )


_INDICATOR = Instrument(resolution=0.001, noise=0.0005)
_DISPLACEMENT = Instrument(resolution=0.1, noise=0.05, drift=1e-5)
_THERMOCOUPLE = Instrument(resolution=0.1, noise=0.05)
_DYNAMOMETER = Instrument(resolution=5.0, noise=1.0)


@dataclass(frozen=True, slots=True)
class MtosInstruments:
    """The MTOS instruments, each in its channel's unit."""

    indicator: Instrument = _INDICATOR
    displacement: Instrument = _DISPLACEMENT
    thermocouple: Instrument = _THERMOCOUPLE
    dynamometer: Instrument = _DYNAMOMETER


@dataclass(frozen=True, slots=True)
class MtosSettings:
    """What the simulated lab does on the MTOS stand; defaults from the manual.

    Attributes
    ----------
    loads_fluid, loads_mixed, loads_boundary : tuple of float
        Load steps of experiments 1, 2 and 3, N (500..3000 step 500; 500, 1500, 2500).
    model : {"finite", "short"}
        Bearing model of the truth.
    configuration : MtosConfig
        The stand's configuration, posted with the run.
    inlet_temperature : float
        Oil at the inlet, °C.
    oil_flow : float
        Full feed of experiment 1, m³/s (0.05 l/min).
    drops_mixed, drops_boundary : float
        Drip feed of experiments 2 and 3, drops/min (50-60, 3-4).
    conductance : float
        Heat carried off by the journal and housing, W/K.
    boundary_friction : float
        Friction coefficient of boundary lubrication (seed 000: 0.1-0.15).
    film_parameter_mixed, film_parameter_boundary : float
        Λ = h_min/√(Rq_journal² + Rq_bush²) of the starved film in experiments 2 and 3.
    step_duration : float
        Time at each load, s (2-3 min).
    x_zero, y_zero : float
        Sensor readings at the zero position (X_уст, Y_уст), μm.
    instruments : MtosInstruments
    faults : tuple of Fault
    operator : str
    """

    loads_fluid: tuple[float, ...] = (500.0, 1000.0, 1500.0, 2000.0, 2500.0, 3000.0)
    loads_mixed: tuple[float, ...] = (500.0, 1500.0, 2500.0)
    loads_boundary: tuple[float, ...] = (500.0, 1500.0, 2500.0)
    model: BearingModel = DEFAULT_MODEL
    configuration: MtosConfig = field(default_factory=simulated_configuration)
    inlet_temperature: float = 25.0
    oil_flow: float = 0.05 * _LITRE_PER_MIN
    drops_mixed: float = 55.0
    drops_boundary: float = 3.5
    conductance: float = 6.0
    boundary_friction: float = 0.12
    film_parameter_mixed: float = 2.5
    film_parameter_boundary: float = 0.5
    step_duration: float = 150.0
    x_zero: float = 250.0
    y_zero: float = 310.0
    instruments: MtosInstruments = MtosInstruments()
    faults: tuple[Fault, ...] = ()
    operator: str = "rigsim"

    def __post_init__(self) -> None:
        loads = (*self.loads_fluid, *self.loads_mixed, *self.loads_boundary)
        if not loads:
            raise SettingsError("the MTOS run needs at least one load step")
        for load in loads:
            if not 0.0 < load <= 10_000.0:
                raise SettingsError(f"load must lie in (0, 10000] N (dynamometer), got {load}")
        if not 0.0 < self.boundary_friction < 1.0:
            raise SettingsError(
                f"boundary_friction must lie in (0, 1), got {self.boundary_friction}"
            )
        for name in ("film_parameter_mixed", "film_parameter_boundary"):
            if not 0.0 < getattr(self, name) <= 10.0:
                raise SettingsError(f"{name} must lie in (0, 10], got {getattr(self, name)}")
        if self.step_duration <= 0:
            raise SettingsError(f"step_duration must be > 0 s, got {self.step_duration}")

    def steps(self) -> list[tuple[Regime, float]]:
        """(experiment, load) in the order the lab runs them."""
        return [
            *((1, n) for n in self.loads_fluid),
            *((2, n) for n in self.loads_mixed),
            *((3, n) for n in self.loads_boundary),
        ]


@dataclass(frozen=True, slots=True)
class MtosStepTruth:
    """The true state at the end of one load step.

    Attributes
    ----------
    regime : int
        Experiment: 1 fluid feed, 2 mixed (drops), 3 boundary (drops).
    load : float
        N, N.
    film_temperature : float
        Mean film temperature, °C.
    temperatures : tuple of float
        t1..t5, °C.
    viscosity : float
        μ_t = (μ3 + μ4 + μ5)/3 at the true t3..t5 (4.18), Pa·s.
    chi : float
        Eccentricity ratio χ.
    angle : float
        Line of centres from the X axis minus 45°: δ = ψ (fluid feed) or -γ (drops), rad.
    e_x, e_y : float
        Eccentricity components along the sensors, m.
    h_min : float
        Minimum film thickness, m.
    friction : float
        f = M/(N·R1).
    friction_moment : float
        M, N·m.
    film : {"fluid", "mixed", "boundary"}
        Lubrication: fluid when h_min >= h_min^crit; else by the film parameter, boundary
        when Λ < 1, mixed otherwise.
    film_parameter : float
        Λ = h_min/√(Rq_journal² + Rq_bush²).
    representable : bool
        Whether (4.11) can give back e_x and e_y (both <= h0·cos45°).
    """

    regime: Regime
    load: float
    film_temperature: float
    temperatures: tuple[float, float, float, float, float]
    viscosity: float
    chi: float
    angle: float
    e_x: float
    e_y: float
    h_min: float
    friction: float
    friction_moment: float
    film: FilmState
    film_parameter: float
    representable: bool


@dataclass(frozen=True, slots=True)
class MtosTruth:
    """The simulated MTOS run's truth.

    Attributes
    ----------
    model : str
        Bearing model used.
    h_crit : float
        h_min^crit (2.105), m.
    steps : tuple of MtosStepTruth
    """

    model: BearingModel
    h_crit: float
    steps: tuple[MtosStepTruth, ...]


@dataclass(frozen=True, slots=True)
class _Friction:
    moment: float
    f: float
    chi: float
    attitude: float | None
    h_min: float


def _temperatures(film_t: float, inlet: float) -> tuple[float, float, float, float, float]:
    rise = film_t - inlet
    t3, t4, t5 = (film_t + s * rise for s in _THERMOCOUPLE_SPREAD)
    return (inlet, inlet + _OUTLET_SHARE * rise, t3, t4, t5)


def _step(
    s: MtosSettings, geometry: Geometry, h_crit: float, regime: Regime, load: float
) -> MtosStepTruth:
    c = s.configuration
    law = c.viscosity
    r1 = geometry.journal_radius
    roughness = float(np.hypot(c.journal_rq, c.bush_rq))

    def film_viscosity(film_t: float) -> float:
        t = _temperatures(film_t, s.inlet_temperature)
        mu = processing.mtos_film_viscosity(t3=t[2], t4=t[3], t5=t[4], A=law.A, alpha=law.alpha)
        return float(mu.mean)

    def friction(film_t: float) -> _Friction:
        try:
            state = bearing_film(
                model=s.model,
                load=load,
                omega=c.omega,
                viscosity=film_viscosity(film_t),
                geometry=geometry,
            )
        except SettingsError:  # the film collapses: nothing but the asperities carry the load
            h_film, f_film, attitude = 0.0, s.boundary_friction, None
        else:
            h_film = c.clearance * (1.0 - state.chi)
            f_film = state.friction_moment / (load * r1)
            attitude = state.attitude_angle
        starved = {1: None, 2: s.film_parameter_mixed, 3: s.film_parameter_boundary}[regime]
        h_min = h_film if starved is None else min(h_film, starved * roughness)
        f = f_film
        if h_min < h_crit:
            f = s.boundary_friction + (f_film - s.boundary_friction) * h_min / h_crit
        return _Friction(f * load * r1, f, 1.0 - h_min / c.clearance, attitude, h_min)

    feed = (
        s.oil_flow
        if regime == 1
        else DROP_VOLUME / 60.0 * (s.drops_mixed if regime == 2 else s.drops_boundary)
    )
    balance = HeatBalance(oil_flow=feed, conductance=s.conductance)
    hot = steady_film_temperature(
        power=lambda t: friction(t).moment * c.omega,
        inlet=s.inlet_temperature,
        balance=balance,
    )
    state = friction(hot.temperature)
    # On a film the line of centres leads the load by ψ; on the asperities it trails it by
    # the friction angle γ, tg γ = f (fig. 4.2).
    angle = -float(np.arctan(state.f))
    if regime == 1 and state.attitude is not None:
        angle = state.attitude
    theta = np.pi / 4.0 + angle
    e = state.chi * c.clearance
    e_x, e_y = float(e * np.cos(theta)), float(e * np.sin(theta))
    film: FilmState = "fluid"
    if state.h_min < h_crit:
        film = "boundary" if state.h_min < roughness else "mixed"
    limit = c.clearance * _COS45
    return MtosStepTruth(
        regime=regime,
        load=load,
        film_temperature=hot.temperature,
        temperatures=_temperatures(hot.temperature, s.inlet_temperature),
        viscosity=film_viscosity(hot.temperature),
        chi=state.chi,
        angle=angle,
        e_x=e_x,
        e_y=e_y,
        h_min=state.h_min,
        friction=state.f,
        friction_moment=state.moment,
        film=film,
        film_parameter=state.h_min / roughness,
        representable=e_x <= limit and e_y <= limit,
    )


def truth_of(settings: MtosSettings) -> MtosTruth:
    """The true state of every step (no instruments, no randomness)."""
    c = settings.configuration
    geometry = Geometry(radius=c.diameter / 2.0, width=c.width, clearance=c.clearance)
    h_crit = film_criterion.critical_film_thickness(
        journal_roughness=c.journal_roughness,
        bush_roughness=c.bush_roughness,
        misalignment=c.misalignment,
        deflection=c.deflection,
        shape_error=c.shape_error,
    ).total
    steps = tuple(_step(settings, geometry, h_crit, r, n) for r, n in settings.steps())
    return MtosTruth(model=settings.model, h_crit=h_crit, steps=steps)


def simulate(settings: MtosSettings | None = None, seed: int = 0) -> SimulatedRun[MtosTruth]:
    """A simulated MTOS run: zero readings, then one row per load step, every 2-3 minutes."""
    s = settings or MtosSettings()
    rng = np.random.default_rng(seed)
    truth = truth_of(s)
    c = s.configuration
    ins = s.instruments
    steps = truth.steps
    at = s.step_duration * np.arange(1, len(steps) + 1)
    limit_um = c.clearance * _COS45 * 1e6
    e_x = np.array([t.e_x for t in steps]) * 1e6
    e_y = np.array([t.e_y for t in steps]) * 1e6
    temps = np.array([t.temperatures for t in steps])
    moment = np.array([t.friction_moment for t in steps])
    rows = {
        "load": ins.dynamometer.read([t.load for t in steps], rng),
        "indicator": ins.indicator.read(moment / c.lever_moment_arm / c.spring_rate, rng),
        "x": ins.displacement.read(s.x_zero + limit_um - e_x, rng, at),
        "y": ins.displacement.read(s.y_zero + limit_um - e_y, rng, at),
        **{f"t{k + 1}": ins.thermocouple.read(temps[:, k], rng) for k in range(5)},
        "regime": np.array([float(t.regime) for t in steps]),
    }
    zero = {
        "x_zero": ins.displacement.read([s.x_zero], rng),
        "y_zero": ins.displacement.read([s.y_zero], rng),
    }
    group_steps, group_zero = MTOS_GROUPS
    rows, at = apply_faults(group_steps, rows, at, s.faults)
    zero, zero_at = apply_faults(group_zero, zero, np.zeros(1), s.faults)
    batches: list[Batch] = []
    if zero:
        batches.append(Batch(group=MEASUREMENTS, columns=zero, at=float(zero_at[0])))
    batches += split("steps", rows, at, rows=1)
    body = RunCreate(
        stand=StandKind.MTOS,
        operator=s.operator,
        title=f"Simulated MTOS run ({s.model} bearing model)",
        specimen={"journal": "steel 45", "bush": "bronze BrO10F1"},
        test_plan={
            "loads_fluid": list(s.loads_fluid),
            "loads_mixed": list(s.loads_mixed),
            "loads_boundary": list(s.loads_boundary),
            "bearing_model": s.model,
            "simulated": True,
        },
        configuration=c.model_dump(mode="json"),
    )
    return SimulatedRun(run_create=body, batches=tuple(batches), truth=truth)
