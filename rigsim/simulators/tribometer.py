"""Commercial tribometers: a ball (or flat pin) on a disc (ASTM G99, ISO 20808) and on a
reciprocating flat (ASTM G133).

The friction coefficient runs in from its static value μ_s to its steady value μ_ss over a
known distance L_r along a truncated exponential that ends there,

    μ(s) = μ_ss + (μ_s - μ_ss)·(e^(-s/λ) - e^(-L_r/λ))/(1 - e^(-L_r/λ)) for s < L_r, λ = L_r/3,

and is μ_ss after it. Its running-in as a tribologist reads it ends earlier, where the
transient's excess falls to the steady band, δ·μ_ss (``settled_distance``, in closed form);
on the disc a once-per-lap part μ_ss·a·sin θ rides on it (a run-out),
on the flat μ_ss·a·cos 2φ over the cycle's phase φ (friction highest at the stroke's ends,
x = -S/2·cos φ), both averaging out over whole laps; the friction's fluctuation is AR(1)
(as the SMTs-2's). Readings are taken a whole number of times per lap (cycle), so lap means
and the steady mean hold no periodic remainder. The instrument writes the normal load, the
friction force and μ = F_t/F_N of its own two readings.

Wear follows Archard's law, V = k·F·L for the ball and for the disc (flat): the ball's
scar is the spherical cap of that volume, the track a parabolic groove of the scar's width
and the area V/(2πR) (V/S on the flat), traced across in four places; the specimens lose
ρ·V on the balance. Defaults: an Al2O3 ball of 6 mm on 100Cr6, 5 N, 0.1 m/s on a 10 mm
radius, 1000 laps (63 m); on the flat 10 mm strokes at 5 Hz, 1000 cycles.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from rigserver.core import tribometer
from rigserver.core.tribometer import STEADY_BAND
from rigsim.batches import Batch, SimulatedRun, split
from rigsim.errors import SettingsError
from rigsim.instruments import Fault, Instrument, apply_faults
from rigsim.simulators.smts2 import _fluctuation
from schemas.runs import RunCreate
from schemas.stands import (
    MEASUREMENTS,
    PIN_ON_DISC_GROUPS,
    RECIPROCATING_GROUPS,
    PinOnDiscConfig,
    ReciprocatingConfig,
    StandKind,
)
from schemas.units import UNITS

FloatArray = NDArray[np.float64]
Kind = Literal["pin_on_disc", "reciprocating"]
_KG_PER_G = UNITS["g"].factor
_M_PER_UM = UNITS["um"].factor
#: Profiles traced across the track, and their half-length and step, m.
TRACES = 4
TRACE_HALF = 1.5e-3
TRACE_STEP = 5e-6


_LOAD = Instrument(resolution=1e-3, noise=0.01)
_FORCE = Instrument(resolution=1e-4, noise=0.002)
_THERMOMETER = Instrument(resolution=0.1, noise=0.1)
_DEPTH = Instrument(resolution=0.01, noise=0.05)
_PROFILOMETER = Instrument(resolution=0.001, noise=0.005)
_MICROSCOPE = Instrument(resolution=1.0, noise=1.0)
_BALANCE = Instrument(resolution=1e-5, noise=1e-5)


@dataclass(frozen=True, slots=True)
class TribometerInstruments:
    """The tribometer's sensors, each in its channel's unit."""

    load: Instrument = _LOAD
    force: Instrument = _FORCE
    thermometer: Instrument = _THERMOMETER
    depth: Instrument = _DEPTH
    profilometer: Instrument = _PROFILOMETER
    microscope: Instrument = _MICROSCOPE
    balance: Instrument = _BALANCE


@dataclass(frozen=True, slots=True)
class TribometerSettings:
    """What the simulated lab runs; defaults: a ball-on-disc test.

    Attributes
    ----------
    kind : {"pin_on_disc", "reciprocating"}
    load : float
        F_N on the ball, N.
    laps : int
        Laps (cycles) of the test.
    samples_per_lap : int
        Readings per lap (cycle).
    friction_static, friction_steady : float
        μ_s at the start and μ_ss after the running-in.
    running_in_laps : int
        Laps (cycles) of the running-in: L_r = running_in_laps times a lap's length.
    periodic : float
        a, the once-per-lap (per-cycle) part relative to μ_ss.
    friction_fluctuation : float
        Relative standard deviation of the friction's AR(1) fluctuation.
    ball_wear, disc_wear : float
        Archard's k of the ball and the disc, m³/(N·m).
    temperature_rise : float
        Warming of the contact over the test, °C, from the plan's temperature.
    configuration : PinOnDiscConfig | ReciprocatingConfig
    instruments : TribometerInstruments
    faults : tuple of Fault
    operator : str
    batch_rows : int
    """

    kind: Kind = "pin_on_disc"
    load: float = 5.0
    laps: int = 1000
    samples_per_lap: int = 64
    friction_static: float = 0.8
    friction_steady: float = 0.55
    running_in_laps: int = 160
    periodic: float = 0.04
    friction_fluctuation: float = 0.02
    ball_wear: float = 2e-15
    disc_wear: float = 1e-13
    temperature_rise: float = 4.0
    configuration: PinOnDiscConfig | ReciprocatingConfig = field(default_factory=PinOnDiscConfig)
    instruments: TribometerInstruments = TribometerInstruments()
    faults: tuple[Fault, ...] = ()
    operator: str = "rigsim"
    batch_rows: int = 2000

    def __post_init__(self) -> None:
        wanted = PinOnDiscConfig if self.kind == "pin_on_disc" else ReciprocatingConfig
        if type(self.configuration) is not wanted:
            raise SettingsError(f"a {self.kind} run needs a {wanted.__name__}")
        if not 0 < self.running_in_laps < self.laps:
            raise SettingsError(
                f"running_in_laps must lie in (0, laps = {self.laps}), got {self.running_in_laps}"
            )
        if self.samples_per_lap < 8 or self.samples_per_lap % 4:
            raise SettingsError(
                f"samples_per_lap must be >= 8, a multiple of 4: {self.samples_per_lap}"
            )
        for name in ("friction_static", "friction_steady"):
            if not 0.0 < getattr(self, name) < 2.0:
                raise SettingsError(f"{name} must lie in (0, 2), got {getattr(self, name)}")
        if self.load <= 0 or self.ball_wear <= 0 or self.disc_wear <= 0:
            raise SettingsError("load, ball_wear and disc_wear must be > 0")

    @classmethod
    def reciprocating(cls, **changes: object) -> TribometerSettings:
        """A ball on a reciprocating flat (the defaults of the stroke)."""
        base: dict[str, object] = {
            "kind": "reciprocating",
            "samples_per_lap": 80,
            "configuration": ReciprocatingConfig(),
        }
        return cls(**{**base, **changes})  # type: ignore[arg-type]

    @property
    def lap_length(self) -> float:
        c = self.configuration
        if isinstance(c, PinOnDiscConfig):
            return 2.0 * math.pi * c.track_radius
        return 2.0 * c.stroke_length

    @property
    def speed(self) -> float:
        """The mean sliding speed, m/s (reciprocating: 2S·f)."""
        c = self.configuration
        if isinstance(c, ReciprocatingConfig):
            return 2.0 * c.stroke_length * c.frequency
        return c.plan.speed


@dataclass(frozen=True, slots=True)
class TribometerTruth:
    """The simulated run's truth (SI; μ of the noise-free record).

    ``running_in_distance`` is where the true μ's excess over μ_ss falls to the steady band
    δ·μ_ss (:func:`settled_distance`), ``transient_distance`` L_r, where it ends;
    ``friction_static`` is the largest true μ before the running-in's end, ``friction_mean``
    the true μ's mean over the record; the wear volumes are Archard's, the scar's diameter
    and the track's area those of the volumes.
    """

    kind: Kind
    load: float
    laps: float
    sliding_distance: float
    friction_static: float
    friction_steady: float
    friction_mean: float
    running_in_distance: float
    running_in_laps: float
    transient_distance: float
    lap_amplitude: float
    ball_volume: float
    disc_volume: float
    scar_diameter: float
    track_area: float
    track_width: float
    ball_mass_loss: float
    disc_mass_loss: float
    ball_rate: float
    disc_rate: float
    hertz_pressure: float


def running_in_shape(s: FloatArray, length: float) -> FloatArray:
    """g(s): 1 at s = 0, 0 from s = L_r on, the truncated exponential of λ = L_r/3."""
    lam = length / 3.0
    tail = math.exp(-length / lam)
    return np.where(s < length, (np.exp(-s / lam) - tail) / (1.0 - tail), 0.0)


def settled_distance(length: float, static: float, steady: float) -> float:
    """Where the running-in of :func:`running_in_shape` (from μ_s = ``static`` to μ_ss =
    ``steady`` over L_r = ``length``) enters the steady band: (μ_s - μ_ss)·g(s) = δ·|μ_ss|,
    δ = STEADY_BAND, so e^(-s/λ) = e^(-3) + δ·|μ_ss|·(1 - e^(-3))/|μ_s - μ_ss|; 0 when the
    whole transient lies inside the band."""
    drop, allowed = abs(static - steady), STEADY_BAND * abs(steady)
    if drop <= allowed:
        return 0.0
    tail = math.exp(-3.0)
    return -length / 3.0 * math.log(tail + allowed * (1.0 - tail) / drop)


def scar_of(volume: float, radius: float) -> float:
    """The scar diameter of a spherical cap of ``volume`` on a ball of ``radius``."""
    if volume <= 0:
        return 0.0
    return float(
        brentq(
            lambda d: tribometer.spherical_cap_volume(scar_diameter=d, ball_radius=radius) - volume,
            0.0,
            2.0 * radius,
            xtol=1e-15,
            rtol=1e-15,
        )
    )


def track_profile(x: FloatArray, width: float, depth: float, tilt: float = 2e-4) -> FloatArray:
    """A parabolic groove of ``width`` and ``depth`` in a surface tilted by ``tilt``, m."""
    inside = np.abs(x) < width / 2.0
    groove = np.where(inside, depth * (1.0 - (2.0 * x / width) ** 2), 0.0)
    return tilt * x - groove


def simulate(
    settings: TribometerSettings | None = None, seed: int = 0
) -> SimulatedRun[TribometerTruth]:
    """A simulated tribometer run: weighings, the friction record, the track's profiles,
    the scar and the weighings after."""
    s = settings or TribometerSettings()
    rng = np.random.default_rng(seed)
    motion = _Motion.of(s)
    wear = _Wear.of(s, motion.sliding)
    record = _friction_record(s, motion, wear, rng)
    track = _track_profiles(s, wear, rng)
    weighings = _weighings(s, wear, rng)
    groups = RECIPROCATING_GROUPS if motion.reciprocating else PIN_ON_DISC_GROUPS
    friction, at = apply_faults(groups[0], record, motion.time, s.faults)
    track, _ = apply_faults(groups[1], track, np.zeros(track["x"].size), s.faults)
    weighings, _ = apply_faults(groups[2], weighings, np.zeros(1), s.faults)
    before = {k: v for k, v in weighings.items() if k.endswith("_before")}
    after = {k: v for k, v in weighings.items() if not k.endswith("_before")}
    end = float(motion.time[-1])
    batches: list[Batch] = [Batch(group=MEASUREMENTS, columns=before, at=0.0)] if before else []
    batches += split("friction", friction, at, rows=s.batch_rows)
    if track:
        batches.append(Batch(group="wear_track", columns=track, at=end + 300.0))
    if after:
        batches.append(Batch(group=MEASUREMENTS, columns=after, at=end + 600.0))
    return SimulatedRun(
        run_create=_opening(s, motion.reciprocating),
        batches=tuple(batches),
        truth=_truth(s, motion, wear),
    )


@dataclass(frozen=True, slots=True)
class _Motion:
    """Where the ball is at each reading: laps (cycles), sliding distance, m, and time, s,
    and the friction it truly meets there (running-in and the once-per-lap part)."""

    reciprocating: bool
    laps: FloatArray
    distance: FloatArray
    time: FloatArray
    phase: FloatArray
    true_mu: FloatArray

    @property
    def start(self) -> float:
        return float(self.distance[0])

    @property
    def sliding(self) -> float:
        return float(self.distance[-1] - self.distance[0])

    @classmethod
    def of(cls, s: TribometerSettings) -> _Motion:
        recip = isinstance(s.configuration, ReciprocatingConfig)
        n = s.laps * s.samples_per_lap + (0 if recip else 1)
        offset = 0.5 if recip else 0.0  # never at a reversal, where the friction turns over
        laps = (np.arange(n, dtype=np.float64) + offset) / s.samples_per_lap
        distance = laps * s.lap_length
        g = running_in_shape(distance - distance[0], s.running_in_laps * s.lap_length)
        base = s.friction_steady + (s.friction_static - s.friction_steady) * g
        phase = 2.0 * math.pi * laps
        wave = np.sin(phase) if not recip else np.cos(2.0 * phase)
        return cls(
            reciprocating=recip,
            laps=laps,
            distance=distance,
            time=distance / s.speed,
            phase=phase,
            true_mu=base + s.friction_steady * s.periodic * wave,
        )


@dataclass(frozen=True, slots=True)
class _Wear:
    """Archard's wear over the sliding distance: the volumes, m³, the ball's scar, m, and
    the track's groove (its area across, m², width and depth, m)."""

    ball_volume: float
    disc_volume: float
    scar: float
    area: float
    width: float
    depth: float

    @classmethod
    def of(cls, s: TribometerSettings, sliding: float) -> _Wear:
        c = s.configuration
        ball_volume = s.ball_wear * s.load * sliding
        disc_volume = s.disc_wear * s.load * sliding
        scar = scar_of(ball_volume, c.tip_diameter / 2.0)
        track_length = (
            c.stroke_length
            if isinstance(c, ReciprocatingConfig)
            else 2.0 * math.pi * c.track_radius
        )
        area = disc_volume / track_length
        # the groove's edges on the profiles' samples: the trapezoid rule then errs by the
        # parabola's curvature alone, a relative -(step/width)²
        width = max(round(scar / (2.0 * TRACE_STEP)), 20) * 2.0 * TRACE_STEP
        depth = 1.5 * area / width  # a parabola's area is (2/3)·width·depth
        return cls(ball_volume, disc_volume, scar, area, width, depth)


