"""The ABRIS-PM7 profilometer (lab work 1): a run-in surface's profile y(x).

A stationary random profile with a Gaussian autocorrelation exp(-(τ/β)²) of correlation
length β (white noise filtered by a Gaussian kernel), whose heights are then mapped so that
the material ratio at a depth ε·Rmax below the peak follows the bearing curve
t_p = b·ε^ν (1.8) over its initial part, up to t_p = 1/2, and continues smoothly to 1 at the
valleys: t_p = 1 - (1/2)·((1 - ε)/(1 - ε1))^m with ε1 = (1/(2b))^(1/ν) and m matching the
slope at ε1. The profile is scaled to the requested Ra (1.3) as the model library computes
it, so the truth's Ra is the requested one to rounding; Rq, Rz, Rmax are those of the
generated profile.

The ε of (1.8) is the depth over the distribution's range; the sample's own peak line sits a
little below the distribution's top (the highest of a finite number of asperities), so b and
ν fitted to one trace by (1.16)-(1.19) scatter about the ones set. They are the generating
shape, not a truth the lab recovers exactly.

The stylus traverses at ``traverse_speed`` and the trace is sampled at the configured step;
the instrument adds a tilt of the trace (removed by the mean line), a zero offset, noise and
the converter's resolution.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.special import ndtr

from rigserver.core import roughness
from rigserver.core.errors import ModelInputError
from rigserver.core.roughness_tables import ABRIS_PM7_SUBRANGES
from rigsim.batches import Batch, FloatArray, SimulatedRun, split
from rigsim.errors import SettingsError
from rigsim.instruments import Fault, Instrument, apply_faults
from schemas.runs import RunCreate
from schemas.stands import MEASUREMENTS, PROFILOMETER_GROUPS, ProfilometerConfig, StandKind
from schemas.units import UNITS

_M_PER_MM = UNITS["mm"].factor
_M_PER_UM = UNITS["um"].factor
#: The power law of the bearing curve holds up to this material ratio.
_POWER_LAW_TOP = 0.5


_GAUGE = Instrument(resolution=0.001, noise=0.002, offset=3.0)


@dataclass(frozen=True, slots=True)
class ProfilometerInstruments:
    """The profilometer's gauge, in μm."""

    gauge: Instrument = _GAUGE


@dataclass(frozen=True, slots=True)
class ProfilometerSettings:
    """The surface and the trace; defaults: a run-in steel surface, Ra 0.8 μm.

    Attributes
    ----------
    ra : float
        Ra of the surface, m (the ABRIS-PM7 range, 0.04-12.5 μm).
    correlation_length : float
        β of the autocorrelation exp(-(τ/β)²), m.
    nu, b : float
        Bearing-curve shape t_p = b·ε^ν (1.8) (after run-in ν ≈ 2, b ≈ 2); ν >= 1, b > 1/2.
    base_length : float or None
        Length traced, m; by default the cutoff of the subrange that holds Ra.
    traverse_speed : float
        Stylus speed, m/s.
    tilt : float
        Slope of the trace against the surface (removed by the mean line).
    batch_rows : int
        Rows per posted batch.
    configuration : ProfilometerConfig
        Its ``step`` is the sampling step.
    instruments : ProfilometerInstruments
    faults : tuple of Fault
    operator : str
    """

    ra: float = 0.8e-6
    correlation_length: float = 20e-6
    nu: float = 2.0
    b: float = 2.0
    base_length: float | None = None
    traverse_speed: float = 0.5e-3
    tilt: float = 1e-4
    batch_rows: int = 800
    configuration: ProfilometerConfig = field(default_factory=ProfilometerConfig)
    instruments: ProfilometerInstruments = ProfilometerInstruments()
    faults: tuple[Fault, ...] = ()
    operator: str = "rigsim"

    def __post_init__(self) -> None:
        low, high = ABRIS_PM7_SUBRANGES[0].ra_min, ABRIS_PM7_SUBRANGES[-1].ra_max
        if not low <= self.ra <= high:
            raise SettingsError(f"ra must lie in [{low:g}, {high:g}] m (ABRIS-PM7), got {self.ra}")
        if self.nu < 1.0 or self.b <= _POWER_LAW_TOP:
            raise SettingsError(f"need nu >= 1 and b > 0.5, got nu = {self.nu}, b = {self.b}")
        step = self.configuration.step
        if not 2.0 * step <= self.correlation_length <= self.length / 10.0:
            raise SettingsError(
                f"correlation_length must lie in [2·step, base_length/10] = [{2 * step:g}, "
                f"{self.length / 10:g}] m, got {self.correlation_length}"
            )
        if not 0.01e-3 <= self.length <= 100e-3:
            raise SettingsError(f"base_length must lie in [1e-05, 0.1] m, got {self.length}")
        if self.traverse_speed <= 0 or self.batch_rows < 1:
            raise SettingsError("traverse_speed must be > 0 and batch_rows >= 1")

    @property
    def subrange(self) -> float:
        """Upper Ra of the instrument's subrange that holds Ra, m."""
        return next(sub.ra_max for sub in ABRIS_PM7_SUBRANGES if self.ra <= sub.ra_max)

    @property
    def length(self) -> float:
        """The base length traced, m."""
        if self.base_length is not None:
            return self.base_length
        return next(sub.cutoff for sub in ABRIS_PM7_SUBRANGES if self.ra <= sub.ra_max)


