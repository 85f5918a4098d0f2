"""The profile filters of the standards: the ISO 16610-21 Gaussian filter, as λs and λc.

A trace is split into its primary, waviness and roughness profiles as ISO 21920-2 and
ISO 21920-3 define them (ISO 4287:1997 3.1.4-3.1.6 and ISO 3274:1996 before them):

- the form is removed first: the nominal form of a flat specimen, a straight line fitted by
  least squares over the whole trace;
- the **primary profile** P is what the λs filter (a Gaussian low-pass of cut-off λs) keeps
  of it: the wavelengths the stylus and the sampling cannot resolve are taken off;
- the **waviness profile** W is the Gaussian mean line of P with cut-off λc (ISO 16610-21),
  and the **roughness profile** R = P - W is its complement.

Everything is in metres, on a uniformly sampled trace (:func:`uniform_step`).

The weighting function (ISO 16610-21:2011, clause 4.2; ISO 11562:1996, 4.2, eq. 1)

.. math:: s(x) = \\frac{1}{\\alpha\\lambda_c}
    \\exp\\Big(-\\pi\\Big(\\frac{x}{\\alpha\\lambda_c}\\Big)^2\\Big),
    \\qquad \\alpha = \\sqrt{\\ln 2/\\pi} \\approx 0.4697

is a normal density of standard deviation σ = αλc/√(2π) ≈ 0.1874 λc. Its amplitude
transmission (clause 4.3, eq. 2) is

.. math:: \\frac{a_1}{a_0} = \\exp\\Big(-\\pi\\Big(\\frac{\\alpha\\lambda_c}{\\lambda}\\Big)^2\\Big)

for the mean line (a sine of wavelength λc passes at 50 %), and one minus that for the
roughness profile.

What this module chooses where the standard leaves a choice:

- **the kernel's length**: the weighting function is cut at ±``TRUNCATION``·λc (c = 1, a
  kernel 2λc long, within 10⁻⁷ of the transmission below; ISO 16610-21 also allows
  c = 0.5, a kernel λc long, whose cut tails, 2.8 % of the peak, pass 51.1 % at λc and
  -0.2 % at λc/4), and its sampled weights are normalised to a sum of 1 so that a constant
  passes unchanged;
- **the end effects**: near the ends the kernel runs off the trace. The weights that fall
  on the trace are renormalised to a sum of 1 (ISO 16610-28:2016, the end-effect correction
  by the moment criterion of order 0), so that a mean line exists over the whole trace.
  Where the trace is long enough (at least 2λc) the analysis
  (:mod:`rigserver.core.iso_roughness`) still discards λc/2 at each end, the run-up and
  run-out of ISO 4288:1996 and ISO 21920-3, so that the parameters come from where the
  filter is the standard's own; on a shorter trace it keeps the corrected ends and says so.

Defaults of λc and λs (ISO 21920-3:2021, the tables that replaced ISO 4288:1996 table 1-3
and ISO 3274:1996 table 1): :func:`cutoff_for` and :func:`lambda_s_for`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
import scipy.signal
from numpy.typing import ArrayLike, NDArray

from rigserver.core._checks import finite, positive
from rigserver.core.errors import ModelInputError

#: α = √(ln 2 / π) of the Gaussian weighting function (ISO 16610-21, 4.2).
ALPHA = math.sqrt(math.log(2.0) / math.pi)

#: The kernel is cut at ±TRUNCATION·λc (the truncation constant c of ISO 16610-21).
TRUNCATION = 1.0

#: The cut-off wavelengths λc of the standard series, m (ISO 21920-3; ISO 4288 table 1).
CUTOFFS = (0.08e-3, 0.25e-3, 0.8e-3, 2.5e-3, 8e-3)

#: λs for each λc of :data:`CUTOFFS`, m (ISO 21920-3; ISO 3274:1996 table 1).
LAMBDA_S = {0.08e-3: 2.5e-6, 0.25e-3: 2.5e-6, 0.8e-3: 2.5e-6, 2.5e-3: 8e-6, 8e-3: 25e-6}

#: The largest sampling step for each λs is about λs/5 (ISO 3274:1996 table 1: 0.5 µm for
#: λs = 2.5 µm, 1.5 µm for 8 µm, 5 µm for 25 µm).
STEPS_PER_LAMBDA_S = 5.0

#: Non-periodic profiles: the upper limit of Ra (m) of each λc of :data:`CUTOFFS`, the last
#: open (ISO 21920-3 table for Ra; the same ranges as ISO 4288:1996 table 1).
RA_LIMITS = (0.02e-6, 0.1e-6, 2e-6, 10e-6, math.inf)

#: Non-periodic profiles: the upper limit of Rz (m) of each λc (ISO 21920-3 table for Rz).
RZ_LIMITS = (0.16e-6, 0.8e-6, 16e-6, 80e-6, math.inf)

#: Periodic profiles: the upper limit of RSm (m) of each λc (ISO 4288:1996 table 3).
RSM_LIMITS = (0.04e-3, 0.13e-3, 0.4e-3, 1.3e-3, math.inf)

#: Relative spread of the sampling steps taken as uniform.
UNIFORM_RTOL = 1e-3

Basis = Literal["ra", "rz", "rsm"]


def weighting_function(*, x: ArrayLike, cutoff: float) -> NDArray[np.float64]:
    """The Gaussian weighting function s(x) of ISO 16610-21:2011, 4.2 (eq. 1).

    .. math:: s(x) = \\frac{1}{\\alpha\\lambda_c}
        \\exp\\big(-\\pi (x/(\\alpha\\lambda_c))^2\\big), \\quad \\alpha = \\sqrt{\\ln 2/\\pi}

    Parameters
    ----------
    x : array_like
        Distance from the kernel's centre, m.
    cutoff : float
        Cut-off wavelength λc (or λs), m (> 0).

    Returns
    -------
    ndarray
        s(x), 1/m; its integral over the line is 1.
    """
    lc = float(positive("cutoff", cutoff))
    u = finite("x", x) / (ALPHA * lc)
    return np.asarray(np.exp(-np.pi * u**2) / (ALPHA * lc), dtype=np.float64)


def transmission(*, wavelength: ArrayLike, cutoff: float) -> NDArray[np.float64]:
    """Amplitude transmission of the Gaussian mean line (ISO 16610-21:2011, 4.3, eq. 2).

    .. math:: a_1/a_0 = \\exp\\big(-\\pi(\\alpha\\lambda_c/\\lambda)^2\\big)

    The roughness profile (the complement) transmits ``1 - transmission``.

    Parameters
    ----------
    wavelength : array_like
        Wavelength λ of a sine, m (> 0).
    cutoff : float
        λc, m (> 0).

    Returns
    -------
    ndarray
        a1/a0, 0.5 at λ = λc.
    """
    lam = positive("wavelength", wavelength)
    lc = float(positive("cutoff", cutoff))
    return np.asarray(np.exp(-np.pi * (ALPHA * lc / lam) ** 2), dtype=np.float64)


def uniform_step(x: NDArray[np.float64]) -> float | None:
    """The sampling step of ``x`` if its steps agree to ``UNIFORM_RTOL``, else None."""
    steps = np.diff(x)
    step = float(np.median(steps))
    if step <= 0 or np.any(np.abs(steps - step) > UNIFORM_RTOL * step):
        return None
    return step


#: Most points a trace is resampled into, as a multiple of the points received: a trace whose
#: median-step grid would hold more (a gap much longer than the rest of it) is split at its
#: gaps longer than this many median steps, so that work and memory follow what was received,
#: not the span its positions cover (issue 39; ``docs/roughness.md``, "Gaps").
RESAMPLING_LIMIT = 4


@dataclass(frozen=True, slots=True)
class UniformParts:
    """A trace on a uniform grid: one part, or its parts between gaps on a common step."""

    parts: tuple[tuple[NDArray[np.float64], NDArray[np.float64]], ...]
    step: float
    resampled: bool
    left_out: int  # points of parts shorter than ``min_points``


def on_grid(
    x: NDArray[np.float64], z: NDArray[np.float64], step: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``z`` interpolated linearly onto the grid of ``step`` from ``x[0]`` to ``x[-1]``."""
    grid = x[0] + step * np.arange(math.floor((x[-1] - x[0]) / step * (1.0 + 1e-9)) + 1)
    return grid, np.asarray(np.interp(grid, x, z), dtype=np.float64)


