"""Roughness as the standards define it: ISO 21920-2 parameters of the ISO 16610-21 roughness
profile, beside the lab manual's method (:mod:`rigserver.core.roughness`).

:func:`iso_profile` is the whole analysis of a trace: the λs and λc filters
(:mod:`rigserver.core.profile_filter`), the evaluation length and its sections, and the
parameters. Each parameter is also a function of its own on the roughness ordinates Z(x) of
the evaluation length, measured from the λc mean line (so not re-centred).

Clause numbers: ISO 21920-2:2021 took its parameters over from ISO 4287:1997 and
ISO 13565-2:1996 (and ISO 21920-3 the defaults of ISO 4288:1996 and ISO 3274:1996); each
function names the parameter as ISO 21920-2 does and the clause of the document that defined
it first, whose numbering is the one labs and instrument manuals quote.

Sampled data: the integrals of the definitions are the means of the uniformly spaced
ordinates (the rectangle rule, exact for whole periods of a sampled sine); the manual's
method integrates the piecewise-linear trace instead (see ``docs/roughness.md``).
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rigserver.core._checks import finite, positive
from rigserver.core.errors import ModelInputError, ModelUndefinedError
from rigserver.core.profile_filter import (
    CUTOFFS,
    STEPS_PER_LAMBDA_S,
    Basis,
    FilteredProfile,
    UniformParts,
    cutoff_for,
    filter_profile,
    lambda_s_for,
    uniform_parts,
)

#: Sections (sampling lengths, lsc = λc) of the default evaluation length (ISO 21920-3;
#: ISO 4288:1996, 4.4).
DEFAULT_SECTIONS = 5

#: Default height discrimination of profile elements: 10 % of Rz (ISO 4287:1997, 3.2,
#: "height and spacing discrimination").
HEIGHT_DISCRIMINATION = 0.10

#: Default spacing discrimination: 1 % of the section length (ISO 4287:1997, 3.2).
SPACING_DISCRIMINATION = 0.01

#: Width of the central region of the material ratio curve, % (ISO 13565-2:1996, 4.1).
RK_WINDOW = 40.0

#: λc the default choice starts from (ISO 4288:1996, 7.2.1: an estimate, then the table).
FIRST_CUTOFF = 0.8e-3

#: Rounds of the default choice of λc before it stops where it is.
MAX_ROUNDS = 6

#: Fewest samples of a trace.
MIN_POINTS = 16

Ends = Literal["discarded", "corrected", "instrument"]

#: The codes of :attr:`IsoProfile.remarks`, what departs from the standard's defaults:
#: ``resampled`` (a trace not uniformly sampled, interpolated onto its median step),
#: ``no_rsm`` (no RSm to choose λc by), ``capped`` (the table's λc is longer than the trace:
#: the longest that fits is used), ``unsettled`` (the choice by the table does not settle),
#: ``short`` (shorter than 2λc: the corrected ends are kept), ``few_sections`` (fewer than
#: five sections), ``coarse_step`` (a sampling step longer than λs/5, ISO 3274), ``parts``
#: (a trace with gaps, analysed in its parts between them, ``RESAMPLING_LIMIT``).
REMARKS = (
    "resampled",
    "no_rsm",
    "capped",
    "unsettled",
    "short",
    "few_sections",
    "coarse_step",
    "parts",
)


# --- field parameters of the ordinates -----------------------------------------------------


def _ordinates(z: ArrayLike) -> NDArray[np.float64]:
    za = finite("z", z)
    if za.ndim != 1 or za.size < 2:
        raise ModelInputError(f"z must be one-dimensional with at least 2 values, got {za.shape}")
    return za


def arithmetic_mean_height(z: ArrayLike) -> float:
    """Ra, arithmetic mean height (ISO 21920-2; ISO 4287:1997, 4.2.1).

    .. math:: R_a = \\frac{1}{l_e}\\int_0^{l_e} |Z(x)|\\,dx
    """
    return float(np.mean(np.abs(_ordinates(z))))


def root_mean_square_height(z: ArrayLike) -> float:
    """Rq, root-mean-square height (ISO 21920-2; ISO 4287:1997, 4.2.2).

    .. math:: R_q = \\Big(\\frac{1}{l_e}\\int_0^{l_e} Z^2(x)\\,dx\\Big)^{1/2}
    """
    scale, unit = _unit(_ordinates(z))
    return scale * float(np.sqrt(np.mean(unit**2)))


def _unit(za: NDArray[np.float64]) -> tuple[float, NDArray[np.float64]]:
    """``za`` as its largest magnitude times ordinates of at most 1 (no power underflows)."""
    scale = float(np.max(np.abs(za))) or 1.0
    return scale, za / scale


def _moment(z: ArrayLike, power: int, name: str) -> float:
    _, unit = _unit(_ordinates(z))  # the ratio is the same for the scaled ordinates
    rq = float(np.sqrt(np.mean(unit**2)))
    if rq == 0:
        raise ModelUndefinedError(f"{name} of a flat profile (Rq = 0) is undefined")
    return float(np.mean(unit**power) / rq**power)


def skewness(z: ArrayLike) -> float:
    """Rsk, skewness (ISO 21920-2; ISO 4287:1997, 4.2.3).

    .. math:: R_{sk} = \\frac{1}{R_q^3}\\frac{1}{l_e}\\int_0^{l_e} Z^3(x)\\,dx
    """
    return _moment(z, 3, "Rsk")


def kurtosis(z: ArrayLike) -> float:
    """Rku, kurtosis (ISO 21920-2; ISO 4287:1997, 4.2.4).

    .. math:: R_{ku} = \\frac{1}{R_q^4}\\frac{1}{l_e}\\int_0^{l_e} Z^4(x)\\,dx
    """
    return _moment(z, 4, "Rku")


@dataclass(frozen=True, slots=True)
class SectionHeights:
    """Rp, Rv and Rz averaged over the sections, and each section's values (m)."""

    rp: float
    rv: float
    rz: float
    per_section_rp: tuple[float, ...]
    per_section_rv: tuple[float, ...]


