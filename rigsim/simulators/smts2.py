"""The SMTs-2 friction machine (lab work 2): dry sliding of a pin on a disc.

The friction coefficient runs in from a higher start value to its steady value,
f(n) = f_s + (f_0 - f_s)·exp(-n/n_r) over the revolutions n, with a correlated fluctuation
(stick-slip and debris, an AR(1) process of relative size ``friction_fluctuation``); the
moment sensor shows M = f·N·r2 (2.8). The disc turns at the belt's nominal speed less the
motor's slip; the counter shows whole hundreds of revolutions; the run stops when it reaches
the planned count.

The pin wears by Archard's law, V = k·N·L (L = 2π r2·n), with a wear coefficient of dry
steel pairs (1e-14 m³/(N·m) = 1e-5 mm³/(N·m) for the wear mode; brass on steel wears more,
oxidised steel less) — not by the fatigue formula (2.1) the lab tests, so that the adequacy
check (2.15) passes or fails on its merits. The pin is weighed before and after on a balance
of 0.1 mg.

Modes (the manual's three runs): ``wear`` (St3sp pin, 300 N, 1000 rpm, 15 000 rev),
``adhesive`` (brass pin, 200 N, 2000 rev, friction higher) and ``oxidative`` (rusted steel,
300 N, 2000 rev, friction lower); :meth:`Smts2Settings.for_mode` gives each one's defaults.
The run names its pin (:data:`PINS`) and leaves its properties to the server's materials
table, whose density the simulated weighing uses too (a configuration's own pin is sent).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
from scipy.signal import lfilter

from rigsim.batches import Batch, SimulatedRun, split
from rigsim.errors import SettingsError
from rigsim.instruments import Fault, Instrument, apply_faults
from schemas.materials import properties
from schemas.runs import RunCreate
from schemas.stands import MEASUREMENTS, SMTS2_GROUPS, PinMaterial, Smts2Config, StandKind
from schemas.units import UNITS

Mode = Literal["wear", "adhesive", "oxidative"]
MODES: tuple[Mode, ...] = ("wear", "adhesive", "oxidative")
#: The pin each mode's run names (the manual: steel pins, a brass one for adhesion).
PINS: dict[Mode, str] = {"wear": "St3sp", "adhesive": "brass", "oxidative": "St3sp"}
#: The machine stops above this friction moment, N·m (manual, machine data).
MOMENT_LIMIT = 15.0
#: Belt speeds of the disc, rpm.
SPEEDS = (300.0, 500.0, 1000.0)
#: Load range of the loading screw, N.
LOAD_RANGE = (200.0, 5000.0)
_KG_PER_G = UNITS["g"].factor
_M_PER_UM = UNITS["um"].factor
#: Fluctuations up to this many standard deviations must stay under the moment limit.
_PEAK_SIGMAS = 4.0


_MOMENT = Instrument(resolution=0.01, noise=0.02)
_LOAD = Instrument(resolution=1.0, noise=1.5)
_SPEED = Instrument(resolution=1.0, noise=2.0)
_BALANCE = Instrument(resolution=1e-4, noise=1e-4)
_PROFILOMETER = Instrument(resolution=0.01)


@dataclass(frozen=True, slots=True)
class Smts2Instruments:
    """The machine's instruments, each in its channel's unit."""

    moment: Instrument = _MOMENT
    load: Instrument = _LOAD
    speed: Instrument = _SPEED
    balance: Instrument = _BALANCE
    profilometer: Instrument = _PROFILOMETER


@dataclass(frozen=True, slots=True)
class Smts2Settings:
    """What the simulated lab does on the SMTs-2; defaults: the wear run of the manual.

    Attributes
    ----------
    mode : {"wear", "adhesive", "oxidative"}
    load : float
        N on the pin, N (200-5000).
    speed : float
        Disc speed set by the belts, rpm (300, 500 or 1000).
    revolutions : float
        Planned revolutions; the run stops when the counter reaches them.
    friction_start, friction_steady : float
        f at the first contact and after running in.
    running_in : float
        Revolutions over which the running-in transient decays by e.
    friction_fluctuation : float
        Relative standard deviation of the friction's fluctuation.
    wear_coefficient : float
        Archard's k, m³/(N·m).
    slip : float
        Motor slip: the disc turns at speed·(1 - slip).
    pin_mass : float
        True pin mass before the test, kg.
    disc_ra : float
        Ra of the disc, m (from a profilometer, posted with the run in μm).
    sample_rate : float
        Readings per second of the recorder, Hz.
    batch_rows : int
        Rows per posted batch.
    configuration : Smts2Config
    instruments : Smts2Instruments
    faults : tuple of Fault
    operator : str
    """

    mode: Mode = "wear"
    load: float = 300.0
    speed: float = 1000.0
    revolutions: float = 15_000.0
    friction_start: float = 0.6
    friction_steady: float = 0.4
    running_in: float = 300.0
    friction_fluctuation: float = 0.04
    wear_coefficient: float = 1e-14
    slip: float = 0.02
    pin_mass: float = 12.25e-3
    disc_ra: float = 0.5e-6
    sample_rate: float = 10.0
    batch_rows: int = 300
    configuration: Smts2Config = field(default_factory=Smts2Config)
    instruments: Smts2Instruments = Smts2Instruments()
    faults: tuple[Fault, ...] = ()
    operator: str = "rigsim"

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise SettingsError(f"mode must be one of {MODES}, got {self.mode!r}")
        low, high = LOAD_RANGE
        if not low <= self.load <= high:
            raise SettingsError(f"load must lie in [{low:g}, {high:g}] N, got {self.load}")
        if self.speed not in SPEEDS:
            raise SettingsError(f"speed must be one of {SPEEDS} rpm, got {self.speed}")
        if self.revolutions < 100:
            raise SettingsError(f"revolutions must be >= 100 (one count), got {self.revolutions}")
        for name in ("friction_start", "friction_steady"):
            if not 0.0 < getattr(self, name) < 1.5:
                raise SettingsError(f"{name} must lie in (0, 1.5), got {getattr(self, name)}")
        peak = (
            max(self.friction_start, self.friction_steady)
            * (1.0 + _PEAK_SIGMAS * self.friction_fluctuation)
            * self.load
            * self.configuration.disc_radius
        )
        if peak > MOMENT_LIMIT:
            raise SettingsError(
                f"the friction moment would reach {peak:.3g} N*m: the machine stops above "
                f"{MOMENT_LIMIT:g} N*m (lower the load below "
                f"{self.load * MOMENT_LIMIT / peak:.0f} N)"
            )
        if not 0.0 <= self.slip < 0.09:
            raise SettingsError(f"slip must lie in [0, 0.09) (speed ± 10 %), got {self.slip}")
        if self.wear_coefficient <= 0:
            raise SettingsError(
                f"wear_coefficient must be > 0 m^3/(N*m), got {self.wear_coefficient}"
            )
        if self.sample_rate <= 0 or self.batch_rows < 1:
            raise SettingsError(
                f"sample_rate must be > 0 Hz and batch_rows >= 1, got {self.sample_rate}, "
                f"{self.batch_rows}"
            )

    @classmethod
    def for_mode(cls, mode: Mode, **changes: object) -> Smts2Settings:
        """The manual's run of ``mode``, with ``changes``."""
        defaults: dict[Mode, dict[str, object]] = {
            "wear": {},
            "adhesive": {
                "load": 200.0,
                "revolutions": 2000.0,
                "friction_start": 0.7,
                "friction_steady": 0.55,
                "wear_coefficient": 4e-14,
            },
            "oxidative": {
                "load": 300.0,
                "revolutions": 2000.0,
                "friction_start": 0.45,
                "friction_steady": 0.3,
                "wear_coefficient": 3e-15,
            },
        }
        if mode not in defaults:
            raise SettingsError(f"mode must be one of {MODES}, got {mode!r}")
        return replace(cls(mode=mode), **{**defaults[mode], **changes})  # type: ignore[arg-type]