def resampling_size(x: NDArray[np.float64]) -> int:
    """Points of ``x``'s grid at its median step (``x`` strictly increasing)."""
    step = float(np.median(np.diff(x)))
    return math.floor(float(x[-1] - x[0]) / step * (1.0 + 1e-9)) + 1


def uniform_parts(
    x: NDArray[np.float64], z: NDArray[np.float64], *, min_points: int
) -> UniformParts:
    """``x``, ``z`` (strictly increasing ``x``) on a uniform grid of their median step.

    A uniformly sampled trace is kept as it is; another is interpolated linearly onto the grid
    of its median step, or, when that grid would hold more than ``RESAMPLING_LIMIT`` times the
    points received, split at its steps longer than ``RESAMPLING_LIMIT`` median steps and each
    part interpolated onto the grid of that step from its own first point (a part of n points
    then makes at most ``RESAMPLING_LIMIT``·n). Parts of fewer than ``min_points`` are left out.
    """
    step = uniform_step(x)
    if step is not None:
        return UniformParts(parts=((x, z),), step=step, resampled=False, left_out=0)
    step = float(np.median(np.diff(x)))
    if resampling_size(x) <= RESAMPLING_LIMIT * x.size:
        return UniformParts(parts=(on_grid(x, z, step),), step=step, resampled=True, left_out=0)
    cuts = np.flatnonzero(np.diff(x) > RESAMPLING_LIMIT * step) + 1
    kept = [(xs, zs) for xs, zs in zip(np.split(x, cuts), np.split(z, cuts), strict=True)]
    parts = tuple(on_grid(xs, zs, step) for xs, zs in kept if xs.size >= min_points)
    left_out = sum(xs.size for xs, _ in kept if xs.size < min_points)
    return UniformParts(parts=parts, step=step, resampled=True, left_out=left_out)