def section_heights(z: ArrayLike, *, sections: int) -> SectionHeights:
    """Rp, Rv and Rz per section, averaged over the sections of the evaluation length.

    - Rp, maximum peak height: the largest Z of a section (ISO 4287:1997, 4.1.1);
    - Rv, maximum pit (valley) depth: the largest -Z of a section (4.1.2);
    - Rz, maximum height: Rp + Rv of a section (4.1.3);

    each the mean of its values over the ``sections`` sections (ISO 4288:1996, clause 4: a
    parameter defined on a sampling length is the mean over the sampling lengths of the
    evaluation length, five by default; ISO 21920-2 defines Rz so, as the mean of the
    section heights).

    Parameters
    ----------
    z : array_like
        Ordinates of the evaluation length, m.
    sections : int
        Number of sections (>= 1); the ordinates are cut into that many runs of equal
        length (one sample more in the first ones when it does not divide).
    """
    za = _ordinates(z)
    if sections < 1 or sections > za.size:
        raise ModelInputError(f"sections must lie in [1, {za.size}], got {sections}")
    parts = np.array_split(za, sections)
    rp = tuple(float(p.max()) for p in parts)
    rv = tuple(float(-p.min()) for p in parts)
    return SectionHeights(
        rp=float(np.mean(rp)),
        rv=float(np.mean(rv)),
        rz=float(np.mean(np.add(rp, rv))),
        per_section_rp=rp,
        per_section_rv=rv,
    )


def total_height(z: ArrayLike) -> float:
    """Rt, total height: largest peak plus deepest pit over the evaluation length
    (ISO 21920-2; ISO 4287:1997, 4.1.5)."""
    za = _ordinates(z)
    return float(za.max() - za.min())


def local_slope(z: ArrayLike, *, step: float) -> NDArray[np.float64]:
    """dZ/dx at every sample, dimensionless: the local slope of which RΔq is the
    root mean square (ISO 21920-2; ISO 4287:1997, 4.4.1).

    The seven-point central difference

    .. math:: \\frac{dZ_i}{dx} = \\frac{Z_{i+3} - 9Z_{i+2} + 45Z_{i+1} - 45Z_{i-1}
        + 9Z_{i-2} - Z_{i-3}}{60\\,\\Delta x}

    (the formula ISO 4287 gives for the local slope, its error O(Δx⁶)); the three samples at
    each end, which it cannot reach, take the second-order difference of ``numpy.gradient``.
    """
    za = _ordinates(z)
    dx = float(positive("step", step))
    slope = np.asarray(np.gradient(za, dx), dtype=np.float64)
    if za.size >= 7:
        slope[3:-3] = (
            za[6:] - 9.0 * za[5:-1] + 45.0 * za[4:-2] - 45.0 * za[2:-4] + 9.0 * za[1:-5] - za[:-6]
        ) / (60.0 * dx)
    return slope


# --- RSm -----------------------------------------------------------------------------------


