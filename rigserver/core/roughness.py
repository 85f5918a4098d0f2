"""Lab work 1: roughness of a run-in surface from an ABRIS-PM7 profile.

Equation numbers are those of the lab manual (see ``docs/models.md`` of the project).
A profile is given as samples ``x`` (strictly increasing, m) and ``y`` (m). Between samples
it is taken to be the straight segment joining them (the piecewise-linear interpolant), so
integrals, mean-line crossings and material lengths are exact for that interpolant and do
not need uniform sampling. Reference tables (1.1, 1.2, 1.4, 1.5) and the instrument's
subranges are in :mod:`rigserver.core.roughness_tables`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import scipy.special
from numpy.typing import ArrayLike, NDArray

from rigserver.core._checks import finite, non_negative, one_of, positive, within
from rigserver.core.errors import ModelInputError, ModelUndefinedError
from rigserver.core.roughness_tables import ABRIS_PM7_SUBRANGES, ProfilometerSubrange

#: Coefficient of the run-in relation Ra ≈ 4.3·Δ^(1/2), Ra in μm (1.10).
RA_PER_SQRT_DELTA_UM = 4.3

#: Fewest samples of a profile.
MIN_POINTS = 4

#: Number of highest peaks and of deepest valleys in the ten-point height Rz (1.4).
RZ_POINTS = 5

#: Level pairs (1-based, as in table 1.6) of the manual's estimate of ν (1.16)-(1.17).
MANUAL_NU_PAIRS = ((1, 3), (2, 5), (3, 6))

#: Levels (1-based) of the manual's estimate of b (1.18)-(1.19).
MANUAL_B_LEVELS = (1, 3, 5)

#: Ratio of the effective to the uniaxial hysteresis loss, α_эф = 2.5·α_r (1.12).
ALPHA_EFF_PER_ALPHA_R = 2.5

#: Deviations from the mean line below this fraction of the ordinates are rounding.
_FLAT_RTOL = 1e-10

_SQRT_PI = float(np.sqrt(np.pi))


def ra_from_complex_parameter(*, delta: ArrayLike) -> NDArray[np.float64]:
    """Arithmetic mean deviation of a run-in surface from its complex parameter (1.10).

    .. math:: R_a = 4.3\\,\\Delta^{1/2} \\quad (R_a \\text{ in μm})

    Parameters
    ----------
    delta : array_like
        Complex roughness parameter Δ (dimensionless, >= 0).

    Returns
    -------
    ndarray
        Ra in metres.
    """
    d = non_negative("delta", delta)
    return RA_PER_SQRT_DELTA_UM * np.sqrt(d) * 1e-6


def complex_parameter_from_ra(*, ra: ArrayLike) -> NDArray[np.float64]:
    """Complex roughness parameter of a run-in surface from its Ra (2.6, corrected E2).

    .. math:: \\Delta = (R_a / 4.3)^2 \\approx 5.4\\cdot10^{-2} R_a^2 \\quad (R_a \\text{ in μm})

    The inverse of (1.10); the manual's print of (2.6) drops the square (correction E2).

    Parameters
    ----------
    ra : array_like
        Arithmetic mean deviation Ra in metres (>= 0).

    Returns
    -------
    ndarray
        Δ, dimensionless.
    """
    ra_um = non_negative("ra", ra) * 1e6
    return (ra_um / RA_PER_SQRT_DELTA_UM) ** 2


# --- the sampled profile ------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class MeanLine:
    """The least-squares mean line y = intercept + slope·x of a profile.

    Attributes
    ----------
    slope : float
        Dimensionless (m/m).
    intercept : float
        Ordinate of the line at x = 0, m.
    """

    slope: float
    intercept: float


@dataclass(frozen=True, slots=True)
class ProfileParameters:
    """Roughness parameters of a profile over its base length (1.1)-(1.4).

    Attributes
    ----------
    ra : float
        Arithmetic mean deviation Ra (1.3), m.
    rq : float
        Root-mean-square deviation Rq = ρ, m.
    rz : float
        Ten-point height Rz (1.4), m.
    rmax : float
        Greatest height Rmax: peak line minus valley line, m.
    sm : float
        Mean spacing of the profile elements Sm, m.
    crossings_per_length : float
        ξ, crossings of the mean line per unit length, 1/m.
    peaks_per_length : float
        λ, local maxima of the profile per unit length, 1/m.
    rms_curvature : float
        ρ2 = 2π²·ρ·ξ·λ (1.1), 1/m.
    asperity_radius : float or None
        Mean asperity radius R = √(π/2)/ρ2 (1.1, corrected E5), m; None when it exceeds the
        largest double (heights so small that ρ2 underflows).
    base_length : float
        Base length l = x_last - x_first, m.
    rz_peaks, rz_valleys : tuple of float
        The five highest peaks y_p,i (above the mean line, highest first) and the five
        deepest valleys y_v,i (below it, negative, deepest first) behind Rz (1.4), m.
    """

    ra: float
    rq: float
    rz: float
    rmax: float
    sm: float
    crossings_per_length: float
    peaks_per_length: float
    rms_curvature: float
    asperity_radius: float | None
    base_length: float
    rz_peaks: tuple[float, ...] = ()
    rz_valleys: tuple[float, ...] = ()


def _profile(x: ArrayLike, y: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Check a sampled profile and return it as float arrays."""
    xa = finite("x", x)
    ya = finite("y", y)
    if xa.ndim != 1 or ya.ndim != 1:
        raise ModelInputError(
            f"x and y must be one-dimensional, got shapes {xa.shape} and {ya.shape}"
        )
    if xa.size != ya.size:
        raise ModelInputError(f"x and y must have the same length, got {xa.size} and {ya.size}")
    if xa.size < MIN_POINTS:
        raise ModelInputError(f"a profile needs at least {MIN_POINTS} points, got {xa.size}")
    steps = np.diff(xa)
    if np.any(steps <= 0):
        i = int(np.flatnonzero(steps <= 0)[0])
        raise ModelInputError(
            f"x must be strictly increasing, got x[{i}] = {xa[i]} and x[{i + 1}] = {xa[i + 1]}"
        )
    return xa, ya