@dataclass(frozen=True, slots=True)
class Smts2Truth:
    """The simulated SMTs-2 run's truth (SI units).

    Attributes
    ----------
    mode : str
    load : float
        N, N.
    speed : float
        Actual disc speed, rpm.
    friction_start, friction_steady : float
        f at first contact and after running in.
    revolutions : float
        Revolutions actually turned.
    sliding_distance : float
        L = 2π r2·n, m.
    volume : float
        Worn volume V = k·N·L, m³.
    mass_loss : float
        ρ·V, kg.
    intensity : float
        Linear wear intensity I_h = V/(π r1²·L).
    pin_mass_before, pin_mass_after : float
        True masses, kg.
    disc_ra : float
        Ra of the disc, m.
    """

    mode: Mode
    load: float
    speed: float
    friction_start: float
    friction_steady: float
    revolutions: float
    sliding_distance: float
    volume: float
    mass_loss: float
    intensity: float
    pin_mass_before: float
    pin_mass_after: float
    disc_ra: float


def _fluctuation(n: int, size: float, rng: np.random.Generator) -> np.ndarray:
    """AR(1) noise of standard deviation ``size`` with correlation 0.9 per sample."""
    rho = 0.9
    white = rng.normal(0.0, size * np.sqrt(1.0 - rho**2), n)
    start = rng.normal(0.0, size)
    out, _ = lfilter([1.0], [1.0, -rho], white, zi=[rho * start])
    return np.asarray(out, dtype=np.float64)