def _kernel(step: float, cutoff: float) -> NDArray[np.float64]:
    half = max(math.floor(TRUNCATION * cutoff / step), 0)
    offsets = np.arange(-half, half + 1, dtype=np.float64) * step
    w = weighting_function(x=offsets, cutoff=cutoff)
    return np.asarray(w / w.sum(), dtype=np.float64)


def gaussian_mean_line(*, z: ArrayLike, step: float, cutoff: float) -> NDArray[np.float64]:
    """The Gaussian mean line (low-pass) of a uniformly sampled profile (ISO 16610-21).

    The discrete weights s(kΔx)Δx for |kΔx| <= ``TRUNCATION``·λc, normalised to a sum of 1;
    at the ends, the weights that fall on the trace are renormalised to a sum of 1
    (ISO 16610-28:2016, end-effect correction of order 0).

    Parameters
    ----------
    z : array_like
        Heights, m, uniformly sampled.
    step : float
        Sampling step Δx, m (> 0).
    cutoff : float
        Cut-off wavelength λc (λs for the λs filter), m (> 0).

    Returns
    -------
    ndarray
        The mean line at every sample, m.
    """
    za = finite("z", z)
    if za.ndim != 1 or za.size == 0:
        raise ModelInputError(f"z must be a non-empty one-dimensional array, got {za.shape}")
    dx = float(positive("step", step))
    w = _kernel(dx, float(positive("cutoff", cutoff)))
    if w.size == 1:
        return za.copy()
    weighted = scipy.signal.oaconvolve(za, w, mode="same")
    covered = scipy.signal.oaconvolve(np.ones_like(za), w, mode="same")
    return np.asarray(weighted / covered, dtype=np.float64)


