"""The slide-bearing stand (lab work 3): hydrodynamic pressure at five holes as the load turns.

The journal turns at ω0; the floating bearing carries the loader's force, turned by the limb.
The bearing model (:mod:`rigsim.bearing_model`, finite-length by default; with ``"short"``
the pressure is Hirani's finite-length blend, not (3.10) itself) gives the eccentricity
ratio χ, the attitude angle ψ and the pressure field p(φ, z), at the viscosity of the mean
oil temperature (t1 + t2)/2 (3.21)-(3.22), which a steady heat balance sets
(:mod:`rigsim.thermal`: the film's mean temperature is the mean of inlet and outlet, so the
oil's share of the balance is 2ρc_pQ).

Angles. The manometers sit in the meridional plane at ``hole_limb`` on the limb (90°). The
film is thinnest on the line of centres, ψ past the load in the direction of rotation, and
the film ruptures φ_r further on (φ_r = 0 for the asymptotes, a few degrees for the
finite-length film with the Reynolds condition), so the pressure at the holes falls to zero
with the limb at φ_k = hole_limb + ψ + φ_r. The lab turns the limb back from φ_k in 10°
steps over 180°. (3.20) takes φ_мод = 360° - (φ_k - φ_лимб), i.e. the end of the load zone
at the thinnest film (3.11); the hole truly sees φ = φ_мод + φ_r, where the simulator
evaluates p. The limb is set exactly to its divisions; φ_k is read to a degree.

Displacements. The zero readings are taken at 10 mm of the loader scale without oil, the
limb at 45° (Y_уст) and 135° (X_уст): the bearing then rests on the journal along the sensor's
axis, e_y (e_x) = h0. The load pushes the bearing along 135° - φ_лимб from the X axis, and the
line of centres leads it by ψ. Each gauge reads less as the bearing leaves its zero contact:
X = X_уст - (h0 - e_x)/d with d the gauge's scale, so (3.16) e_x = h0 - |X_уст - X| gives e_x
back for every position (|e_x| <= e < h0); likewise Y.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rigserver.core import bearing
from rigserver.core import bearing_readings as processing
from rigsim.batches import Batch, FloatArray, SimulatedRun, split
from rigsim.bearing_model import DEFAULT_MODEL, BearingModel, Film, Geometry, refined
from rigsim.bearing_model import film as bearing_film
from rigsim.errors import SettingsError
from rigsim.instruments import Fault, Instrument, apply_faults
from rigsim.thermal import HeatBalance, steady_film_temperature
from schemas.runs import RunCreate
from schemas.stands import MEASUREMENTS, SLIDE_BEARING_GROUPS, SlideBearingConfig, StandKind
from schemas.units import UNITS

_LITRE_PER_MIN = 1e-3 / 60.0


_MANOMETER = Instrument(resolution=0.05, noise=0.02)
_DISPLACEMENT = Instrument(resolution=1.0, noise=0.3)
_THERMOMETER = Instrument(resolution=0.1, noise=0.05)
_LIMB = Instrument(resolution=1.0, noise=0.5)


@dataclass(frozen=True, slots=True)
class SlideBearingInstruments:
    """The stand's instruments, each in its channel's unit."""

    manometer: Instrument = _MANOMETER
    displacement: Instrument = _DISPLACEMENT
    thermometer: Instrument = _THERMOMETER
    limb: Instrument = _LIMB


@dataclass(frozen=True, slots=True)
class SlideBearingSettings:
    """What the simulated lab does on the slide-bearing stand; defaults from the manual.

    Attributes
    ----------
    loader_scale : float
        Loader scale setting, mm (16.2 N/mm): 20 mm is 324 N.
    limb_step, limb_span : float
        The limb is turned back from φ_k in steps of ``limb_step`` over ``limb_span``, deg.
    model : {"finite", "short"}
        Bearing model of the truth.
    configuration : SlideBearingConfig
        The stand's configuration (the manual's values), posted with the run.
    inlet_temperature : float
        Oil at the inlet, °C.
    oil_flow : float
        Gravity feed through the bearing, m³/s (0.2 l/min).
    conductance : float
        Heat carried off by the journal and housing, W/K.
    hole_limb : float
        Limb reading of the manometers' meridional plane, deg (90°).
    row_interval : float
        Time per limb position, s.
    x_zero, y_zero : float
        Gauge readings at the zero positions, divisions.
    instruments : SlideBearingInstruments
    faults : tuple of Fault
    operator : str
    """

    loader_scale: float = 20.0
    limb_step: float = 10.0
    limb_span: float = 180.0
    model: BearingModel = DEFAULT_MODEL
    configuration: SlideBearingConfig = field(default_factory=SlideBearingConfig)
    inlet_temperature: float = 22.0
    oil_flow: float = 0.2 * _LITRE_PER_MIN
    conductance: float = 2.0
    hole_limb: float = 90.0
    row_interval: float = 60.0
    x_zero: float = 400.0
    y_zero: float = 380.0
    instruments: SlideBearingInstruments = SlideBearingInstruments()
    faults: tuple[Fault, ...] = ()
    operator: str = "rigsim"

    def __post_init__(self) -> None:
        if not 0.0 < self.loader_scale <= 1000.0:
            raise SettingsError(
                f"loader_scale must lie in (0, 1000] mm (the loader's scale), "
                f"got {self.loader_scale}"
            )
        if not 0.0 < self.limb_step <= self.limb_span <= 360.0:
            raise SettingsError(
                f"need 0 < limb_step <= limb_span <= 360 deg, got {self.limb_step}, "
                f"{self.limb_span}"
            )

    @property
    def load(self) -> float:
        """The loader's force, N."""
        return self.loader_scale * self.configuration.loader_rate