def mean_width(
    *,
    x: ArrayLike,
    z: ArrayLike,
    height_discrimination: float,
    spacing_discrimination: float,
) -> float | None:
    """RSm, mean width of the profile elements (ISO 21920-2; ISO 4287:1997, 4.3.1).

    A profile element is a peak (the part above the mean line between two crossings) and the
    valley beside it (ISO 4287:1997, 3.2). A peak or valley lower than
    ``height_discrimination`` or narrower than ``spacing_discrimination`` is no element of
    its own: it is merged with its two neighbours into one part on their side (the lowest
    first, until none is left), so that noise on a flank does not split an element. RSm is
    then the mean distance between successive up-crossings of the mean line (crossings
    located by linear interpolation between samples).

    Parameters
    ----------
    x, z : array_like
        Positions and ordinates of the evaluation length, m.
    height_discrimination : float
        Smallest height of a peak or depth of a valley, m (ISO default: 10 % of Rz).
    spacing_discrimination : float
        Smallest width, m (ISO default: 1 % of the section length).

    Returns
    -------
    float or None
        RSm, m; None when fewer than two elements are left.
    """
    xa = finite("x", x)
    za = _ordinates(z)
    above = za >= 0.0
    idx = np.flatnonzero(above[:-1] != above[1:])
    if idx.size < 3:
        return None
    z0, z1 = za[idx], za[idx + 1]
    xc = xa[idx] + (xa[idx + 1] - xa[idx]) * z0 / (z0 - z1)
    # parts between successive crossings: side (True above), height, start and end
    sides = [bool(above[i + 1]) for i in idx[:-1]]
    heights = [
        float(za[a + 1 : b + 1].max() if up else -za[a + 1 : b + 1].min())
        for a, b, up in zip(idx[:-1], idx[1:], sides, strict=True)
    ]
    starts = list(map(float, xc[:-1]))
    ends = list(map(float, xc[1:]))
    n = len(sides)
    prev = list(range(-1, n - 1))
    nxt = [*range(1, n), -1]
    alive = [True] * n

    def fails(i: int) -> bool:
        return heights[i] < height_discrimination or ends[i] - starts[i] < spacing_discrimination

    heap = [(heights[i], i) for i in range(n) if fails(i)]
    heapq.heapify(heap)
    while heap:
        h, i = heapq.heappop(heap)
        if not alive[i] or h != heights[i] or not fails(i):
            continue
        p, q = prev[i], nxt[i]
        alive[i] = False
        if p < 0 or q < 0:  # an end part: dropped, its neighbour starts the record
            if p >= 0:
                nxt[p] = -1
            if q >= 0:
                prev[q] = -1
            continue
        # the part and its two neighbours (on the other side) become one part there
        heights[p] = max(heights[p], heights[q])
        ends[p] = ends[q]
        alive[q] = False
        nxt[p] = nxt[q]
        if nxt[q] >= 0:
            prev[nxt[q]] = p
        if fails(p):
            heapq.heappush(heap, (heights[p], p))
    ups = [starts[i] for i in range(n) if alive[i] and sides[i]]
    if len(ups) < 2:
        return None
    return (ups[-1] - ups[0]) / (len(ups) - 1)


# --- the material ratio curve and the Rk family -------------------------------------------


@dataclass(frozen=True, slots=True)
class MaterialRatioCurve:
    """The material ratio curve of ordinates (ISO 21920-2; ISO 4287:1997, 4.5.2).

    Attributes
    ----------
    mr : ndarray
        Material ratios, %, increasing from 0 to 100.
    c : ndarray
        Section levels, m, decreasing: the level at which the material ratio is ``mr``.
    """

    mr: NDArray[np.float64]
    c: NDArray[np.float64]

    def ratio(self, level: ArrayLike) -> NDArray[np.float64]:
        """Rmr(c), % (100 below the deepest pit, 0 above the highest peak)."""
        return np.asarray(
            np.interp(finite("c", level), self.c[::-1], self.mr[::-1]), dtype=np.float64
        )

    def level(self, ratio: ArrayLike) -> NDArray[np.float64]:
        """The section level c(Rmr) at a material ratio, m (the inverse of :meth:`ratio`)."""
        r = finite("ratio", ratio)
        if np.any((r < 0) | (r > 100)):
            raise ModelInputError("ratio must lie in [0, 100] %")
        return np.asarray(np.interp(r, self.mr, self.c), dtype=np.float64)


def material_ratio_curve(z: ArrayLike) -> MaterialRatioCurve:
    """The material ratio curve of the ordinates of the evaluation length.

    The i-th highest of n ordinates stands at Rmr = 100·(i - 1/2)/n % (each sample carries
    1/n of the evaluation length), and the curve runs from the highest ordinate at 0 % to
    the lowest at 100 %, linear between.
    """
    za = np.sort(_ordinates(z))[::-1]
    n = za.size
    mr = np.concatenate(([0.0], 100.0 * (np.arange(n) + 0.5) / n, [100.0]))
    c = np.concatenate(([za[0]], za, [za[-1]]))
    return MaterialRatioCurve(mr=mr, c=np.asarray(c, dtype=np.float64))


def material_ratio(z: ArrayLike, *, level: ArrayLike) -> NDArray[np.float64]:
    """Rmr(c), material ratio at level c, % (ISO 21920-2; ISO 4287:1997, 4.5.1).

    .. math:: R_{mr}(c) = \\frac{Ml(c)}{l_e}

    with Ml(c) the material length of the profile at the level c (measured from the mean
    line, positive up).
    """
    return material_ratio_curve(z).ratio(level)