@dataclass(frozen=True, slots=True)
class ProfilometerTruth:
    """Parameters of the generated profile (before the instrument), SI units.

    Attributes
    ----------
    ra, rq, rz, rmax : float
        Of the generated profile (1.2)-(1.4), m.
    base_length : float
        m.
    correlation_length : float
        m.
    nu, b : float
        The generating bearing-curve shape.
    """

    ra: float
    rq: float
    rz: float
    rmax: float
    base_length: float
    correlation_length: float
    nu: float
    b: float


def depth_of_material_ratio(t: FloatArray, *, nu: float, b: float) -> FloatArray:
    """Relative depth ε at which the material ratio is t: the inverse of the bearing curve.

    t_p = b·ε^ν up to t_p = 1/2 (1.8), then 1 - (1/2)((1 - ε)/(1 - ε1))^m to 1 at ε = 1.
    """
    t1 = _POWER_LAW_TOP
    eps1 = (t1 / b) ** (1.0 / nu)
    m = b * nu * eps1 ** (nu - 1.0) * (1.0 - eps1) / (1.0 - t1)
    t = np.clip(t, 0.0, 1.0)
    upper = (np.minimum(t, t1) / b) ** (1.0 / nu)
    lower = 1.0 - (1.0 - eps1) * ((1.0 - np.maximum(t, t1)) / (1.0 - t1)) ** (1.0 / m)
    return np.asarray(np.where(t <= t1, upper, lower), dtype=np.float64)


def _correlated(n: int, beta_samples: float, rng: np.random.Generator) -> FloatArray:
    """Unit-variance Gaussian noise with autocorrelation exp(-(k/β)²), k in samples."""
    pad = int(np.ceil(4.0 * beta_samples))
    size = n + 2 * pad
    k = np.fft.rfftfreq(size)
    # exp(-2x²/β²) convolved with itself gives exp(-x²/β²): its transform is the filter.
    spectrum = np.exp(-((np.pi * beta_samples * k) ** 2) / 2.0)
    noise = np.fft.irfft(np.fft.rfft(rng.normal(size=size)) * spectrum, size)[pad : pad + n]
    return np.asarray((noise - noise.mean()) / noise.std(), dtype=np.float64)


#: Profiles drawn at most for one trace (:func:`simulate`).
_DRAWS = 20


def simulate(
    settings: ProfilometerSettings | None = None, seed: int = 0
) -> SimulatedRun[ProfilometerTruth]:
    """A simulated trace: the instrument settings, then the profile in batches."""
    s = settings or ProfilometerSettings()
    rng = np.random.default_rng(seed)
    step = s.configuration.step
    n = int(np.floor(s.length / step + 1e-9)) + 1
    x = np.arange(n) * step
    # A trace too short for its correlation length may cross its mean line too seldom for
    # Sm (a few seeds in a hundred at the shortest base length): such a draw is not a
    # surface the instrument could evaluate, and the next one is taken.
    for _ in range(_DRAWS):
        exceed = 1.0 - ndtr(_correlated(n, s.correlation_length / step, rng))
        shape = -depth_of_material_ratio(exceed, nu=s.nu, b=s.b)
        try:
            y = shape * (s.ra / roughness.profile_parameters(x=x, y=shape).ra)
            params = roughness.profile_parameters(x=x, y=y)
            break
        except ModelInputError as exc:
            failure = exc
    else:
        raise SettingsError(f"the generated profile has no roughness parameters: {failure}")
    gauge = s.instruments.gauge
    trace = {
        "x": np.round(x / _M_PER_MM, 9),
        "y": gauge.read((y + s.tilt * x) / _M_PER_UM, rng),
    }
    setup = {
        "base_length": np.array([s.length / _M_PER_MM]),
        "subrange": np.array([round(s.subrange / _M_PER_UM, 6)]),
        # the instrument's own Ra, Rz, Rmax (procedure item 1), read to its 0.001 µm
        "rz_instrument": np.array([round(params.rz / _M_PER_UM, 3)]),
        "rmax_instrument": np.array([round(params.rmax / _M_PER_UM, 3)]),
        "ra_instrument": np.array([round(params.ra / _M_PER_UM, 3)]),
    }
    at = x / s.traverse_speed
    profile_group, setup_group = PROFILOMETER_GROUPS
    trace, at = apply_faults(profile_group, trace, at, s.faults)
    setup, _ = apply_faults(setup_group, setup, np.zeros(1), s.faults)
    batches: list[Batch] = []
    if setup:
        batches.append(Batch(group=MEASUREMENTS, columns=setup, at=0.0))
    batches += split("profile", trace, at, rows=s.batch_rows)
    body = RunCreate(
        stand=StandKind.PROFILOMETER,
        operator=s.operator,
        title=f"Simulated profile, Ra {s.ra / _M_PER_UM:g} um",
        specimen={"surface": "run-in steel"},
        test_plan={
            "ra_um": s.ra / _M_PER_UM,
            "base_length_mm": s.length / _M_PER_MM,
            "simulated": True,
        },
        configuration=s.configuration.model_dump(mode="json"),
    )
    truth = ProfilometerTruth(
        ra=params.ra,
        rq=params.rq,
        rz=params.rz,
        rmax=params.rmax,
        base_length=params.base_length,
        correlation_length=s.correlation_length,
        nu=s.nu,
        b=s.b,
    )
    return SimulatedRun(run_create=body, batches=tuple(batches), truth=truth)