def _fit_mean_line(x: NDArray[np.float64], y: NDArray[np.float64]) -> MeanLine:
    """The least-squares line, its sums taken on x and y scaled to a largest deviation of 1
    so that no square underflows (a trace 1e-300 m long) or overflows."""
    x_mean = float(x.mean())
    y_mean = float(y.mean())
    xc, yc = x - x_mean, y - y_mean
    sx = float(np.max(np.abs(xc)))
    sy = float(np.max(np.abs(yc))) or 1.0
    if sx == 0.0:
        raise ModelUndefinedError("x spans no length: no mean line can be fitted")
    u, v = xc / sx, yc / sy
    with np.errstate(over="ignore"):
        slope = float(np.dot(u, v) / np.dot(u, u) * (sy / sx))
        intercept = y_mean - slope * x_mean
    if not (math.isfinite(slope) and math.isfinite(intercept)):
        raise ModelUndefinedError(
            f"the mean line's slope overflows (heights over {sy} m on a trace {2 * sx} m long)"
        )
    return MeanLine(slope=slope, intercept=intercept)


def mean_line(*, x: ArrayLike, y: ArrayLike) -> MeanLine:
    """Least-squares mean line of a profile over its base length.

    The mean line minimises the sum of the squared distances of the profile points to it
    within the base length (manual, lab work 1, procedure item 4); the ordinates Y(X) of
    (1.3)-(1.5) are measured from it.

    Parameters
    ----------
    x : array_like
        Abscissae, strictly increasing, m.
    y : array_like
        Ordinates, m, as many as ``x``.

    Returns
    -------
    MeanLine
        ``slope`` (m/m) and ``intercept`` (m).

    Notes
    -----
    The sum runs over the sample points, as the manual defines it. A sine record that starts
    at a zero of the sine has a non-zero mean line over whole periods (its first half-period
    is above the axis, its last below); a record symmetric about its middle has none.
    """
    return _fit_mean_line(*_profile(x, y))


