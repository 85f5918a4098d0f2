"""Commercial tribometers: pin- or ball-on-disc (ASTM G99, ISO 20808) and reciprocating
(ASTM G133): the wear volumes, the specific wear rate, the Hertz contact, the per-lap views.

Sources (docs/models.md, section 6): ASTM G99-17 (pin-on-disk wear: the disc's volume from
the track, the ball's from its scar), ASTM G133-05 (linearly reciprocating ball-on-flat),
ISO 20808:2016 (ball-on-disc on fine ceramics), K. L. Johnson, *Contact Mechanics*, CUP 1985,
§4.2 (Hertz: a sphere on a flat), and Archard's specific wear rate k = V/(F·L).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rigserver.core._checks import finite, non_negative, positive, within
from rigserver.core.errors import ModelInputError

__all__ = [
    "STEADY_BAND",
    "STEADY_SHARE",
    "HertzContact",
    "LapMap",
    "disc_track_volume",
    "effective_modulus",
    "flat_pin_volume",
    "hertz_ball_on_flat",
    "lap_harmonic",
    "lap_map",
    "segment_means",
    "settled_from",
    "specific_wear_rate",
    "spherical_cap_volume",
    "stroke_track_volume",
]


def effective_modulus(
    *, youngs_1: float, poisson_1: float, youngs_2: float, poisson_2: float
) -> float:
    """The contact modulus of two elastic bodies (Johnson 1985, (4.22)).

    .. math:: \\frac{1}{E^*} = \\frac{1 - ν_1^2}{E_1} + \\frac{1 - ν_2^2}{E_2}

    Parameters
    ----------
    youngs_1, youngs_2 : float
        Young's moduli, Pa (> 0).
    poisson_1, poisson_2 : float
        Poisson's ratios, 0 <= ν < 0.5.

    Returns
    -------
    float
        E*, Pa.
    """
    e1, e2 = float(positive("youngs_1", youngs_1)), float(positive("youngs_2", youngs_2))
    n1 = float(within("poisson_1", poisson_1, 0.0, 0.5, closed=(True, False)))
    n2 = float(within("poisson_2", poisson_2, 0.0, 0.5, closed=(True, False)))
    return 1.0 / ((1.0 - n1**2) / e1 + (1.0 - n2**2) / e2)


@dataclass(frozen=True, slots=True)
class HertzContact:
    """A sphere pressed on a flat (Johnson 1985, §4.2).

    Attributes
    ----------
    radius : float
        a = (3FR/(4E*))^(1/3), the contact circle's radius, m.
    max_pressure : float
        p0 = 3F/(2πa²) = (6FE*²/(π³R²))^(1/3), Pa.
    mean_pressure : float
        p_m = F/(πa²) = 2p0/3, Pa.
    """

    radius: float
    max_pressure: float
    mean_pressure: float


def hertz_ball_on_flat(*, load: float, ball_radius: float, modulus: float) -> HertzContact:
    """The initial Hertz contact of a ball of radius R on a flat under the load F.

    .. math:: a = \\left(\\frac{3FR}{4E^*}\\right)^{1/3}, \\qquad
              p_0 = \\frac{3F}{2\\pi a^2} = \\left(\\frac{6FE^{*2}}{\\pi^3R^2}\\right)^{1/3}

    Parameters
    ----------
    load : float
        F, N (> 0).
    ball_radius : float
        R, m (> 0).
    modulus : float
        E* of :func:`effective_modulus`, Pa (> 0).
    """
    f = float(positive("load", load))
    r = float(positive("ball_radius", ball_radius))
    e = float(positive("modulus", modulus))
    a = (3.0 * f * r / (4.0 * e)) ** (1.0 / 3.0)
    if a**2 == 0.0:
        raise ModelInputError(f"the contact radius of a load of {f:g} N is below the floats'")
    mean = f / (math.pi * a**2)
    return HertzContact(radius=a, max_pressure=1.5 * mean, mean_pressure=mean)


def spherical_cap_volume(*, scar_diameter: float, ball_radius: float) -> float:
    """The volume worn off a ball whose flat scar has the diameter d (ASTM G99-17, 9.2.1).

    .. math:: h = R - \\sqrt{R^2 - d^2/4}, \\qquad V = \\frac{\\pi h}{6}
              \\left(\\frac{3d^2}{4} + h^2\\right)

    the exact spherical cap; for d ≪ R it tends to πd⁴/(64R), the form G99 also prints.

    Parameters
    ----------
    scar_diameter : float
        d, m (0 <= d <= 2R).
    ball_radius : float
        R, m (> 0).
    """
    r = float(positive("ball_radius", ball_radius))
    d = float(within("scar_diameter", scar_diameter, 0.0, 2.0 * r))
    h = r - math.sqrt(max(r**2 - d**2 / 4.0, 0.0))
    if d < 1e-4 * r:  # the cancellation in R - √(R² - d²/4): the series is exact there
        h = d**2 / (8.0 * r) * (1.0 + d**2 / (16.0 * r**2))
    return math.pi * h / 6.0 * (3.0 * d**2 / 4.0 + h**2)


def flat_pin_volume(*, diameter: float, height_loss: float) -> float:
    """The volume worn off a flat-ended cylindrical pin: V = (πD²/4)·Δh (ASTM G99-17, 9.2.1).

    Parameters
    ----------
    diameter : float
        D of the pin's flat end, m (> 0).
    height_loss : float
        Δh, the pin's loss of length, m (>= 0).
    """
    dia = float(positive("diameter", diameter))
    return math.pi * dia**2 / 4.0 * float(non_negative("height_loss", height_loss))


def disc_track_volume(*, area: float, track_radius: float) -> float:
    """The disc's worn volume from the track's mean cross-section: V = 2πR·A (ASTM G99-17,
    9.2.2, where A is measured by a profile across the track)."""
    return (
        2.0
        * math.pi
        * float(positive("track_radius", track_radius))
        * float(non_negative("area", area))
    )


def stroke_track_volume(*, area: float, stroke_length: float) -> float:
    """The flat's worn volume from the track's mean cross-section: V = S·A, the stroke
    length times the area (ASTM G133-05, 9.3; the rounded ends of the track left out)."""
    return float(positive("stroke_length", stroke_length)) * float(non_negative("area", area))


def specific_wear_rate(*, volume: float, load: float, distance: float) -> float:
    """Archard's specific wear rate k = V/(F·L), m³/(N·m) (ASTM G99-17, note 6; ISO 20808,
    9.4).

    Parameters
    ----------
    volume : float
        V, m³ (>= 0).
    load : float
        F, N (> 0).
    distance : float
        L, the sliding distance, m (> 0).
    """
    v = float(non_negative("volume", volume))
    return v / (float(positive("load", load)) * float(positive("distance", distance)))


#: The band of a steady state: every block mean within ±5 % of the steady part's mean.
STEADY_BAND = 0.05
#: The share of the record a steady part holds at least; a shorter one is no steady state.
STEADY_SHARE = 0.2


def settled_from(
    levels: ArrayLike,
    *,
    band: float = STEADY_BAND,
    allowance: float = 0.0,
    share: float = STEADY_SHARE,
) -> int | None:
    """Where a friction record has settled: the first of its block means from which every
    later one stays within ``band``·|m| + ``allowance`` of their mean m (docs/models.md,
    section 6).

    .. math:: \\max_{i \\ge j} |y_i - \\bar y_j| \\le δ·|\\bar y_j| + a, \\qquad
              \\bar y_j = \\frac{1}{n - j}\\sum_{i \\ge j} y_i

    the smallest such j. For an exponential approach μ = μ_ss + Δμ·e^(-s/s0) (P. J. Blau,
    ASME J. Tribol. 109 (1987) 537) the band is entered near s = s0·ln(Δμ/(δ·μ_ss)); a slow
    drift of the steady level by less than 2δ over the steady part stays inside it.

    Parameters
    ----------
    levels : array_like
        y, the block means in order (laps or cycles, or blocks of them).
    band : float
        δ, the band's half-width relative to the steady mean (0 <= δ < 1).
    allowance : float
        a, the block means' noise allowed beyond the band (>= 0), in y's unit.
    share : float
        The steady part's least share of the blocks (0 < share <= 1).

    Returns
    -------
    int or None
        j, the steady part's first block; None when no tail of at least ``share`` of the
        blocks stays within the band: the record has not settled.
    """
    y = finite("levels", levels)
    if y.ndim != 1 or not y.size:
        raise ModelInputError(f"levels must be 1-D and not empty, got shape {y.shape}")
    delta = float(within("band", band, 0.0, 1.0, closed=(True, False)))
    a = float(non_negative("allowance", allowance))
    least = math.ceil(float(within("share", share, 0.0, 1.0, closed=(False, True))) * y.size)
    count = np.arange(y.size, 0, -1, dtype=np.float64)
    mean = np.cumsum(y[::-1])[::-1] / count
    high = np.maximum.accumulate(y[::-1])[::-1]
    low = np.minimum.accumulate(y[::-1])[::-1]
    tolerance = delta * np.abs(mean) + a
    inside = np.flatnonzero((high - mean <= tolerance) & (mean - low <= tolerance))
    first = int(inside[0])  # the last block alone always holds
    return first if y.size - first >= least else None


def segment_means(
    index: ArrayLike, values: ArrayLike
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.int64]]:
    """The mean of ``values`` over each run of equal ``index`` (a lap, a stroke, a cycle).

    Returns the distinct indices in order, the means and the rows of each. ``index`` must
    not decrease (a lap counter).
    """
    idx = np.asarray(index, dtype=np.int64)
    v = finite("values", values)
    if idx.shape != v.shape or idx.ndim != 1 or not idx.size:
        raise ModelInputError(f"index and values must be 1-D of one length, got {idx.shape}")
    if np.any(np.diff(idx) < 0):
        raise ModelInputError("index must not decrease")
    starts = np.flatnonzero(np.r_[True, idx[1:] != idx[:-1]])
    counts = np.diff(np.r_[starts, idx.size])
    return idx[starts], np.add.reduceat(v, starts) / counts, counts


@dataclass(frozen=True, slots=True)
class LapMap:
    """μ against the lap and the angular position on the disc: cell means.

    Attributes
    ----------
    lap : ndarray
        The middle lap of each row of cells (laps counted from 0).
    angle : ndarray
        The middle of each angular bin, degrees.
    values : ndarray
        Mean μ of the rows in each cell (rows × bins); NaN where no reading fell.
    """

    lap: NDArray[np.float64]
    angle: NDArray[np.float64]
    values: NDArray[np.float64]


def lap_map(*, laps: ArrayLike, values: ArrayLike, rows: int = 40, bins: int = 36) -> LapMap:
    """The cell means of ``values`` over the lap (its whole part, grouped into at most
    ``rows`` rows of equal laps) and the angle 360°·(laps mod 1) (``bins`` equal bins).

    Parameters
    ----------
    laps : array_like
        Laps run at each reading, fractional (>= 0).
    values : array_like
        μ at each reading.
    """
    turns = non_negative("laps", laps)
    v = finite("values", values)
    if turns.shape != v.shape or turns.ndim != 1 or not turns.size:
        raise ModelInputError("laps and values must be 1-D of one length, not empty")
    if rows < 1 or bins < 1:
        raise ModelInputError(f"rows and bins must be >= 1, got {rows}, {bins}")
    whole = np.floor(turns)
    span = int(whole.max()) + 1
    per_row = max(1, math.ceil(span / rows))
    row = (whole // per_row).astype(np.int64)
    column = np.minimum((np.mod(turns, 1.0) * bins).astype(np.int64), bins - 1)
    n_rows = int(row.max()) + 1
    cell = row * bins + column
    sums = np.bincount(cell, weights=v, minlength=n_rows * bins)
    counts = np.bincount(cell, minlength=n_rows * bins)
    with np.errstate(invalid="ignore", divide="ignore"):
        means = np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)
    return LapMap(
        lap=(np.arange(n_rows, dtype=np.float64) + 0.5) * per_row,
        angle=(np.arange(bins, dtype=np.float64) + 0.5) * 360.0 / bins,
        values=means.reshape(n_rows, bins),
    )


def lap_harmonic(*, laps: ArrayLike, values: ArrayLike) -> tuple[float, float]:
    """The once-per-lap part of ``values``: the least-squares fit
    μ = c + a·cos θ + b·sin θ, θ = 2π·laps, gives (c, √(a² + b²)).

    A disc's run-out or a spot on the track repeats each lap; its amplitude against the
    mean says how even the track is.
    """
    theta = 2.0 * math.pi * finite("laps", laps)
    v = finite("values", values)
    if theta.shape != v.shape or v.size < 3:
        raise ModelInputError("laps and values must be of one length, at least 3")
    basis = np.column_stack([np.ones_like(theta), np.cos(theta), np.sin(theta)])
    (c, a, b), *_ = np.linalg.lstsq(basis, v, rcond=None)
    return float(c), float(math.hypot(a, b))