def section_height_difference(z: ArrayLike, *, upper: float, lower: float) -> float:
    """Rδc, section height difference between two material ratios, m (ISO 21920-2;
    ISO 4287:1997, 4.5.3).

    .. math:: R_{\\delta c} = c(R_{mr1}) - c(R_{mr2}), \\quad R_{mr1} < R_{mr2}

    ``upper`` is Rmr1 and ``lower`` Rmr2, both in %.
    """
    if not 0 <= upper < lower <= 100:
        raise ModelInputError(f"need 0 <= upper < lower <= 100 %, got {upper} and {lower}")
    curve = material_ratio_curve(z)
    return float(curve.level(upper) - curve.level(lower))


@dataclass(frozen=True, slots=True)
class RkFamily:
    """The material-ratio parameters of ISO 13565-2 (ISO 21920-2 names them alike).

    Attributes
    ----------
    rk, rpk, rvk : float
        Core height Rk, reduced peak height Rpk, reduced valley depth Rvk, m.
    mr1, mr2 : float
        Material ratios Mr1 (Rmrk1) and Mr2 (Rmrk2) that bound the core, %.
    upper, lower : float
        Levels of the equivalent straight line at 0 % and 100 %, m.
    window_start : float
        Material ratio where the 40 % central region starts, %.
    """

    rk: float
    rpk: float
    rvk: float
    mr1: float
    mr2: float
    upper: float
    lower: float
    window_start: float


def rk_family(z: ArrayLike) -> RkFamily:
    """Rk, Rpk, Rvk, Mr1 and Mr2 of the material ratio curve (ISO 13565-2:1996, 3 and 4).

    1. The central region (4.1): the secant of the material ratio curve over a window of
       40 % material ratio is moved along the curve; the window whose secant has the least
       gradient (the first of equals) is the central region.
    2. The equivalent straight line (4.1): the least-squares line of the curve's points in
       that region (deviations in height).
    3. Rk (4.2): the line's level at 0 % minus its level at 100 %; Mr1 and Mr2 (4.2): the
       material ratios where the curve crosses those two levels.
    4. Rpk and Rvk (4.3): the heights of the right triangles on the bases Mr1 and
       100 % - Mr2 with the areas A1 (of the peaks above the core) and A2 (of the valleys
       below it): Rpk = 2·A1/Mr1, Rvk = 2·A2/(100 % - Mr2).

    Parameters
    ----------
    z : array_like
        Ordinates of the evaluation length, m; the curve is built on them scaled to a largest
        magnitude of 1 (so that no fit underflows on heights of 1e-300 m) and scaled back.
    """
    scale, ordinates = _unit(_ordinates(z))
    unit = _rk_family(ordinates)
    return replace(
        unit,
        rk=unit.rk * scale,
        rpk=unit.rpk * scale,
        rvk=unit.rvk * scale,
        upper=unit.upper * scale,
        lower=unit.lower * scale,
    )


def _rk_family(z: NDArray[np.float64]) -> RkFamily:
    curve = material_ratio_curve(z)
    mr, c = curve.mr[1:-1], curve.c[1:-1]  # the samples (the end points repeat them)
    if float(c[0] - c[-1]) == 0.0:
        raise ModelUndefinedError("the Rk family of a flat profile is undefined")
    fits = mr <= 100.0 - RK_WINDOW
    if not np.any(fits):
        raise ModelUndefinedError("too few ordinates for a 40 % central region")
    start = mr[fits]
    secant = (np.interp(start + RK_WINDOW, mr, c) - c[fits]) / RK_WINDOW
    first = int(np.argmax(secant))  # the least steep (the gradients are <= 0)
    lo = float(start[first])
    inside = (mr >= lo) & (mr <= lo + RK_WINDOW)
    slope, intercept = np.polyfit(mr[inside], c[inside], 1)
    upper = float(intercept)
    lower = float(intercept + 100.0 * slope)
    mr1 = float(curve.ratio(upper))
    mr2 = float(curve.ratio(lower))
    area_peaks = _area(curve.mr, curve.c - upper, 0.0, mr1)
    area_valleys = _area(curve.mr, lower - curve.c, mr2, 100.0)
    return RkFamily(
        rk=upper - lower,
        rpk=2.0 * area_peaks / mr1 if mr1 > 0 else 0.0,
        rvk=2.0 * area_valleys / (100.0 - mr2) if mr2 < 100 else 0.0,
        mr1=mr1,
        mr2=mr2,
        upper=upper,
        lower=lower,
        window_start=lo,
    )