def _friction_record(
    s: TribometerSettings, motion: _Motion, wear: _Wear, rng: np.random.Generator
) -> dict[str, FloatArray]:
    """The friction group as the instrument writes it: μ = F_t/F_N of its own readings, the
    distance and laps, the temperature and the wear depth (and on the flat the position and
    the stroke's number)."""
    ins, n = s.instruments, motion.laps.size
    direction = np.sign(np.sin(motion.phase)) if motion.reciprocating else np.ones(n)
    mu = motion.true_mu * (1.0 + _fluctuation(n, s.friction_fluctuation, rng))
    load = ins.load.read(np.full(n, s.load), rng)
    force = ins.force.read(direction * mu * s.load, rng)
    record: dict[str, FloatArray] = {
        "time": np.round(motion.time, 9),
        "normal_load": load,
        "friction_force": force,
        "friction_coefficient": force / load,
        "distance": motion.distance,
        "laps": motion.laps,
    }
    c = s.configuration
    if isinstance(c, ReciprocatingConfig):
        record["position"] = -c.stroke_length / 2.0 * np.cos(motion.phase) / 1e-3
        record["stroke"] = np.floor(2.0 * motion.laps) + 1.0
    slid = motion.distance - motion.start
    heat = 1.0 - np.exp(-slid / (0.2 * motion.sliding))
    record["temperature"] = ins.thermometer.read(
        c.plan.temperature + s.temperature_rise * heat, rng
    )
    record["wear_depth"] = ins.depth.read(wear.depth * slid / motion.sliding / _M_PER_UM, rng)
    return record