@dataclass(frozen=True, slots=True)
class FilteredProfile:
    """A trace split into its profiles (ISO 21920-2; ISO 4287:1997 3.1.4-3.1.6).

    Attributes
    ----------
    x : ndarray
        Positions along the trace, m, uniform.
    step : float
        Sampling step, m.
    form : ndarray
        The least-squares line removed (the nominal form), m.
    primary : ndarray
        P: the trace less its form, after the λs filter, m.
    waviness : ndarray
        W: the λc Gaussian mean line of P, m.
    roughness : ndarray
        R = P - W, m.
    lambda_c : float
        λc used, m.
    lambda_s : float or None
        λs used, m; None when no λs filter was applied.
    """

    x: NDArray[np.float64]
    step: float
    form: NDArray[np.float64]
    primary: NDArray[np.float64]
    waviness: NDArray[np.float64]
    roughness: NDArray[np.float64]
    lambda_c: float
    lambda_s: float | None


def filter_profile(
    *, x: ArrayLike, z: ArrayLike, lambda_c: float, lambda_s: float | None
) -> FilteredProfile:
    """Primary, waviness and roughness profiles of a uniformly sampled trace.

    Parameters
    ----------
    x : array_like
        Positions, m, strictly increasing with a uniform step (``UNIFORM_RTOL``).
    z : array_like
        Heights, m, as many as ``x`` (at least 4).
    lambda_c : float
        λc, m (> 0).
    lambda_s : float or None
        λs, m (> 0, < λc), or None for no λs filter.

    Returns
    -------
    FilteredProfile
    """
    xa = finite("x", x)
    za = finite("z", z)
    if xa.ndim != 1 or xa.shape != za.shape or xa.size < 4:
        raise ModelInputError(
            f"x and z must be one-dimensional, of the same length and at least 4 long, got "
            f"shapes {xa.shape} and {za.shape}"
        )
    step = uniform_step(xa)
    if step is None:
        raise ModelInputError("x must be uniformly sampled (resample the trace first)")
    lc = float(positive("lambda_c", lambda_c))
    if lambda_s is not None and not 0 < lambda_s < lc:
        raise ModelInputError(f"lambda_s must lie in (0, lambda_c = {lc}) m, got {lambda_s}")
    slope, intercept = np.polyfit(xa - xa[0], za, 1)
    form = np.asarray(intercept + slope * (xa - xa[0]), dtype=np.float64)
    levelled = za - form
    primary = (
        levelled
        if lambda_s is None
        else gaussian_mean_line(z=levelled, step=step, cutoff=float(lambda_s))
    )
    waviness = gaussian_mean_line(z=primary, step=step, cutoff=lc)
    return FilteredProfile(
        x=xa,
        step=step,
        form=form,
        primary=primary,
        waviness=waviness,
        roughness=np.asarray(primary - waviness, dtype=np.float64),
        lambda_c=lc,
        lambda_s=None if lambda_s is None else float(lambda_s),
    )


def cutoff_for(*, value: float, basis: Basis = "ra") -> float:
    """λc by the table of ISO 21920-3 (ex ISO 4288:1996, tables 1-3) for a measured value.

    Parameters
    ----------
    value : float
        Ra or Rz (non-periodic profiles) or RSm (periodic profiles), m (>= 0).
    basis : {"ra", "rz", "rsm"}
        Which parameter ``value`` is.

    Returns
    -------
    float
        λc, m: the first of :data:`CUTOFFS` whose range holds ``value`` (upper limits
        inclusive).
    """
    limits = {"ra": RA_LIMITS, "rz": RZ_LIMITS, "rsm": RSM_LIMITS}.get(basis)
    if limits is None:
        raise ModelInputError(f"basis must be one of ra, rz, rsm, got {basis!r}")
    v = float(finite("value", value))
    if v < 0:
        raise ModelInputError(f"value must be >= 0, got {v}")
    for cutoff, upper in zip(CUTOFFS, limits, strict=True):
        if v <= upper:
            return cutoff
    return CUTOFFS[-1]  # pragma: no cover - the last limit is infinite


def lambda_s_for(*, lambda_c: float) -> float:
    """λs for λc by ISO 21920-3 (ex ISO 3274:1996, table 1); λc/300 for a λc off the series
    (the ratio of the series from 0.8 mm up)."""
    lc = float(positive("lambda_c", lambda_c))
    for cutoff, ls in LAMBDA_S.items():
        if math.isclose(cutoff, lc, rel_tol=1e-6):
            return ls
    return lc / 300.0