def _area(mr: NDArray[np.float64], h: NDArray[np.float64], a: float, b: float) -> float:
    """∫_a^b h(mr) d(mr) of the piecewise-linear curve, h clipped at 0."""
    if b <= a:
        return 0.0
    inner = (mr > a) & (mr < b)
    grid = np.concatenate(([a], mr[inner], [b]))
    values = np.clip(np.interp(grid, mr, h), 0.0, None)
    return float(np.sum(np.diff(grid) * (values[1:] + values[:-1]) / 2.0))


# --- the whole analysis --------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class IsoParameters:
    """The ISO 21920-2 parameters of a roughness profile (m unless said).

    ``rsm`` is None when the profile has fewer than two elements; ``rsk``, ``rku`` are
    dimensionless, ``rdq`` is a slope (dimensionless), ``mr1`` and ``mr2`` are in %.
    """

    ra: float
    rq: float
    rsk: float
    rku: float
    rp: float
    rv: float
    rz: float
    rt: float
    rsm: float | None
    rdq: float
    rk: float
    rpk: float
    rvk: float
    mr1: float
    mr2: float


def roughness_parameters(
    *,
    x: ArrayLike,
    z: ArrayLike,
    step: float,
    sections: int,
    slope: ArrayLike | None = None,
) -> IsoParameters:
    """Every parameter of :class:`IsoParameters` on the ordinates of an evaluation length.

    Parameters
    ----------
    x, z : array_like
        Positions and roughness ordinates of the evaluation length, m (uniform step).
    step : float
        Sampling step, m.
    sections : int
        Sections of the evaluation length (Rp, Rv, Rz; the spacing discrimination is 1 % of
        one section).
    slope : array_like, optional
        dZ/dx over the evaluation length when the caller has it from a longer record (the
        seven-point difference then reaches the ends); else from ``z``.
    """
    xa = finite("x", x)
    za = _ordinates(z)
    heights = section_heights(za, sections=sections)
    section_length = (float(xa[-1] - xa[0]) + step) / sections
    rk = rk_family(za)
    dz = local_slope(za, step=step) if slope is None else finite("slope", slope)
    return IsoParameters(
        ra=arithmetic_mean_height(za),
        rq=root_mean_square_height(za),
        rsk=skewness(za),
        rku=kurtosis(za),
        rp=heights.rp,
        rv=heights.rv,
        rz=heights.rz,
        rt=total_height(za),
        rsm=mean_width(
            x=xa,
            z=za,
            height_discrimination=HEIGHT_DISCRIMINATION * heights.rz,
            spacing_discrimination=SPACING_DISCRIMINATION * section_length,
        ),
        rdq=root_mean_square_height(dz),
        rk=rk.rk,
        rpk=rk.rpk,
        rvk=rk.rvk,
        mr1=rk.mr1,
        mr2=rk.mr2,
    )


@dataclass(frozen=True, slots=True)
class IsoProfile:
    """A trace analysed as ISO 21920-2 and ISO 16610-21 define it.

    Attributes
    ----------
    x : ndarray
        Positions of the (uniformly sampled) trace, m.
    primary, waviness, roughness : ndarray
        P (form removed, λs filtered), W (its λc mean line), R = P - W, m, over the trace.
    form : ndarray
        The least-squares line removed from the trace, m (the mean line drawn over the
        trace is ``form + waviness``).
    start, stop : int
        The evaluation length is ``x[start:stop]``.
    lambda_c, lambda_s : float
        λc and λs used, m; λs is 0 when no λs filter was applied.
    lambda_c_basis : str
        ``"given"`` or the parameter whose table chose λc (``"ra"``, ``"rz"``, ``"rsm"``).
    ends : {"discarded", "corrected"}
        λc/2 discarded at each end (the trace is at least 2λc long), or the ends kept with
        the ISO 16610-28 correction (a shorter trace).
    sections : int
        Sections of length ``section_length`` = λc in the evaluation length.
    evaluation_length : float
        m.
    parameters : IsoParameters
    resampled : bool
        The trace was not uniformly sampled and was interpolated onto a uniform grid.
    parts : int
        Parts of the trace between its gaps that were analysed (1 but for a trace whose
        resampling would exceed ``RESAMPLING_LIMIT`` times its points); the arrays above are
        then the parts end to end, and ``start``, ``stop`` run from the first evaluation
        length to the last.
    left_out : int
        Points of parts too short to analyse (fewer than ``MIN_POINTS``, or shorter than λc).
    remarks : tuple of str
        What departs from the standard's defaults, as the codes of :data:`REMARKS`.
    """

    x: NDArray[np.float64]
    primary: NDArray[np.float64]
    waviness: NDArray[np.float64]
    roughness: NDArray[np.float64]
    form: NDArray[np.float64]
    start: int
    stop: int
    lambda_c: float
    lambda_s: float
    lambda_c_basis: str
    ends: Ends
    sections: int
    section_length: float
    evaluation_length: float
    parameters: IsoParameters
    resampled: bool = False
    parts: int = 1
    left_out: int = 0
    remarks: tuple[str, ...] = field(default_factory=tuple)