def _track_profiles(
    s: TribometerSettings, wear: _Wear, rng: np.random.Generator
) -> dict[str, FloatArray]:
    """The groove traced across in :data:`TRACES` places (x in mm, z in µm)."""
    half = round(TRACE_HALF / TRACE_STEP)
    x = np.arange(-half, half + 1, dtype=np.float64) * TRACE_STEP
    profiles: dict[str, list[FloatArray]] = {"x": [], "z": [], "trace": []}
    for trace in range(TRACES):
        profiles["x"].append(x / 1e-3)
        z = track_profile(x, wear.width, wear.depth) / 1e-6
        profiles["z"].append(s.instruments.profilometer.read(z, rng))
        profiles["trace"].append(np.full(x.size, float(trace)))
    return {name: np.concatenate(parts) for name, parts in profiles.items()}


def _weighings(
    s: TribometerSettings, wear: _Wear, rng: np.random.Generator
) -> dict[str, FloatArray]:
    """The specimens on the balance before and after (g), and the scar under the
    microscope (µm)."""
    c, ins = s.configuration, s.instruments
    ball_mass, disc_mass = 0.44e-3 * c.pin.density / 3950.0, 20e-3
    ball_loss, disc_loss = c.pin.density * wear.ball_volume, c.disc.density * wear.disc_volume
    return {
        "pin_mass_before": ins.balance.read([ball_mass / _KG_PER_G], rng),
        "disc_mass_before": ins.balance.read([disc_mass / _KG_PER_G], rng),
        "pin_mass_after": ins.balance.read([(ball_mass - ball_loss) / _KG_PER_G], rng),
        "disc_mass_after": ins.balance.read([(disc_mass - disc_loss) / _KG_PER_G], rng),
        "scar_diameter": ins.microscope.read([wear.scar / _M_PER_UM], rng),
    }


