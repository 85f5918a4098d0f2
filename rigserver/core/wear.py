"""Lab work 2: dry sliding wear of a pin on a disc, SMTs-2 friction and wear machine.

The upper specimen (the pin, steel St3sp in the lab, radius r1) wears; the lower one (the
disc, steel R9, radius r2) is harder and sets the roughness. Equation numbers are those of
the lab manual; ``docs/models.md`` of the project (section 2, corrections E1 and E2) is the
checked form of every formula here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rigserver.core._checks import finite, non_negative, positive, within
from rigserver.core.errors import ModelInputError, ModelUndefinedError
from rigserver.core.roughness import complex_parameter_from_ra

__all__ = [
    "ADEQUACY_LOWER",
    "ADEQUACY_UPPER",
    "STEEL_DENSITY",
    "Contact",
    "ExperimentalWear",
    "SteadyFriction",
    "TheoreticalWear",
    "WearAdequacy",
    "adhesive_oxidative_difference",
    "adhesive_oxidative_uncertainty",
    "elastic_fatigue_factor",
    "friction_coefficient",
    "plastic_fatigue_factor",
    "steady_friction",
    "wear_adequacy",
    "wear_intensity_experimental",
    "wear_intensity_theoretical",
    "wear_track_area",
]

#: Density of steel the manual uses for the worn volume, kg/m³ (2.10).
STEEL_DENSITY = 7800.0

#: Band of (2.15): the model is adequate (P = 0.95) when
#: ADEQUACY_LOWER·I_theor <= I_exp <= ADEQUACY_UPPER·I_theor.
ADEQUACY_LOWER = 0.4
ADEQUACY_UPPER = 2.6

#: Contact mode of the pin decided by (2.7).
Contact = Literal["elastic", "plastic"]


def _positive_float(name: str, value: float) -> float:
    return float(positive(name, value))


def friction_coefficient(
    *, friction_moment: ArrayLike, load: ArrayLike, radius: ArrayLike
) -> NDArray[np.float64]:
    """Friction coefficient from the friction moment on the disc shaft (2.8).

    .. math:: f = \\frac{M_{тр}}{N r_2}

    Parameters
    ----------
    friction_moment : array_like
        Friction moment M_тр, N·m (>= 0; a time series is fine).
    load : array_like
        Normal load N on the specimens, N (> 0).
    radius : array_like
        Disc radius r2, m (> 0).

    Returns
    -------
    ndarray
        f, dimensionless, of the broadcast shape of the arguments (a NumPy scalar when all
        three are scalars).

    Notes
    -----
    A zero moment (machine running unloaded) gives f = 0. The stand's own limits
    (moment 1.5-15 N·m, load 200-5000 N) are reading limits, checked where readings enter
    the service, not here.
    """
    moment = non_negative("friction_moment", friction_moment)
    n = positive("load", load)
    r2 = positive("radius", radius)
    return moment / (n * r2)


@dataclass(frozen=True, slots=True)
class SteadyFriction:
    """Steady-state friction coefficient of a run.

    Attributes
    ----------
    mean : float
        Mean f over the steady window, dimensionless.
    std : float
        Standard deviation of f about that mean over the window (ddof = 0), dimensionless.
    start : int
        Index of the first sample of the steady window (the samples before it are taken
        as running-in).
    count : int
        Number of samples in the window.
    """

    mean: float
    std: float
    start: int
    count: int


def steady_window_start(*, samples: int, fraction: float = 0.5) -> int:
    """Index of the first sample of the steady window: the last ``fraction`` of ``samples``.

    The rule of :func:`steady_friction`, for callers that stream a long record.

    Parameters
    ----------
    samples : int
        Length of the series, >= 1.
    fraction : float
        Share of the series, from the end, taken as steady; 0 < fraction <= 1.
    """
    if samples < 1:
        raise ModelInputError(f"samples must be >= 1, got {samples}")
    share = float(within("fraction", fraction, 0.0, 1.0, closed=(False, True)))
    return min(math.floor(samples * (1.0 - share)), samples - 1)


def steady_friction(*, f: ArrayLike, fraction: float = 0.5) -> SteadyFriction:
    """Steady mean of a friction-coefficient series after running-in (for (2.8)).

    The steady window is the last ``fraction`` of the samples; the earlier part is taken as
    running-in. This is a fixed rule, not a detection of when f settles: look at ``std``
    (and at the plot) to judge whether the window is steady.

    Parameters
    ----------
    f : array_like
        Friction coefficient series, one dimension, at least one sample, >= 0, sampled
        evenly (the window is counted in samples, not in time).
    fraction : float
        Share of the series, from the end, taken as steady; 0 < fraction <= 1 (default:
        the last half).

    Returns
    -------
    SteadyFriction
        Mean, standard deviation, index of the first steady sample, sample count.
    """
    series = non_negative("f", f)
    if series.ndim != 1 or series.size == 0:
        raise ModelInputError(
            f"f must be a non-empty one-dimensional series, got shape {series.shape}"
        )
    start = steady_window_start(samples=series.size, fraction=fraction)
    window = series[start:]
    return SteadyFriction(
        mean=float(window.mean()),
        std=float(window.std()),
        start=start,
        count=int(window.size),
    )


@dataclass(frozen=True, slots=True)
class ExperimentalWear:
    """Measured wear of the pin (2.9)-(2.13).

    Attributes
    ----------
    mass_loss : float
        Δm = m1 - m2, kg (2.9).
    volume : float
        Worn volume V = Δm/ρ, m³ (2.10).
    wear_depth : float
        Worn layer thickness h = V/(π r1²), m (2.11).
    sliding_distance : float
        Sliding distance L = 2π r2 M, m (2.12).
    intensity : float
        Linear wear intensity I_h = h/L, dimensionless (2.13).
    """

    mass_loss: float
    volume: float
    wear_depth: float
    sliding_distance: float
    intensity: float


def wear_intensity_experimental(
    *,
    mass_before: float,
    mass_after: float,
    density: float,
    pin_radius: float,
    disc_radius: float,
    revolutions: float,
) -> ExperimentalWear:
    """Linear wear intensity of the pin from its weighings (2.9)-(2.13).

    .. math:: I_{h,exp} = \\frac{h}{L} = \\frac{(m_1 - m_2)/\\rho}{\\pi r_1^2 \\cdot 2\\pi r_2 M}

    Parameters
    ----------
    mass_before : float
        Pin mass before the test m1, kg (> 0).
    mass_after : float
        Pin mass after the test m2, kg (> 0, <= mass_before).
    density : float
        Pin density ρ, kg/m³ (> 0; the manual takes steel, :data:`STEEL_DENSITY`).
    pin_radius : float
        Pin radius r1, m (> 0).
    disc_radius : float
        Disc radius r2, m (> 0).
    revolutions : float
        Total disc revolutions M, a count (> 0). The SMTs-2 counter reads in hundreds: the
        caller multiplies by 100.

    Returns
    -------
    ExperimentalWear
        Δm, V, h, L and I_h.

    Notes
    -----
    Equal masses give zero wear. A pin heavier after the test (material transferred from
    the disc, or a weighing error) is refused: (2.9) measures loss only.
    """
    m1 = _positive_float("mass_before", mass_before)
    m2 = _positive_float("mass_after", mass_after)
    if m2 > m1:
        raise ModelInputError(
            f"mass_after = {m2} kg exceeds mass_before = {m1} kg: the pin gained mass "
            "(transfer from the disc or a weighing error); (2.9) needs mass_after <= mass_before"
        )
    rho = _positive_float("density", density)
    r1 = _positive_float("pin_radius", pin_radius)
    r2 = _positive_float("disc_radius", disc_radius)
    turns = _positive_float("revolutions", revolutions)
    mass_loss = m1 - m2
    volume = mass_loss / rho
    depth = volume / (math.pi * r1**2)
    distance = float(sliding_distance(disc_radius=r2, revolutions=turns))
    return ExperimentalWear(
        mass_loss=mass_loss,
        volume=volume,
        wear_depth=depth,
        sliding_distance=distance,
        intensity=depth / distance,
    )


def sliding_distance(*, disc_radius: float, revolutions: ArrayLike) -> NDArray[np.float64]:
    """Sliding distance of the pin over the disc (2.12).

    .. math:: L = 2\\pi r_2 M_{rev}

    Parameters
    ----------
    disc_radius : float
        r2, radius of the wear track on the disc, m (> 0).
    revolutions : array_like
        M_rev, disc revolutions (>= 0; a count, not the counter's hundreds).

    Returns
    -------
    ndarray
        L, m, shaped as ``revolutions``.
    """
    r2 = _positive_float("disc_radius", disc_radius)
    return 2.0 * math.pi * r2 * non_negative("revolutions", revolutions)


@dataclass(frozen=True, slots=True)
class TheoreticalWear:
    """Kragelsky fatigue-wear intensity of the pin and the quantities behind it (2.1)-(2.7).

    Attributes
    ----------
    intensity : float
        Linear wear intensity I_h^y (elastic) or I_h^n (plastic), dimensionless (2.1).
    contact : {"elastic", "plastic"}
        Contact mode by (2.7): elastic when p_c <= HB.
    contour_pressure : float
        p_c = N/A_c, Pa (2.3).
    nominal_area : float
        A_a = 4π r2 r1, m² (2.5).
    contour_area : float
        A_c = π r1², m² (2.4).
    eta_c : float
        η_c = A_c/A_a, dimensionless.
    complex_parameter : float
        Δ of the disc from its Ra, dimensionless (2.6, corrected E2).
    rmax_over_r : float
        Rmax/R = Δ·b_ν^(1/ν), dimensionless.
    theta : float
        θ = (1 - μ²)/E of the pin, 1/Pa.
    C : float
        C = √ν Γ(ν) Γ(1 + t/2)/(4(ν + 1) Γ(ν + t/2)), dimensionless.
    beta : float
        β = 1/(1 + 2ν), dimensionless.
    k_nu : float
        k_ν = Γ(ν + 1)/(2√π Γ(ν + 1.5)), dimensionless.
    k_f : float
        k_f^y (elastic) or k_f^n (plastic), whichever the contact mode uses, dimensionless.
    """

    intensity: float
    contact: Contact
    contour_pressure: float
    nominal_area: float
    contour_area: float
    eta_c: float
    complex_parameter: float
    rmax_over_r: float
    theta: float
    C: float
    beta: float
    k_nu: float
    k_f: float


def wear_intensity_theoretical(
    *,
    load: float,
    pin_radius: float,
    disc_radius: float,
    friction_coefficient: float,
    ra_disc: float,
    youngs_modulus: float,
    poisson: float,
    hardness: float,
    yield_strength: float,
    tensile_strength: float,
    elongation: float,
    fatigue_t: float,
    nu: float = 2.0,
    b: float = 2.0,
    fatigue_strength: float | None = None,
) -> TheoreticalWear:
    """Linear fatigue-wear intensity of the pin by Kragelsky's model (2.1)-(2.7).

    .. math::

        I_h^y = C \\left(\\frac{p_c\\theta}{k_\\nu}\\right)^{1+\\beta t}
                \\left(\\frac{k_f^y}{\\sigma_B\\theta}\\right)^t
                \\left(\\frac{R_{max}}{R}\\right)^{t(1+\\beta)/2} (\\eta_c b_\\nu)^{-\\beta t}

        I_h^n = C\\sqrt2 \\left(\\frac{p_c}{HB}\\right)^{\\frac{1+\\beta t}{1-\\beta}}
                \\left(\\frac{k_f^n}{e_B}\\right)^t
                \\left(\\frac{R_{max}}{R}\\right)^{(1+t)/2}
                (\\eta_c b_\\nu)^{\\frac{\\beta(1+t)}{1-\\beta}}

    with k_f^y = (2/π)√(4f²(1 - μ + μ²) + 1 - 2μ), k_f^n = √(2(σ_T + 2f·HB)/(σ_T - 2f·HB)),
    p_c = N/A_c (2.3), A_c = π r1² (2.4), A_a = 4π r2 r1 (2.5), Rmax/R = Δ·b_ν^(1/ν).

    Parameters
    ----------
    load : float
        Normal load N, N (> 0).
    pin_radius : float
        Pin radius r1, m (> 0, <= 4·disc_radius so that A_c <= A_a).
    disc_radius : float
        Disc radius r2, m (> 0).
    friction_coefficient : float
        Measured f (2.8), dimensionless (> 0).
    ra_disc : float
        Ra of the disc (the harder, run-in surface), m (> 0).
    youngs_modulus : float
        E1 of the pin, Pa (> 0).
    poisson : float
        μ1 of the pin, 0 <= μ1 <= 0.5.
    hardness : float
        Brinell hardness HB1 of the pin (the softer body), Pa (> 0).
    yield_strength : float
        σ_T of the pin, Pa (> 0, <= tensile_strength).
    tensile_strength : float
        σ_B of the pin, Pa (> 0).
    elongation : float
        e_B = δ/100 of the pin, a fraction, 0 < e_B <= 1.
    fatigue_t : float
        Friction-fatigue exponent t (> 0); the lab takes 3 for elastic and 1.3 for plastic
        contact (table 2.1 lists more). Pass the one that fits the expected mode.
    nu, b : float
        Bearing-curve parameters ν and b_ν of the disc (> 0); 2 and 2 after running-in.
    fatigue_strength : float, optional
        σ0 of the fatigue curve n = (σ0/σ)^t, Pa (> 0); (2.1) takes σ0 = σ_B, the default.
        Only the elastic branch uses it (a sensitivity study varies σ0/σ_B).

    Returns
    -------
    TheoreticalWear
        I_h, the contact mode and the intermediate quantities.

    Raises
    ------
    ModelUndefinedError
        In plastic contact when σ_T <= 2f·HB, where k_f^n has no real value.

    Notes
    -----
    Which body gives which data (manual, (2.1) and item 8 of the calculation procedure):
    the wearing body is the pin, so θ = θ1 = (1 - μ1²)/E1, μ = μ1, HB = HB1 (the softer
    body, in (2.7), in I_h^n and in k_f^n), σ_T, σ_B, e_B and t are the pin's. The disc, the
    harder body, gives the roughness: Δ from its Ra and its bearing-curve ν, b_ν. The disc's
    E2, μ2 and HB2 do not enter (2.1).

    Corrections applied: E1 (the general C is used; at ν = b_ν = 2 it reduces to
    0.118/(1 + t/2), not the printed 0.118·(1 + t/2)); E2 (Δ = 5.4·10⁻²·Ra², Ra in μm, by
    :func:`rigserver.core.roughness.complex_parameter_from_ra`). This k_ν carries the
    factor 1/(2√π) that the k_ν of (1.13) in lab work 1 does not.

    Validity: ν > 0 and t > 0, where Γ(ν) and the exponents are defined (table 1.1 of the
    manual reports measured ν from 0.4 to 3, so no narrower range is imposed);
    0 <= μ1 <= 0.5 keeps k_f^y real; e_B <= 1 catches an elongation passed in percent.
    With steel's data the elastic formula gives I_h orders of magnitude above measured
    values (models.md, section 2); it is computed as specified, never tuned.

    References
    ----------
    .. [1] Lab manual, lab work 2, (2.1)-(2.8), tables 2.1-2.2, item 18.
    """
    n = _positive_float("load", load)
    r1 = _positive_float("pin_radius", pin_radius)
    r2 = _positive_float("disc_radius", disc_radius)
    f = _positive_float("friction_coefficient", friction_coefficient)
    ra = _positive_float("ra_disc", ra_disc)
    E1 = _positive_float("youngs_modulus", youngs_modulus)
    mu = float(within("poisson", poisson, 0.0, 0.5))
    HB = _positive_float("hardness", hardness)
    sigma_t = _positive_float("yield_strength", yield_strength)
    sigma_b = _positive_float("tensile_strength", tensile_strength)
    sigma_0 = (
        sigma_b
        if fatigue_strength is None
        else _positive_float("fatigue_strength", fatigue_strength)
    )
    e_b = float(within("elongation", elongation, 0.0, 1.0, closed=(False, True)))
    t = _positive_float("fatigue_t", fatigue_t)
    nu_ = _positive_float("nu", nu)
    b_nu = _positive_float("b", b)
    if r1 > 4.0 * r2:
        raise ModelInputError(
            f"pin_radius = {r1} m exceeds 4·disc_radius = {4.0 * r2} m: the contour area "
            "A_c = π r1² would exceed the nominal area A_a = 4π r2 r1"
        )
    if sigma_t > sigma_b:
        raise ModelInputError(
            f"yield_strength = {sigma_t} Pa exceeds tensile_strength = {sigma_b} Pa "
            "(σ_T <= σ_B for any material: are the two swapped?)"
        )

    contour_area = math.pi * r1**2
    nominal_area = 4.0 * math.pi * r2 * r1
    eta_c = contour_area / nominal_area
    p_c = n / contour_area
    delta = float(complex_parameter_from_ra(ra=ra))
    rmax_over_r = delta * b_nu ** (1.0 / nu_)
    theta = (1.0 - mu**2) / E1
    C = (
        math.sqrt(nu_)
        * math.exp(math.lgamma(nu_) + math.lgamma(1.0 + t / 2.0) - math.lgamma(nu_ + t / 2.0))
        / (4.0 * (nu_ + 1.0))
    )
    beta = 1.0 / (1.0 + 2.0 * nu_)
    k_nu = math.exp(math.lgamma(nu_ + 1.0) - math.lgamma(nu_ + 1.5)) / (2.0 * math.sqrt(math.pi))

    contact: Contact
    if p_c <= HB:  # (2.7)
        contact = "elastic"
        k_f = elastic_fatigue_factor(friction_coefficient=f, poisson=mu)
        intensity = (
            C
            * (p_c * theta / k_nu) ** (1.0 + beta * t)
            * (k_f / (sigma_0 * theta)) ** t
            * rmax_over_r ** (t * (1.0 + beta) / 2.0)
            * (eta_c * b_nu) ** (-beta * t)
        )
    else:
        contact = "plastic"
        plastic_k_f = plastic_fatigue_factor(
            friction_coefficient=f, yield_strength=sigma_t, hardness=HB
        )
        if plastic_k_f is None:
            raise ModelUndefinedError(
                f"k_f^n of (2.1) is undefined in plastic contact: σ_T = yield_strength = "
                f"{sigma_t} Pa <= 2f·HB = {2.0 * f * HB} Pa (f = {f}, HB = {HB} Pa); "
                "the plastic fatigue model needs σ_T > 2f·HB"
            )
        k_f = plastic_k_f
        intensity = (
            C
            * math.sqrt(2.0)
            * (p_c / HB) ** ((1.0 + beta * t) / (1.0 - beta))
            * (k_f / e_b) ** t
            * rmax_over_r ** ((1.0 + t) / 2.0)
            * (eta_c * b_nu) ** (beta * (1.0 + t) / (1.0 - beta))
        )
    return TheoreticalWear(
        intensity=intensity,
        contact=contact,
        contour_pressure=p_c,
        nominal_area=nominal_area,
        contour_area=contour_area,
        eta_c=eta_c,
        complex_parameter=delta,
        rmax_over_r=rmax_over_r,
        theta=theta,
        C=C,
        beta=beta,
        k_nu=k_nu,
        k_f=k_f,
    )


def elastic_fatigue_factor(*, friction_coefficient: float, poisson: float) -> float:
    """Stress factor of elastic sliding contact, k_f^y of (2.1).

    .. math:: k_f^y = \\frac{2}{\\pi}\\sqrt{4f^2(1 - μ + μ^2) + 1 - 2μ}

    Parameters
    ----------
    friction_coefficient : float
        f, dimensionless (>= 0).
    poisson : float
        μ of the wearing body, 0 <= μ <= 0.5.

    Returns
    -------
    float
        k_f^y: the largest stress at an asperity over its mean contact pressure.
    """
    f = float(non_negative("friction_coefficient", friction_coefficient))
    mu = float(within("poisson", poisson, 0.0, 0.5))
    return (2.0 / math.pi) * math.sqrt(4.0 * f**2 * (1.0 - mu + mu**2) + (1.0 - 2.0 * mu))


def plastic_fatigue_factor(
    *, friction_coefficient: float, yield_strength: float, hardness: float
) -> float | None:
    """Strain factor of plastic sliding contact, k_f^n of (2.1); None where undefined.

    .. math:: k_f^n = \\sqrt{\\frac{2(σ_T + 2f\\,HB)}{σ_T - 2f\\,HB}}

    Parameters
    ----------
    friction_coefficient : float
        f, dimensionless (>= 0).
    yield_strength : float
        σ_T of the wearing body, Pa (> 0).
    hardness : float
        HB of the wearing body, Pa (> 0).

    Returns
    -------
    float or None
        k_f^n, or None when σ_T <= 2f·HB (no real value: the plastic branch of (2.1) does
        not apply).
    """
    f = float(non_negative("friction_coefficient", friction_coefficient))
    sigma_t = _positive_float("yield_strength", yield_strength)
    two_f_hb = 2.0 * f * _positive_float("hardness", hardness)
    if sigma_t <= two_f_hb:
        return None
    return math.sqrt(2.0 * (sigma_t + two_f_hb) / (sigma_t - two_f_hb))


def wear_track_area(*, x: ArrayLike, y: ArrayLike, shoulder: float = 0.1) -> float:
    """Cross-section area of a wear track from a profile traced across it.

    .. math:: A = \\int \\max(0,\\ y_0(x) - y(x))\\,dx

    with y_0 the unworn surface: the least-squares line through the trace's two shoulders
    (its first and last ``shoulder`` of the length, which must lie off the track).

    Parameters
    ----------
    x, y : array_like
        Position across the track and height, m; x increasing, at least 10 samples.
    shoulder : float
        Share of the trace at each end taken as unworn, 0 < shoulder < 0.5.

    Returns
    -------
    float
        A, m² (the trapezoid rule on the depths below y_0). Times the track's length 2π r2
        it is the disc's worn volume (ASTM G99).
    """
    xs = finite("x", x)
    ys = finite("y", y)
    share = float(within("shoulder", shoulder, 0.0, 0.5, closed=(False, False)))
    if xs.ndim != 1 or xs.shape != ys.shape or xs.size < 10 or np.any(np.diff(xs) <= 0):
        raise ModelInputError(
            f"x and y must be one-dimensional, of equal length >= 10, x increasing; got "
            f"shapes {xs.shape}, {ys.shape}"
        )
    edge = max(2, int(share * xs.size))
    ends = np.r_[0:edge, xs.size - edge : xs.size]
    slope, intercept = np.polyfit(xs[ends], ys[ends], 1)
    depth = np.clip(slope * xs + intercept - ys, 0.0, None)
    return float(np.sum((depth[1:] + depth[:-1]) * np.diff(xs)) / 2.0)


@dataclass(frozen=True, slots=True)
class WearAdequacy:
    """Theory against experiment for the wear intensity (2.14)-(2.15).

    Attributes
    ----------
    relative_error_percent : float
        ΔI_h = (I_exp - I_theor)/I_exp·100, percent (2.14).
    adequate : bool
        True when lower <= I_exp <= upper (2.15).
    lower : float
        0.4·I_theor, dimensionless.
    upper : float
        2.6·I_theor, dimensionless.
    """

    relative_error_percent: float
    adequate: bool
    lower: float
    upper: float


def wear_adequacy(*, i_exp: float, i_theor: float) -> WearAdequacy:
    """Relative error of the theoretical wear intensity and the adequacy verdict (2.14)-(2.15).

    .. math:: \\Delta I_h = \\frac{I_{exp} - I_{theor}}{I_{exp}}\\cdot 100\\,\\%, \\qquad
              0.4\\,I_{theor} \\le I_{exp} \\le 2.6\\,I_{theor}

    Parameters
    ----------
    i_exp : float
        Experimental linear wear intensity (2.13), dimensionless (> 0).
    i_theor : float
        Theoretical linear wear intensity (2.1), dimensionless (> 0).

    Returns
    -------
    WearAdequacy
        ΔI_h, the verdict at confidence 0.95 and the band edges (both inclusive).

    Raises
    ------
    ModelUndefinedError
        When i_exp = 0 (no measurable wear): (2.14) divides by I_exp.
    """
    exp_ = float(non_negative("i_exp", i_exp))
    if exp_ == 0.0:
        raise ModelUndefinedError(
            "i_exp = 0 (no measured wear): the relative error (2.14) divides by I_exp"
        )
    theor = _positive_float("i_theor", i_theor)
    lower = ADEQUACY_LOWER * theor
    upper = ADEQUACY_UPPER * theor
    return WearAdequacy(
        relative_error_percent=(exp_ - theor) / exp_ * 100.0,
        adequate=lower <= exp_ <= upper,
        lower=lower,
        upper=upper,
    )


def adhesive_oxidative_difference(*, f_adhesive: float, f_oxidative: float) -> float:
    """Difference of the adhesive and oxidative friction coefficients, percent (2.16).

    .. math:: \\Delta f = \\frac{f_a - f_{ok}}{f_a}\\cdot 100\\,\\%

    Parameters
    ----------
    f_adhesive : float
        f_a of the adhesive run (brass or soft steel pin, 200 N), dimensionless (> 0).
    f_oxidative : float
        f_ok of the oxidative run (rusted or oxidised specimens, 300 N), dimensionless (> 0).

    Returns
    -------
    float
        Δf, percent; positive when adhesive friction is the higher (the usual outcome:
        oxide films lower friction).
    """
    fa = _positive_float("f_adhesive", f_adhesive)
    fok = _positive_float("f_oxidative", f_oxidative)
    return (fa - fok) / fa * 100.0


def adhesive_oxidative_uncertainty(
    *, f_adhesive: float, f_oxidative: float, u_adhesive: float, u_oxidative: float
) -> float:
    """Standard uncertainty of Δf (2.16), percent, from the standard uncertainties of f_a and
    f_ok (independent runs), by the first-order propagation of GUM 5.1.2:

    .. math:: u(\\Delta f) = \\frac{100\\,\\%}{f_a}
              \\sqrt{u(f_{ok})^2 + \\left(\\frac{f_{ok}}{f_a}\\right)^2 u(f_a)^2}

    (∂Δf/∂f_ok = -100 %/f_a, ∂Δf/∂f_a = 100 %·f_ok/f_a²).
    """
    fa = _positive_float("f_adhesive", f_adhesive)
    fok = _positive_float("f_oxidative", f_oxidative)
    ua = float(non_negative("u_adhesive", u_adhesive))
    uok = float(non_negative("u_oxidative", u_oxidative))
    return 100.0 / fa * math.hypot(uok, fok / fa * ua)