def _trace(x_m: ArrayLike, z_m: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    x = finite("x", x_m)
    z = finite("z", z_m)
    if x.ndim != 1 or x.shape != z.shape:
        raise ModelInputError(
            f"x and z must be one-dimensional and of the same length, got {x.shape}, {z.shape}"
        )
    if x.size < MIN_POINTS:
        raise ModelInputError(f"a trace needs at least {MIN_POINTS} points, got {x.size}")
    if np.any(np.diff(x) <= 0):
        raise ModelInputError("x must be strictly increasing")
    return x, z


@dataclass(frozen=True, slots=True)
class _Evaluation:
    """The filtered parts of a trace joined end to end, and the parameters of their
    evaluation lengths taken together (one part: the trace's own analysis)."""

    profile: FilteredProfile
    start: int
    stop: int
    ends: Ends
    sections: int
    evaluation_length: float
    parts: int
    left_out: int  # points of the parts shorter than λc
    params: IsoParameters


def _evaluate(parts: UniformParts, lc: float, ls: float) -> _Evaluation:
    """Each part at least λc long filtered on its own, its evaluation length centred on it;
    the parameters from the evaluation lengths joined (the sections stay whole, the filters
    never reach across a gap)."""
    step = parts.step
    filtered: list[FilteredProfile] = []
    windows: list[tuple[int, int]] = []
    ends: Ends = "discarded"
    sections = left_out = 0
    for x, z in parts.parts:
        length = float(x[-1] - x[0])
        if length < lc * (1.0 - 1e-9):
            left_out += x.size
            continue
        fp = filter_profile(x=x, z=z, lambda_c=lc, lambda_s=ls if ls > 0 else None)
        if length >= 2.0 * lc * (1.0 - 1e-9):
            own = max(1, math.floor((length - lc) / lc + 1e-9))
        else:
            ends = "corrected"
            own = max(1, math.floor(length / lc + 1e-9))
        count = min(own * max(1, round(lc / step)), x.size)
        start = (x.size - count) // 2
        filtered.append(fp)
        windows.append((start, start + count))
        sections += own
    if not filtered:
        raise ModelInputError(f"no part of the trace between its gaps is as long as λc ({lc} m)")
    offsets = np.cumsum([0] + [fp.x.size for fp in filtered])
    z_eval = np.concatenate(
        [fp.roughness[a:b] for fp, (a, b) in zip(filtered, windows, strict=True)]
    )
    slope = np.concatenate(
        [
            local_slope(fp.roughness, step=step)[a:b]
            for fp, (a, b) in zip(filtered, windows, strict=True)
        ]
    )
    x0 = filtered[0].x[windows[0][0]]
    params = roughness_parameters(
        x=x0 + step * np.arange(z_eval.size), z=z_eval, step=step, sections=sections, slope=slope
    )
    joined = (
        filtered[0]
        if len(filtered) == 1
        else FilteredProfile(
            x=np.concatenate([fp.x for fp in filtered]),
            step=step,
            form=np.concatenate([fp.form for fp in filtered]),
            primary=np.concatenate([fp.primary for fp in filtered]),
            waviness=np.concatenate([fp.waviness for fp in filtered]),
            roughness=np.concatenate([fp.roughness for fp in filtered]),
            lambda_c=lc,
            lambda_s=filtered[0].lambda_s,
        )
    )
    return _Evaluation(
        profile=joined,
        start=int(offsets[0]) + windows[0][0],
        stop=int(offsets[-2]) + windows[-1][1],
        ends=ends,
        sections=sections,
        evaluation_length=float(z_eval.size * step),
        parts=len(filtered),
        left_out=left_out,
        params=params,
    )


def iso_profile(
    x_m: ArrayLike,
    z_m: ArrayLike,
    *,
    lambda_c: float | None = None,
    lambda_s: float | None = None,
    basis: Basis = "ra",
) -> IsoProfile:
    """The ISO analysis of a trace: filters, evaluation length, sections, parameters.

    Parameters
    ----------
    x_m : array_like
        Positions along the trace, m, strictly increasing (at least ``MIN_POINTS``); a trace
        not uniformly sampled is interpolated linearly onto a uniform grid of its median step.
    z_m : array_like
        Heights, m.
    lambda_c : float, optional
        λc, m. By default chosen by the table of ISO 21920-3 (ex ISO 4288:1996) for the
        profile's own ``basis`` parameter, as ISO 4288:1996 7.2 describes: measured with a
        first λc (0.8 mm), then with the table's λc for that value, until the two agree;
        a table value longer than the trace is replaced by the longest one it holds.
    lambda_s : float, optional
        λs, m; by default the one the table pairs with λc (2.5 µm for λc <= 0.8 mm);
        0 for no λs filter.
    basis : {"ra", "rz", "rsm"}
        The table used for the default λc: Ra or Rz (non-periodic profiles) or RSm
        (periodic ones).

    Returns
    -------
    IsoProfile

    Notes
    -----
    Evaluation length (ISO 21920-3; ISO 4288:1996, 4.4): as many whole sections of length
    λc as the trace holds after λc/2 of run-up and run-out at its ends (the default, five
    sections, needs a trace of 6λc); a trace shorter than 2λc keeps its ends (corrected by
    renormalised weights, ISO 16610-28) and has floor(length/λc) sections, at least one.
    The sections are centred on the trace.
    """
    x, z = _trace(x_m, z_m)
    remarks: list[str] = []
    parts = uniform_parts(x, z, min_points=MIN_POINTS)
    if parts.resampled:
        remarks.append("resampled")
    if len(parts.parts) > 1 or parts.left_out:
        remarks.append("parts")
    if not parts.parts:
        raise ModelInputError(
            f"no part of the trace between its gaps holds {MIN_POINTS} points or more"
        )
    length = max(float(px[-1] - px[0]) for px, _ in parts.parts)
    fitting = [c for c in CUTOFFS if c <= length * (1.0 + 1e-9)]
    if lambda_c is not None:
        lc = float(positive("lambda_c", lambda_c))
        if lc > length * (1.0 + 1e-9):
            raise ModelInputError(f"lambda_c = {lc} m is longer than the trace ({length} m)")
        basis_used = "given"
    else:
        if not fitting:
            raise ModelInputError(
                f"the trace ({length} m) is shorter than the smallest λc of the standard "
                f"({CUTOFFS[0]} m)"
            )
        lc = FIRST_CUTOFF if FIRST_CUTOFF in fitting else fitting[-1]
        basis_used = basis
    if lambda_s is not None and not (math.isfinite(lambda_s) and lambda_s >= 0):
        raise ModelInputError(f"lambda_s must be >= 0 m (0: no λs filter), got {lambda_s}")

    def lambda_s_of(cutoff: float) -> float:
        if lambda_s is not None:
            return float(lambda_s)
        return lambda_s_for(lambda_c=cutoff)

    tried: list[float] = []
    choice: list[str] = []  # remarks of the last round of the choice only
    while True:
        ls = lambda_s_of(lc)
        found = _evaluate(parts, lc, ls)
        params = found.params
        if lambda_c is not None:
            break
        value = {"ra": params.ra, "rz": params.rz, "rsm": params.rsm}[basis]
        if value is None:
            choice = ["no_rsm"]
            break
        wanted = cutoff_for(value=value, basis=basis)
        choice = []
        if wanted > length * (1.0 + 1e-9):
            choice = ["capped"]
            wanted = fitting[-1]
        if wanted == lc:
            break
        tried.append(lc)
        if wanted in tried or len(tried) >= MAX_ROUNDS:
            choice.append("unsettled")
            break
        lc = wanted
    remarks += choice
    if found.ends == "corrected":
        remarks.append("short")
    if found.sections < DEFAULT_SECTIONS:
        remarks.append("few_sections")
    if ls > 0 and parts.step > ls / STEPS_PER_LAMBDA_S * (1.0 + 1e-6):
        remarks.append("coarse_step")
    return IsoProfile(
        x=found.profile.x,
        primary=found.profile.primary,
        waviness=found.profile.waviness,
        roughness=found.profile.roughness,
        form=found.profile.form,
        start=found.start,
        stop=found.stop,
        lambda_c=lc,
        lambda_s=ls,
        lambda_c_basis=basis_used,
        ends=found.ends,
        sections=found.sections,
        section_length=lc,
        evaluation_length=found.evaluation_length,
        parameters=params,
        resampled=parts.resampled,
        parts=found.parts,
        left_out=parts.left_out + found.left_out,
        remarks=tuple(remarks),
    )


def section_mean_parameters(
    *,
    x: ArrayLike,
    z: ArrayLike,
    step: float,
    sections: int,
) -> IsoParameters:
    """The parameters of a roughness profile as ISO 4287:1997 defines them on the sampling
    length and ISO 4288:1996 (clause 4) reports them: each the mean of its values over the
    ``sections`` sampling lengths of the evaluation length; Rt and the Rk family (ISO
    13565-2) over the whole evaluation length.

    Per section: Ra, Rq, Rsk, Rku, RΔq, Rp, Rv, Rz and RSm (the height discrimination 10 %
    of that section's Rz, the spacing 1 % of its length), each on the section's ordinates
    from the profile's mean line (not re-centred per section). RΔq takes the local slope
    of ISO 4287:1997's seven-point difference (:func:`local_slope`) over the whole profile,
    so that a section's ends use its neighbours' samples. RSm is the mean over the sections
    that have two elements or more (None when none has).

    Parameters
    ----------
    x, z : array_like
        Positions and roughness ordinates, m (uniform step), the whole evaluation length.
    step : float
        Sampling step, m.
    sections : int
        Sampling lengths in the evaluation length (>= 1); the samples are cut into that
        many runs of equal length (one sample more in the first ones when it does not
        divide).
    """
    xa = finite("x", x)
    za = _ordinates(z)
    if xa.shape != za.shape:
        raise ModelInputError(f"x and z must be of one length, got {xa.shape}, {za.shape}")
    if sections < 1 or sections * 4 > za.size:
        raise ModelInputError(
            f"sections must lie in [1, {za.size // 4}] (four samples each), got {sections}"
        )
    slope = local_slope(za, step=step)
    parts = list(
        zip(
            np.array_split(xa, sections),
            np.array_split(za, sections),
            np.array_split(slope, sections),
            strict=True,
        )
    )
    heights = section_heights(za, sections=sections)
    widths = []
    for xs, zs, _ in parts:
        rz = float(zs.max() - zs.min())
        width = mean_width(
            x=xs,
            z=zs,
            height_discrimination=HEIGHT_DISCRIMINATION * rz,
            spacing_discrimination=SPACING_DISCRIMINATION * (float(xs[-1] - xs[0]) + step),
        )
        if width is not None:
            widths.append(width)
    rk = rk_family(za)

    def mean_of(value: Callable[[NDArray[np.float64], NDArray[np.float64]], float]) -> float:
        return float(np.mean([value(zs, ds) for _, zs, ds in parts]))

    return IsoParameters(
        ra=mean_of(lambda zs, _: arithmetic_mean_height(zs)),
        rq=mean_of(lambda zs, _: root_mean_square_height(zs)),
        rsk=mean_of(lambda zs, _: skewness(zs)),
        rku=mean_of(lambda zs, _: kurtosis(zs)),
        rp=heights.rp,
        rv=heights.rv,
        rz=heights.rz,
        rt=total_height(za),
        rsm=float(np.mean(widths)) if widths else None,
        rdq=mean_of(lambda _, ds: float(np.sqrt(np.mean(ds**2)))),
        rk=rk.rk,
        rpk=rk.rpk,
        rvk=rk.rvk,
        mr1=rk.mr1,
        mr2=rk.mr2,
    )


def instrument_roughness(
    x_m: ArrayLike,
    z_m: ArrayLike,
    *,
    sections: int,
    lambda_c: float = 0.0,
    lambda_s: float = 0.0,
) -> IsoProfile:
    """The ISO parameters of a roughness profile an instrument has already filtered: not
    filtered again, evaluated over its whole length in ``sections`` sampling lengths
    (:func:`section_mean_parameters`). λc and λs are the instrument's, as its file states
    them (0: not stated), reported, not applied.

    Parameters
    ----------
    x_m, z_m : array_like
        Positions (strictly increasing; a trace not uniformly sampled is interpolated onto
        a uniform grid of its median step) and the roughness profile's ordinates, m.
    sections : int
        The sampling lengths the instrument evaluated (>= 1).
    lambda_c, lambda_s : float
        The instrument's λc and λs, m (>= 0).
    """
    found = uniform_parts(*_trace(x_m, z_m), min_points=MIN_POINTS)
    if not found.parts:
        raise ModelInputError(
            f"no part of the trace between its gaps holds {MIN_POINTS} points or more"
        )
    x, z = max(found.parts, key=lambda part: part[0].size)  # a gap: the longest part
    step, resampled = found.step, found.resampled
    lc = float(_stated_cutoff("lambda_c", lambda_c))
    ls = float(_stated_cutoff("lambda_s", lambda_s))
    remarks: list[str] = ["resampled"] if resampled else []
    if len(found.parts) > 1 or found.left_out:
        remarks.append("parts")
    params = section_mean_parameters(x=x, z=z, step=step, sections=sections)
    if sections < DEFAULT_SECTIONS:
        remarks.append("few_sections")
    length = float(x.size * step)
    zero = np.zeros_like(z)
    return IsoProfile(
        x=x,
        primary=z,
        waviness=zero,
        roughness=z,
        form=zero,
        start=0,
        stop=x.size,
        lambda_c=lc,
        lambda_s=ls,
        lambda_c_basis="instrument",
        ends="instrument",
        sections=sections,
        section_length=length / sections,
        evaluation_length=length,
        parameters=params,
        resampled=resampled,
        left_out=found.left_out + sum(px.size for px, _ in found.parts) - x.size,
        remarks=tuple(remarks),
    )


def _stated_cutoff(name: str, value: float) -> float:
    """A cut-off as the instrument states it, m: finite and >= 0 (0: not stated)."""
    if not (math.isfinite(value) and value >= 0):
        raise ModelInputError(f"{name} must be >= 0 m (0: not stated), got {value}")
    return value