def _opening(s: TribometerSettings, reciprocating: bool) -> RunCreate:
    c = s.configuration
    return RunCreate(
        stand=StandKind.RECIPROCATING if reciprocating else StandKind.PIN_ON_DISC,
        operator=s.operator,
        title=f"Simulated {'reciprocating' if reciprocating else 'ball-on-disc'} test, "
        f"{s.load:g} N",
        specimen={"ball": c.pin.name, "disc": c.disc.name},
        test_plan={"load_N": s.load, "laps": s.laps, "simulated": True},
        configuration=c.model_dump(mode="json"),
    )


def _truth(s: TribometerSettings, motion: _Motion, wear: _Wear) -> TribometerTruth:
    c = s.configuration
    modulus = tribometer.effective_modulus(
        youngs_1=c.pin.youngs_modulus,
        poisson_1=c.pin.poisson,
        youngs_2=c.disc.youngs_modulus,
        poisson_2=c.disc.poisson,
    )
    hertz = tribometer.hertz_ball_on_flat(
        load=s.load, ball_radius=c.tip_diameter / 2.0, modulus=modulus
    )
    transient = s.running_in_laps * s.lap_length
    settled = settled_distance(transient, s.friction_static, s.friction_steady)
    slid = motion.distance - motion.start
    steady = max(1, int(np.searchsorted(slid, settled - 1e-12)))
    return TribometerTruth(
        kind=s.kind,
        load=s.load,
        laps=float(motion.laps[-1] - motion.laps[0]),
        sliding_distance=motion.sliding,
        friction_static=float(np.abs(motion.true_mu[:steady]).max()),
        friction_steady=s.friction_steady,
        friction_mean=float(np.abs(motion.true_mu).mean()),
        running_in_distance=settled,
        running_in_laps=settled / s.lap_length,
        transient_distance=transient,
        lap_amplitude=s.friction_steady * s.periodic,
        ball_volume=wear.ball_volume,
        disc_volume=wear.disc_volume,
        scar_diameter=wear.scar,
        track_area=wear.area,
        track_width=wear.width,
        ball_mass_loss=c.pin.density * wear.ball_volume,
        disc_mass_loss=c.disc.density * wear.disc_volume,
        ball_rate=s.ball_wear,
        disc_rate=s.disc_wear,
        hertz_pressure=hertz.max_pressure,
    )