@dataclass(frozen=True, slots=True)
class SlideBearingTruth:
    """The simulated slide-bearing run's truth.

    Attributes
    ----------
    model : str
        Bearing model used.
    load : float
        N.
    chi : float
        Eccentricity ratio χ (the same at every limb position).
    attitude_angle : float
        ψ, rad.
    load_zone_end : float
        φ_k, limb angle of the end of the load zone, deg.
    rupture_angle : float
        φ_r, where the film ruptures past the thinnest film, deg.
    temperature : float
        Mean oil temperature (t1 + t2)/2, °C.
    viscosity : float
        μ_t at that temperature (3.21), Pa·s.
    mu_bar : float
        μ_t/μ0 (3.22).
    phi_model : ndarray
        φ_мод of each row by (3.20) with the true φ_k, deg.
    pressure : ndarray, shape (rows, 5)
        Gauge pressure at the five manometers, Pa, at φ_мод + φ_r.
    """

    model: BearingModel
    load: float
    chi: float
    attitude_angle: float
    load_zone_end: float
    rupture_angle: float
    temperature: float
    viscosity: float
    mu_bar: float
    phi_model: FloatArray
    pressure: FloatArray


def _rupture_deg(film: Film) -> float:
    """φ_r: the first angle past the thinnest film where p(φ, 0) is below 0.1 % of its peak."""
    return bearing.rupture_angle_deg(pressure=lambda phi: film.pressure(phi=phi, z=0.0))