def _deviation(x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
    """Ordinates from the mean line; refuse a profile that is a straight line."""
    line = _fit_mean_line(x, y)
    fitted = line.intercept + line.slope * x
    r = y - fitted
    scale = max(float(np.max(np.abs(y))), float(np.max(np.abs(fitted))))
    if np.ptp(r) <= _FLAT_RTOL * scale:
        raise ModelUndefinedError(
            f"y is a straight line to rounding (deviation from the mean line {np.ptp(r)} m): "
            "its roughness is undefined"
        )
    return r


def _extrema(r: NDArray[np.float64]) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Indices of the interior local maxima and minima; a flat top or bottom counts once."""
    step = np.diff(r)
    moving = np.flatnonzero(step != 0)
    rising = step[moving] > 0
    # a rising step followed (after any flat steps) by a falling one has its top at the
    # sample after the rising step
    peaks = moving[:-1][rising[:-1] & ~rising[1:]] + 1
    valleys = moving[:-1][~rising[:-1] & rising[1:]] + 1
    return peaks, valleys


def _ten_point_height(
    r: NDArray[np.float64], peaks: NDArray[np.intp], valleys: NDArray[np.intp]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The five highest peaks (heights above the mean line, highest first) and the five
    deepest valleys (their y below it, deepest first) of (1.4); Rz is the difference of
    their means."""
    if peaks.size == 0 or valleys.size == 0:
        raise ModelUndefinedError(
            f"y has {peaks.size} local peaks and {valleys.size} local valleys: Rz needs at "
            "least one of each"
        )
    highest = np.sort(_per_element(r, peaks, above=True))[::-1][:RZ_POINTS]
    deepest = np.sort(-_per_element(r, valleys, above=False))[:RZ_POINTS]
    return highest, deepest


def _per_element(
    r: NDArray[np.float64], extrema: NDArray[np.intp], *, above: bool
) -> NDArray[np.float64]:
    """The highest peak (above) or, negated, the deepest valley of each stretch of the profile
    on one side of the mean line: noise on one asperity makes several local extrema, its
    element has one peak. Extrema on the other side of the line count as their own stretch
    (they never reach the five highest unless the profile has fewer elements)."""
    side = r >= 0.0
    stretch = np.concatenate(([0], np.cumsum(side[1:] != side[:-1])))
    value = r[extrema] if above else -r[extrema]
    order = np.lexsort((value, stretch[extrema]))
    labels = stretch[extrema][order]
    last = np.flatnonzero(np.append(labels[1:] != labels[:-1], True))
    return np.asarray(value[order][last], dtype=np.float64)


def _crossings(x: NDArray[np.float64], r: NDArray[np.float64]) -> tuple[NDArray[np.float64], int]:
    """Abscissae of the up-crossings of the mean line, and the number of down-crossings.

    A sample on the mean line counts as above it.
    """
    below = r < 0
    up = np.flatnonzero(below[:-1] & ~below[1:])
    down = int(np.count_nonzero(~below[:-1] & below[1:]))
    x_up = x[up] + (x[up + 1] - x[up]) * (-r[up]) / (r[up + 1] - r[up])
    return x_up, down


def _integrals(x: NDArray[np.float64], r: NDArray[np.float64]) -> tuple[float, float]:
    """Exact integrals of |r| and r² of the piecewise-linear profile."""
    h = np.diff(x)
    r0 = r[:-1]
    r1 = r[1:]
    a0 = np.abs(r0)
    a1 = np.abs(r1)
    total = a0 + a1
    safe = np.where(total > 0, total, 1.0)
    # a step that changes sign: two triangles meeting on the mean line
    abs_step = np.where(r0 * r1 >= 0, 0.5 * total, 0.5 * (r0**2 + r1**2) / safe)
    sq_step = (r0**2 + r0 * r1 + r1**2) / 3.0
    return float(np.dot(h, abs_step)), float(np.dot(h, sq_step))


def profile_parameters(*, x: ArrayLike, y: ArrayLike) -> ProfileParameters:
    """Roughness parameters of a sampled profile (1.1)-(1.4).

    After removing the least-squares mean line (:func:`mean_line`):

    .. math::
        R_a = \\frac{1}{l}\\int_0^l |Y|\\,dx \\;(1.3), \\quad
        R_q = \\rho = \\Big(\\frac{1}{l}\\int_0^l Y^2 dx\\Big)^{1/2},

    .. math:: R_z = \\frac{1}{5}\\Big(\\sum_{i=1}^5 H_{\\max i}
        - \\sum_{i=1}^5 H_{\\min i}\\Big) \\;(1.4),

    Rmax = max Y - min Y, Sm the mean distance between successive up-crossings of the mean
    line, and the mean asperity radius

    .. math:: \\rho_2 = 2\\pi^2\\rho\\,\\xi\\,\\lambda, \\qquad R = \\sqrt{\\pi/2}\\,/\\,\\rho_2
        \\quad (1.1,\\ \\text{corrected E5}).

    Parameters
    ----------
    x : array_like
        Abscissae, strictly increasing, m (at least ``MIN_POINTS``).
    y : array_like
        Ordinates, m, as many as ``x``.

    Returns
    -------
    ProfileParameters
        Ra, Rq, Rz, Rmax, Sm, ξ, λ, ρ2, R and the base length l.

    Raises
    ------
    ModelInputError
        Empty, mismatched, non-finite or too short input, or x not strictly increasing.
    ModelUndefinedError
        The profile is a straight line, has no interior local peak or valley (Rz), or fewer
        than two up-crossings of the mean line (Sm).

    Notes
    -----
    - Ra and Rq are the exact integrals of the piecewise-linear profile divided by l (the
      trapezoid rule, with a step that crosses the mean line split at the crossing), not
      means of the samples. For a sine of amplitude A sampled M times a period they carry a
      relative error of order (2π/M)².
    - Rz uses the local extrema of the samples (endpoints excluded) measured from the mean
      line, with H_min signed, so that (1.4) with absolute values is recovered when the
      peaks are above and the valleys below the mean line; of the extrema between two
      crossings of the mean line only the highest peak (deepest valley) counts, so that the
      noise on one asperity's top does not count as five peaks. With fewer than five peaks
      (valleys) the mean is taken over those there are.
    - A profile element runs from one up-crossing of the mean line to the next (crossings
      located by linear interpolation; a sample on the line counts as above), so Sm is
      (last - first up-crossing)/(number of up-crossings - 1).
    - ξ counts the up- and down-crossings, λ all local maxima (every sample-level maximum,
      as in the manual: noise adds maxima). ρ is the measured Rq (the manual's ρ ≈ 1.25 Ra
      is its Gaussian estimate).
    - E5: the manual prints R = √(π/(2ρ2)), which is not a length (ρ2 is in 1/m);
      R = √(π/2)/ρ2 is.

    References
    ----------
    Lab manual, lab work 1, (1.1)-(1.4); models.md section 1 and correction E5.
    """
    xa, ya = _profile(x, y)
    r = _deviation(xa, ya)
    length = float(xa[-1] - xa[0])
    height = float(np.max(np.abs(r)))  # integrals of r/height: no square underflows
    abs_integral, sq_integral = _integrals(xa, r / height)
    rq = height * float(np.sqrt(sq_integral / length))
    peaks, valleys = _extrema(r)
    highest, deepest = _ten_point_height(r, peaks, valleys)
    rz = float(highest.mean() - deepest.mean())
    x_up, n_down = _crossings(xa, r)
    if x_up.size < 2:
        raise ModelUndefinedError(
            f"y crosses its mean line upwards {x_up.size} times: Sm needs at least 2"
        )
    xi = (x_up.size + n_down) / length
    lam = peaks.size / length
    rho2 = 2.0 * np.pi**2 * rq * xi * lam
    with np.errstate(divide="ignore", over="ignore"):
        radius = float(np.sqrt(np.pi / 2.0) / rho2)
    return ProfileParameters(
        ra=height * abs_integral / length,
        rq=rq,
        rz=rz,
        rmax=float(np.ptp(r)),
        sm=float((x_up[-1] - x_up[0]) / (x_up.size - 1)),
        crossings_per_length=xi,
        peaks_per_length=lam,
        rms_curvature=rho2,
        asperity_radius=radius if math.isfinite(radius) else None,
        base_length=length,
        rz_peaks=tuple(float(p) for p in highest),
        rz_valleys=tuple(float(v) for v in deepest),
    )


# --- the bearing curve --------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class BearingCurve:
    """Points of the bearing (material-ratio) curve (1.5)-(1.7), one per level (table 1.6).

    Attributes
    ----------
    levels : ndarray
        Levels p below the peak line, m.
    eps : ndarray
        Relative depth ε = p/Rmax (1.7), dimensionless.
    tp : ndarray
        Relative material length t_p = η_p/l (1.6), dimensionless.
    """

    levels: NDArray[np.float64]
    eps: NDArray[np.float64]
    tp: NDArray[np.float64]


def bearing_curve(*, x: ArrayLike, y: ArrayLike, levels: ArrayLike) -> BearingCurve:
    """Bearing curve of a sampled profile at given levels (1.5)-(1.7).

    .. math:: \\eta_p = \\sum_i \\Delta_i \\;(1.5), \\quad t_p = \\eta_p / l \\;(1.6), \\quad
        \\varepsilon = p / R_{\\max} \\;(1.7)

    Parameters
    ----------
    x : array_like
        Abscissae, strictly increasing, m.
    y : array_like
        Ordinates, m, as many as ``x``.
    levels : array_like
        Levels p, m, measured down from the peak line, 0 <= p <= Rmax.

    Returns
    -------
    BearingCurve
        ``levels`` (m), ``eps`` and ``tp`` (dimensionless), in the order given.

    Notes
    -----
    The peak line is parallel to the least-squares mean line through the highest point.
    η_p is the length of x over which the piecewise-linear profile is at or above the level
    (each step cut exactly where it meets the level), not a count of samples; so t_p rises
    continuously from 0 at p = 0 to 1 at p = Rmax.

    References
    ----------
    Lab manual, lab work 1, (1.5)-(1.7), table 1.6, fig. 1.1.
    """
    xa, ya = _profile(x, y)
    r = _deviation(xa, ya)
    rmax = float(np.ptp(r))
    p = within("levels", np.atleast_1d(np.asarray(levels, dtype=np.float64)), 0.0, rmax)
    if p.ndim != 1:
        raise ModelInputError(f"levels must be one-dimensional, got shape {p.shape}")
    cut = float(np.max(r)) - p[:, np.newaxis]
    hi = np.maximum(r[:-1], r[1:])
    lo = np.minimum(r[:-1], r[1:])
    rise = hi - lo
    sloped = rise > 0
    inside = np.clip((hi - cut) / np.where(sloped, rise, 1.0), 0.0, 1.0)
    fraction = np.where(sloped, inside, hi >= cut)
    eta = fraction @ np.diff(xa)
    return BearingCurve(levels=p, eps=p / rmax, tp=eta / float(xa[-1] - xa[0]))


@dataclass(frozen=True, slots=True)
class BearingFit:
    """Parameters of t_p = b·ε^ν (1.8) fitted to a bearing curve (tables 1.7, 1.8).

    Attributes
    ----------
    b : float
        Dimensionless.
    nu : float
        Dimensionless.
    residuals : ndarray
        Δt_p = t_pэ - t_pт = t_p - b·ε^ν at each point given (table 1.8), dimensionless.
    method : str
        ``"manual"`` or ``"lsq"``.
    nu_partial : tuple of float
        (ν_13, ν_25, ν_36) of (1.16) for ``"manual"``; empty for ``"lsq"``.
    b_partial : tuple of float
        (b_1, b_3, b_5) of (1.18) for ``"manual"``; empty for ``"lsq"``.
    """

    b: float
    nu: float
    residuals: NDArray[np.float64]
    method: str
    nu_partial: tuple[float, ...]
    b_partial: tuple[float, ...]


def _fit_manual(
    eps: NDArray[np.float64], tp: NDArray[np.float64]
) -> tuple[float, float, tuple[float, ...], tuple[float, ...]]:
    need = max(max(pair) for pair in MANUAL_NU_PAIRS)
    if eps.size < need:
        raise ModelInputError(
            f"the manual method needs at least {need} levels (pairs {MANUAL_NU_PAIRS}), "
            f"got {eps.size}"
        )
    nus = []
    for i, j in MANUAL_NU_PAIRS:
        if eps[i - 1] == eps[j - 1]:
            raise ModelInputError(
                f"eps[{i - 1}] and eps[{j - 1}] must differ for (1.16), both are {eps[i - 1]}"
            )
        # (1.16) with t_p and ε: the ratios η_pi/η_pj and p_i/p_j are the same
        nus.append(float(np.log10(tp[i - 1] / tp[j - 1]) / np.log10(eps[i - 1] / eps[j - 1])))
    nu = sum(nus) / len(nus)
    with np.errstate(over="ignore"):
        bs = tuple(
            float(10 ** (np.log10(tp[i - 1]) - nu * np.log10(eps[i - 1]))) for i in MANUAL_B_LEVELS
        )
    if not all(math.isfinite(b) for b in bs):
        raise ModelUndefinedError(f"b of (1.8) overflows: ν = {nu}, b = {bs}")
    return sum(bs) / len(bs), nu, tuple(nus), bs


def _fit_lsq(eps: NDArray[np.float64], tp: NDArray[np.float64]) -> tuple[float, float]:
    if eps.size < 2 or np.all(eps == eps[0]):
        raise ModelInputError(
            f"the least-squares fit needs at least two distinct eps, got {eps.tolist()}"
        )
    nu, log_b = np.polyfit(np.log(eps), np.log(tp), 1)
    return float(np.exp(log_b)), float(nu)


def fit_bearing_curve(*, eps: ArrayLike, tp: ArrayLike, method: str = "manual") -> BearingFit:
    """Fit t_p = b·ε^ν (1.8) to points of the bearing curve (1.16)-(1.19).

    ``"manual"``, as students do it by hand:

    .. math:: \\nu_{ij} = \\lg\\frac{\\eta_{pi}}{\\eta_{pj}} \\Big/ \\lg\\frac{p_i}{p_j} \\;(1.16),
        \\quad \\nu = \\frac{\\nu_{1,3} + \\nu_{2,5} + \\nu_{3,6}}{3} \\;(1.17),

    .. math:: \\lg b_i = \\lg t_{pi} - \\nu \\lg\\varepsilon_i \\;(1.18), \\quad
        b = \\frac{b_1 + b_3 + b_5}{3} \\;(1.19).

    ``"lsq"``: least squares of lg t_p on lg ε over all the points given.

    Parameters
    ----------
    eps : array_like
        Relative depths ε, 0 < ε <= 1, in the order of table 1.6 (the manual method uses
        points 1, 2, 3, 5 and 6 for ν and 1, 3, 5 for b, 1-based).
    tp : array_like
        Relative material lengths t_p, 0 < t_p <= 1, as many as ``eps``.
    method : {"manual", "lsq"}
        Fitting method.

    Returns
    -------
    BearingFit
        b, ν, the residuals t_p - b·ε^ν of table 1.8 at every point, the method, and the
        partial values of table 1.7 for the manual method.

    Notes
    -----
    Give only the initial part of the curve: (1.8) describes it, not the whole curve.
    In (1.16) η_pi/η_pj = t_pi/t_pj and p_i/p_j = ε_i/ε_j, so t_p and ε are used.

    References
    ----------
    Lab manual, lab work 1, (1.8), (1.16)-(1.19), tables 1.7-1.8.
    """
    method = one_of("method", method, ("manual", "lsq"))
    e = within(
        "eps", np.atleast_1d(np.asarray(eps, dtype=np.float64)), 0.0, 1.0, closed=(False, True)
    )
    t = within(
        "tp", np.atleast_1d(np.asarray(tp, dtype=np.float64)), 0.0, 1.0, closed=(False, True)
    )
    if e.ndim != 1 or e.shape != t.shape:
        raise ModelInputError(
            f"eps and tp must be one-dimensional and of the same length, got shapes "
            f"{e.shape} and {t.shape}"
        )
    nu_partial: tuple[float, ...] = ()
    b_partial: tuple[float, ...] = ()
    if method == "manual":
        b, nu, nu_partial, b_partial = _fit_manual(e, t)
    else:
        b, nu = _fit_lsq(e, t)
    return BearingFit(
        b=b,
        nu=nu,
        residuals=t - b * e**nu,
        method=method,
        nu_partial=nu_partial,
        b_partial=b_partial,
    )


# --- complex parameter and equilibrium roughness -------------------------------------------


def complex_parameter(
    *, rmax: ArrayLike, radius: ArrayLike, b: ArrayLike, nu: ArrayLike
) -> NDArray[np.float64]:
    """Complex roughness parameter (1.9).

    .. math:: \\Delta = \\frac{R_{\\max}}{R\\, b^{1/\\nu}}

    Parameters
    ----------
    rmax : array_like
        Greatest profile height Rmax, m (> 0).
    radius : array_like
        Mean asperity radius R, m (> 0).
    b, nu : array_like
        Bearing-curve parameters of (1.8), dimensionless (> 0).

    Returns
    -------
    ndarray
        Δ, dimensionless.

    References
    ----------
    Lab manual, lab work 1, (1.9).
    """
    rm, r = positive("rmax", rmax), positive("radius", radius)
    bb, n = positive("b", b), positive("nu", nu)
    with np.errstate(over="ignore", divide="ignore"):
        delta = rm / (r * bb ** (1.0 / n))
    if not np.all(np.isfinite(delta)):
        raise ModelUndefinedError(f"Δ overflows: Rmax = {rm} m, R = {r} m, b = {bb}, ν = {n}")
    return delta


class K1K2(NamedTuple):
    """Coefficients k1, k2 of (1.11), from (1.13); unpacks as ``k1, k2``.

    Attributes
    ----------
    k1, k2 : ndarray
        Dimensionless.
    """

    k1: NDArray[np.float64]
    k2: NDArray[np.float64]

    @property
    def k_nu(self) -> NDArray[np.float64]:
        """k_ν = Γ(ν+1)/Γ(ν+1.5) of (1.13), dimensionless (lab 1's k_ν, not lab 2's)."""
        return 2.0 * _SQRT_PI / self.k1


def k1_k2(*, nu: ArrayLike) -> K1K2:
    """Coefficients k1 and k2 of the equilibrium roughness (1.13), table 1.3.

    .. math:: k_\\nu = \\frac{\\Gamma(\\nu+1)}{\\Gamma(\\nu+1.5)}, \\quad
        k_1 = \\frac{2\\sqrt{\\pi}}{k_\\nu}, \\quad
        k_2 = \\frac{3.04}{3\\sqrt{\\pi}(\\nu+1)k_\\nu}

    Parameters
    ----------
    nu : array_like
        Bearing-curve exponent ν (> 0).

    Returns
    -------
    K1K2
        ``k1`` and ``k2`` (dimensionless); ``k_nu`` as a property.

    Notes
    -----
    This k_ν is lab work 1's; lab work 2 (2.1) calls Γ(ν+1)/(2√π·Γ(ν+1.5)) = 1/k1 k_ν.
    Against table 1.3 (ν = 1..3.5) the formula reproduces every printed value except
    k2(2.5) = 0.295 (printed 0.30) and k1(3.5) = 7.31 (printed 7.4).

    References
    ----------
    Lab manual, lab work 1, (1.13), table 1.3.
    """
    n = positive("nu", nu)
    k_nu = np.exp(
        np.asarray(
            scipy.special.gammaln(n + 1.0) - scipy.special.gammaln(n + 1.5), dtype=np.float64
        )
    )
    return K1K2(k1=2.0 * _SQRT_PI / k_nu, k2=3.04 / (3.0 * _SQRT_PI * (n + 1.0) * k_nu))


def equilibrium_complex_parameter(
    *,
    nu: ArrayLike,
    poisson: ArrayLike,
    youngs_modulus: ArrayLike,
    contour_pressure: ArrayLike,
    tau0: ArrayLike,
    alpha_r: ArrayLike,
) -> NDArray[np.float64]:
    """Theoretical complex parameter of the equilibrium (run-in) roughness (1.11)-(1.12).

    .. math:: \\Delta = (k_1\\theta)^{\\frac{2\\nu-1}{2\\nu}}\\, p_c^{-1/\\nu}
        \\Big(\\frac{\\tau_0}{k_2\\,\\alpha_{эф}}\\Big)^{\\frac{2\\nu+1}{2\\nu}},
        \\quad \\theta = \\frac{1-\\mu^2}{E}, \\quad \\alpha_{эф} = 2.5\\,\\alpha_r

    Parameters
    ----------
    nu : array_like
        Bearing-curve exponent ν (> 0).
    poisson : array_like
        Poisson's ratio μ, 0 <= μ <= 0.5.
    youngs_modulus : array_like
        Young's modulus E, Pa (> 0).
    contour_pressure : array_like
        Contour pressure p_c, Pa (> 0).
    tau0 : array_like
        Friction parameter τ0, Pa (> 0); tables 1.4-1.5.
    alpha_r : array_like
        Hysteresis loss coefficient under uniaxial load α_r, 0 < α_r <= 0.4; table 1.2.

    Returns
    -------
    ndarray
        Δ, dimensionless.

    Notes
    -----
    Dimensionless: θ is in 1/Pa, so the pascals carry the exponent
    -(2ν-1)/(2ν) - 1/ν + (2ν+1)/(2ν) = 0. α_эф = 2.5·α_r is a fraction of the energy lost
    per cycle and cannot exceed 1, hence α_r <= 0.4. k1, k2 from :func:`k1_k2`.

    References
    ----------
    Lab manual, lab work 1, (1.11)-(1.13), procedure item 13.
    """
    n = positive("nu", nu)
    mu = within("poisson", poisson, 0.0, 0.5)
    theta = (1.0 - mu**2) / positive("youngs_modulus", youngs_modulus)
    p_c = positive("contour_pressure", contour_pressure)
    alpha_eff = ALPHA_EFF_PER_ALPHA_R * within("alpha_r", alpha_r, 0.0, 0.4, closed=(False, True))
    k1, k2 = k1_k2(nu=n)
    ratio = positive("tau0", tau0) / (k2 * alpha_eff)
    return (
        (k1 * theta) ** ((2.0 * n - 1.0) / (2.0 * n))
        * p_c ** (-1.0 / n)
        * ratio ** ((2.0 * n + 1.0) / (2.0 * n))
    )


# --- instrument error limits ---------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class InstrumentError:
    """Limits of the ABRIS-PM7's basic error for a set of parameters (1.14).

    Attributes
    ----------
    ra, rz, rmax, sm : float
        Error limits ΔRa, ΔRz, ΔRmax, ΔSm, m.
    cutoff : float
        Base length (cutoff) of the subrange whose upper limits were used, m.
    """

    ra: float
    rz: float
    rmax: float
    sm: float
    cutoff: float


def _subrange(ra: float, cutoff: float | None) -> ProfilometerSubrange:
    if cutoff is None:
        for sub in ABRIS_PM7_SUBRANGES:
            if sub.ra_min <= ra <= sub.ra_max:
                return sub
        raise ModelInputError(
            f"parameters.ra must lie in the ABRIS-PM7 range [{ABRIS_PM7_SUBRANGES[0].ra_min}, "
            f"{ABRIS_PM7_SUBRANGES[-1].ra_max}] m, got {ra}"
        )
    for sub in ABRIS_PM7_SUBRANGES:
        if np.isclose(cutoff, sub.cutoff, rtol=1e-9, atol=0.0):
            return sub
    listed = ", ".join(str(sub.cutoff) for sub in ABRIS_PM7_SUBRANGES)
    raise ModelInputError(f"cutoff must be one of {listed} m, got {cutoff}")


def instrument_error(
    *, parameters: ProfileParameters, cutoff: float | None = None
) -> InstrumentError:
    """Limits of the profilometer's basic error of Ra, Rz, Rmax, Sm (1.14).

    .. math::
        \\Delta R_a = 0.02 R_{a\\,г.н.} + 0.04 R_a, \\quad
        \\Delta R_z = 0.03 R_{z\\,г.н.} + 0.05 R_z, \\quad
        \\Delta R_{\\max} = 0.03 R_{\\max\\,г.н.} + 0.05 R_{\\max}, \\quad
        \\Delta S_m = 0.02 S_{m\\,г.н.} + 0.01 S_m

    where ``г.н.`` is the upper limit of the subrange.

    Parameters
    ----------
    parameters : ProfileParameters
        The measured parameters (Ra, Rz, Rmax, Sm are used).
    cutoff : float, optional
        Base length of the subrange the instrument was set to, m: 0.25e-3, 0.8e-3 or
        2.5e-3. By default the subrange whose Ra range holds the measured Ra (the finer one
        at a shared limit), as the operator chooses it by Ra.

    Returns
    -------
    InstrumentError
        ΔRa, ΔRz, ΔRmax, ΔSm in metres and the cutoff used.

    Notes
    -----
    The manual states the limits for a near-trapezoidal profile with a step of at most
    0.25 of the cutoff; Rz and Rmax share the upper limit of their range.

    References
    ----------
    Lab manual, lab work 1, ABRIS-PM7 technical data, items 1 and 7, (1.14).
    """
    sub = _subrange(parameters.ra, cutoff)
    return InstrumentError(
        ra=0.02 * sub.ra_max + 0.04 * parameters.ra,
        rz=0.03 * sub.rz_max + 0.05 * parameters.rz,
        rmax=0.03 * sub.rz_max + 0.05 * parameters.rmax,
        sm=0.02 * sub.sm_max + 0.01 * parameters.sm,
        cutoff=sub.cutoff,
    )


def subrange_of_base_length(base_length: float) -> ProfilometerSubrange | None:
    """The ABRIS-PM7 subrange whose cutoff is the traced base length (within 1 %), if any."""
    for sub in ABRIS_PM7_SUBRANGES:
        if abs(base_length - sub.cutoff) <= 0.01 * sub.cutoff:
            return sub
    return None


def outside_subrange(
    *, parameters: ProfileParameters, subrange: ProfilometerSubrange
) -> tuple[str, ...]:
    """The parameters (``"Ra"``, ``"Rz"``, ``"Rmax"``, ``"Sm"``) outside the ranges of
    ``subrange``, for which the error limits (1.14) are not stated.

    References
    ----------
    Lab manual, lab work 1, ABRIS-PM7 technical data, item 1 (the subranges' ranges).
    """
    checks = (
        ("Ra", parameters.ra, subrange.ra_min, subrange.ra_max),
        ("Rz", parameters.rz, subrange.rz_min, subrange.rz_max),
        ("Rmax", parameters.rmax, subrange.rz_min, subrange.rz_max),
        ("Sm", parameters.sm, subrange.sm_min, subrange.sm_max),
    )
    return tuple(name for name, value, low, high in checks if not low <= value <= high)


@dataclass(frozen=True, slots=True)
class ProfilogramDiscrepancy:
    """The profilometer's readings against the profilogram's values (1.20), in %, each
    relative to the profilometer's reading (E10).

    Attributes
    ----------
    rmax : float
        δ = (Rmax1 - Rmax2)/Rmax1·100 %.
    rz : float
        δ_Rz = (Rz1 - Rz2)/Rz1·100 %.
    ra : float or None
        δ_Ra = (Ra1 - Ra2)/Ra1·100 % (item 10 compares Ra too), None without the reading.
    """

    rmax: float
    rz: float
    ra: float | None = None


def relative_to_reading(reading: float, profilogram: float) -> float:
    """(reading - profilogram)/reading·100 %: (1.20) with the denominator of E10;
    ``ModelInputError`` when the reading is so small against the profilogram that the
    difference passes the largest float."""
    found = (reading - profilogram) / reading * 100.0
    if not math.isfinite(found):
        raise ModelInputError(
            f"the reading {reading:g} m is too small for a difference relative to it "
            f"(the profilogram's {profilogram:g} m)"
        )
    return float(found)


def profilogram_discrepancy(
    *,
    rmax_instrument: float,
    rmax_profilogram: float,
    rz_instrument: float,
    rz_profilogram: float,
    ra_instrument: float | None = None,
    ra_profilogram: float | None = None,
) -> ProfilogramDiscrepancy:
    """Differences of the profilometer's Ra, Rz, Rmax from the profilogram's (1.20, E10).

    .. math:: δ = \\frac{R_{max1} - R_{max2}}{R_{max1}}\\,100\\ \\%,\\quad
              δ_{Rz} = \\frac{Rz_1 - Rz_2}{Rz_1}\\,100\\ \\%

    Index 1: the profilometer's reading (procedure item 1); 2: from the profilogram (items
    4-5). The manual divides δ_Rz by Rz2 but δ by Rmax1; E10 takes the reading for both
    (and for δ_Ra), one convention for the three.

    References
    ----------
    Lab manual, lab work 1, procedure item 10, (1.20); models.md, E10.
    """
    r1 = float(positive("rmax_instrument", rmax_instrument))
    r2 = float(positive("rmax_profilogram", rmax_profilogram))
    z1 = float(positive("rz_instrument", rz_instrument))
    z2 = float(positive("rz_profilogram", rz_profilogram))
    ra = None
    if ra_instrument is not None and ra_profilogram is not None:
        a1 = float(positive("ra_instrument", ra_instrument))
        ra = relative_to_reading(a1, float(positive("ra_profilogram", ra_profilogram)))
    return ProfilogramDiscrepancy(
        rmax=relative_to_reading(r1, r2), rz=relative_to_reading(z1, z2), ra=ra
    )


def bearing_ratio_error(*, tp: ArrayLike) -> NDArray[np.float64]:
    """Limit of the profilometer's basic error of t_p (1.14).

    .. math:: \\Delta t_p = 8 + 0.02\\,t_p \\quad (\\%)

    Parameters
    ----------
    tp : array_like
        Relative material length t_p as a fraction, 0 <= t_p <= 1.

    Returns
    -------
    ndarray
        Δt_p as a fraction (8 % is 0.08).

    References
    ----------
    Lab manual, lab work 1, ABRIS-PM7 technical data, item 7, (1.14).
    """
    return 0.08 + 0.02 * within("tp", tp, 0.0, 1.0)


def profile_ordinate_error(*, y: ArrayLike, y_upper: ArrayLike) -> NDArray[np.float64]:
    """Limit of the profilograph's basic error of the profile ordinates (1.15).

    .. math:: \\Delta y = 0.02\\,y_{г.н.} + 0.01\\,y

    Parameters
    ----------
    y : array_like
        Largest absolute ordinate of the profilogram, m (>= 0).
    y_upper : array_like
        Upper limit of the subrange of the chosen vertical magnification, m (> 0).

    Returns
    -------
    ndarray
        Δy, m.

    References
    ----------
    Lab manual, lab work 1, ABRIS-PM7 technical data, item 8, (1.15).
    """
    return 0.02 * positive("y_upper", y_upper) + 0.01 * non_negative("y", y)