def simulate_reciprocating(
    settings: TribometerSettings | None = None, seed: int = 0
) -> SimulatedRun[TribometerTruth]:
    """:func:`simulate` of a reciprocating test (its defaults when ``settings`` is None)."""
    return simulate(settings or TribometerSettings.reciprocating(), seed)


@dataclass(frozen=True, slots=True)
class SweepTruth:
    """A speed sweep's truth, step by step (SI): the sliding speed, the track's radius, the
    steps' μ (a Stribeck-like fall with the speed), the load and each step's duration."""

    sliding_speed: tuple[float, ...]
    track_radius: tuple[float, ...]
    friction: tuple[float, ...]
    load: float
    duration: float


#: The sweep of a rotary tribometer's recipe: (track radius, m; sliding speed, m/s).
SWEEP = ((6e-3, 0.075), (9e-3, 0.150), (12e-3, 0.225), (15e-3, 0.300))


def sweep_friction(speed: float) -> float:
    """μ(v) of the simulated sweep: a boundary value falling towards a lower one with the
    speed, μ = 0.12 + 0.4·e^(-v/(0.1 m/s)) (a Stribeck curve's mixed-lubrication side)."""
    return 0.12 + 0.4 * math.exp(-speed / 0.1)


def simulate_sweep(
    seed: int = 0, *, step_time: float = 180.0, rate: float = 10.0, load: float = 5.0
) -> SimulatedRun[SweepTruth]:
    """A pin-on-disc speed sweep as a rotary tribometer's recipe runs it: four steps of
    ``step_time`` s at the radii and speeds of :data:`SWEEP` (the radial stage moved between
    steps), read ``rate`` times a second. The record has the step, the rotational speed
    n = 60v/(2πR) in rpm and the radius per row, no distance and no laps: the analysis
    derives them, v = 2πRn/60. μ of each step is :func:`sweep_friction` with a 2 % AR(1)
    fluctuation."""
    rng = np.random.default_rng(seed)
    per_step = round(step_time * rate)
    columns: dict[str, list[FloatArray]] = {}
    for k, (radius, speed) in enumerate(SWEEP):
        t = (k * per_step + np.arange(per_step)) / rate
        mu = sweep_friction(speed) * (1.0 + _fluctuation(per_step, 0.02, rng))
        part = {
            "time": t,
            "step": np.full(per_step, float(k + 1)),
            "rotational_speed": np.full(per_step, 60.0 * speed / (2.0 * math.pi * radius)),
            "track_radius": np.full(per_step, radius),
            "normal_load": np.full(per_step, load),
            "friction_coefficient": mu,
        }
        for name, values in part.items():
            columns.setdefault(name, []).append(values)
    record = {name: np.concatenate(parts) for name, parts in columns.items()}
    body = RunCreate(
        stand=StandKind.PIN_ON_DISC,
        operator="rigsim",
        title=f"Simulated speed sweep, {load:g} N, {len(SWEEP)} steps",
        test_plan={"load_N": load, "simulated": True},
        configuration={"track_radius": SWEEP[0][0]},
    )
    truth = SweepTruth(
        sliding_speed=tuple(v for _, v in SWEEP),
        track_radius=tuple(r for r, _ in SWEEP),
        friction=tuple(sweep_friction(v) for _, v in SWEEP),
        load=load,
        duration=(per_step - 1) / rate,
    )
    batches = split("friction", record, record["time"], rows=2000)
    return SimulatedRun(run_create=body, batches=tuple(batches), truth=truth)