def simulate(
    settings: SlideBearingSettings | None = None, seed: int = 0
) -> SimulatedRun[SlideBearingTruth]:
    """A simulated slide-bearing run: zero readings, φ_k, then one row per limb position."""
    s = settings or SlideBearingSettings()
    rng = np.random.default_rng(seed)
    c = s.configuration
    law = c.viscosity
    geometry = Geometry(radius=c.bearing_radius, width=c.width, clearance=c.clearance)

    def state(t_mean: float) -> Film:
        mu = float(processing.viscosity(t=t_mean, A=law.A, alpha=law.alpha))
        return bearing_film(
            model=s.model, load=s.load, omega=c.omega0, viscosity=mu, geometry=geometry
        )

    # The film's mean temperature is (t1 + t2)/2: the oil carries 2ρc_pQ per kelvin of it.
    balance = HeatBalance(oil_flow=2.0 * s.oil_flow, conductance=s.conductance)
    hot = steady_film_temperature(
        power=lambda t: state(t).friction_moment * c.omega0,
        inlet=s.inlet_temperature,
        balance=balance,
    )
    t_mean = hot.temperature
    film = refined(state(t_mean), half_width=c.width / (2.0 * c.bearing_radius))
    mu_t = float(processing.viscosity(t=t_mean, A=law.A, alpha=law.alpha))
    psi_deg = float(np.degrees(film.attitude_angle))
    rupture = _rupture_deg(film)
    ins = s.instruments
    phi_k_true = s.hole_limb + psi_deg + rupture
    phi_k = float(ins.limb.read([phi_k_true], rng)[0])
    n_rows = int(np.floor(s.limb_span / s.limb_step + 1e-9)) + 1
    limb: FloatArray = phi_k - s.limb_step * np.arange(n_rows, dtype=np.float64)
    phi_model: FloatArray = 360.0 - (phi_k_true - limb)
    z = np.asarray(c.manometer_z)
    pressure = film.pressure(phi=np.radians(phi_model + rupture)[:, None], z=z[None, :])
    e = film.chi * c.clearance
    theta = np.radians(135.0 - limb) + film.attitude_angle
    e_x, e_y = e * np.cos(theta), e * np.sin(theta)
    d = c.displacement_per_division
    at = s.row_interval * (np.arange(n_rows) + 2.0)
    gauge = UNITS[c.gauge_unit].factor
    t_out = 2.0 * t_mean - s.inlet_temperature
    rows = {
        "limb_angle": limb,
        **{f"p{k + 1}": ins.manometer.read(pressure[:, k] / gauge, rng) for k in range(5)},
        "x": ins.displacement.read(s.x_zero - (c.clearance - e_x) / d, rng, at),
        "y": ins.displacement.read(s.y_zero - (c.clearance - e_y) / d, rng, at),
        "t1": ins.thermometer.read(np.full(n_rows, s.inlet_temperature), rng),
        "t2": ins.thermometer.read(np.full(n_rows, t_out), rng),
    }
    setup = {
        "x_zero": ins.displacement.read([s.x_zero], rng),
        "y_zero": ins.displacement.read([s.y_zero], rng),
        "loader_scale": np.array([s.loader_scale]),
        "load_zone_end": np.array([phi_k]),
    }
    rows_group, setup_group = SLIDE_BEARING_GROUPS
    rows, at = apply_faults(rows_group, rows, at, s.faults)
    setup, _ = apply_faults(setup_group, setup, np.zeros(1), s.faults)
    batches: list[Batch] = []
    if setup:
        batches.append(Batch(group=MEASUREMENTS, columns=setup, at=s.row_interval))
    batches += split("rows", rows, at, rows=1)
    body = RunCreate(
        stand=StandKind.SLIDE_BEARING,
        operator=s.operator,
        title=f"Simulated slide-bearing run ({s.model} bearing model)",
        specimen={"journal": "steel 45", "bearing": "bronze"},
        test_plan={
            "loader_scale_mm": s.loader_scale,
            "limb_step_deg": s.limb_step,
            "bearing_model": s.model,
            "simulated": True,
        },
        configuration=c.model_dump(mode="json"),
    )
    truth = SlideBearingTruth(
        model=s.model,
        load=s.load,
        chi=film.chi,
        attitude_angle=film.attitude_angle,
        load_zone_end=phi_k_true,
        rupture_angle=rupture,
        temperature=t_mean,
        viscosity=mu_t,
        mu_bar=mu_t / c.mu0,
        phi_model=phi_model,
        pressure=pressure,
    )
    return SimulatedRun(run_create=body, batches=tuple(batches), truth=truth)