def _pin(s: Smts2Settings) -> tuple[PinMaterial, bool]:
    """The pin's material and whether the run's configuration gives it: the settings' own
    pin when they change the stand's default, else the materials table's for the pin the
    mode's run names (the server looks it up by that name)."""
    if s.configuration.pin != PinMaterial():
        return s.configuration.pin, True
    named = properties(PINS[s.mode], PinMaterial)
    assert named is not None, f"the materials table holds {PINS[s.mode]}"
    return named, False


def simulate(settings: Smts2Settings | None = None, seed: int = 0) -> SimulatedRun[Smts2Truth]:
    """A simulated SMTs-2 run: the weighing, the friction record, the second weighing."""
    s = settings or Smts2Settings()
    rng = np.random.default_rng(seed)
    c = s.configuration
    ins = s.instruments
    r2 = c.disc_radius
    rev_per_s = s.speed * (1.0 - s.slip) / 60.0
    dt = 1.0 / s.sample_rate
    samples = int(np.ceil(s.revolutions / (rev_per_s * dt))) + 1
    time = np.round(np.arange(samples) * dt, 9)
    turned = rev_per_s * time
    f = s.friction_steady + (s.friction_start - s.friction_steady) * np.exp(-turned / s.running_in)
    f = f * (1.0 + _fluctuation(samples, s.friction_fluctuation, rng))
    revolutions = float(turned[-1])
    distance = 2.0 * np.pi * r2 * revolutions
    volume = s.wear_coefficient * s.load * distance
    pin, pin_given = _pin(s)
    mass_loss = pin.density * volume
    m1 = s.pin_mass
    pin_area = np.pi * (c.pin_diameter / 2.0) ** 2
    friction = {
        "time": time,
        "load": ins.load.read(np.full(samples, s.load), rng),
        "speed": ins.speed.read(np.full(samples, s.speed * (1.0 - s.slip)), rng),
        "friction_moment": ins.moment.read(f * s.load * r2, rng),
        "revolutions": np.floor(turned / 100.0),
    }
    weighings = {
        "pin_mass_before": ins.balance.read([m1 / _KG_PER_G], rng),
        "disc_ra": ins.profilometer.read([s.disc_ra / _M_PER_UM], rng),
        "pin_mass_after": ins.balance.read([(m1 - mass_loss) / _KG_PER_G], rng),
    }
    record, before = SMTS2_GROUPS
    friction, at = apply_faults(record, friction, time, s.faults)
    weighings, _ = apply_faults(before, weighings, np.zeros(1), s.faults)
    first = {k: v for k, v in weighings.items() if k != "pin_mass_after"}
    last = {k: v for k, v in weighings.items() if k == "pin_mass_after"}
    batches: list[Batch] = []
    if first:
        batches.append(Batch(group=MEASUREMENTS, columns=first, at=0.0))
    batches += split("friction", friction, at, rows=s.batch_rows)
    if last:  # weighed once the pin has cooled, ten minutes after the stop
        batches.append(Batch(group=MEASUREMENTS, columns=last, at=float(time[-1]) + 600.0))
    body = RunCreate(
        stand=StandKind.SMTS2,
        operator=s.operator,
        title=f"Simulated SMTs-2 run, {s.mode} mode, {s.load:g} N, {s.speed:g} rpm",
        specimen={
            "pin": PINS[s.mode],
            "disc": c.disc.name,
        },
        test_plan={
            "mode": s.mode,
            "load_N": s.load,
            "speed_rpm": s.speed,
            "revolutions": s.revolutions,
            "simulated": True,
        },
        configuration=c.model_dump(mode="json", exclude=None if pin_given else {"pin"}),
    )
    truth = Smts2Truth(
        mode=s.mode,
        load=s.load,
        speed=s.speed * (1.0 - s.slip),
        friction_start=s.friction_start,
        friction_steady=s.friction_steady,
        revolutions=revolutions,
        sliding_distance=distance,
        volume=volume,
        mass_loss=mass_loss,
        intensity=volume / pin_area / distance,
        pin_mass_before=m1,
        pin_mass_after=m1 - mass_loss,
        disc_ra=s.disc_ra,
    )
    return SimulatedRun(run_create=body, batches=tuple(batches), truth=truth)
