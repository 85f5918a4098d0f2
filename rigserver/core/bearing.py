"""Labs 3 and 4: asymptotic theory of a plain journal bearing.

Short bearing (3.10) and infinitely long bearing (3.15) pressure fields, the integrals
A_n^ij of the short-bearing method (4.5), the short-bearing film force (4.2)-(4.4) with its
inverse, and the friction moment and coefficient (4.1), (4.10).

Frame and signs (manual, fig. 3.2): the film is H = 1 - χ cos φ, widest at φ = π and
thinnest at φ = 0 = 2π; for a journal turning with G > 0 the film converges from π to 2π,
which is the load zone (3.11) where both asymptotic pressures are positive. The force
projections are P_τ = ∫∫ p sin φ dA (perpendicular to the line of centres, negative for
G > 0 as the manual's V of (4.4)) and P_r = ∫∫ p cos φ dA (along the line of centres).

The half-width is a = B/(2R) = B/D (correction E3 of docs/models.md; the print has B/(4R)).
Equation numbers are the lab manual's.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from rigserver.core._checks import finite, non_negative, positive, within
from rigserver.core.errors import ModelInputError

FloatArray = NDArray[np.float64]

#: Upper end of the eccentricity-ratio bracket of :func:`short_bearing_eccentricity`.
CHI_BRACKET_TOP = 1.0 - 1e-12


def _chi(chi: ArrayLike) -> FloatArray:
    return within("chi", chi, 0.0, 1.0, closed=(True, False))


def _half_width_check(z: FloatArray, a: FloatArray) -> None:
    outside = np.abs(z) > a
    if np.any(outside):
        zb, ab = np.broadcast_arrays(z, a)
        raise ModelInputError(
            f"z must lie in [-a, a] (the bearing width), got z = {zb[outside].flat[0]} "
            f"with a = {ab[outside].flat[0]}"
        )


def _clip(pressure: FloatArray, cavitated: bool) -> FloatArray:
    return np.maximum(pressure, 0.0) if cavitated else pressure


def short_bearing_pressure(
    *,
    phi: ArrayLike,
    z: ArrayLike,
    chi: ArrayLike,
    a: ArrayLike,
    mu_bar: ArrayLike,
    G: ArrayLike,
    E: ArrayLike = 0.0,
    cavitated: bool = False,
) -> FloatArray:
    """Dimensionless hydrodynamic pressure of a short bearing (3.10).

    .. math:: Π_0 = 3\\bar μ a^2 \\frac{Gχ\\sin φ - E\\cos φ}{(1 - χ\\cos φ)^3}
              \\left[\\left(\\frac{z}{a}\\right)^2 - 1\\right]

    Parameters
    ----------
    phi : array_like
        Angular coordinate φ, rad, from the widest gap of the film (fig. 3.2).
    z : array_like
        Axial coordinate z = Z/R, dimensionless, within [-a, a].
    chi : array_like
        Eccentricity ratio χ = e/h0, in [0, 1).
    a : array_like
        Half-width a = B/(2R) (> 0), see correction E3.
    mu_bar : array_like
        Dimensionless mean viscosity μ̄ = μ/μ0 (> 0).
    G : array_like
        G = Ω - 2δ' (3.4); for a steady journal G = ω1/ω0 (3.12).
    E : array_like, optional
        E = 2χ' (3.4), zero for a steady load (3.12).
    cavitated : bool, optional
        False (default): the raw signed formula. True: negative pressures clipped to zero
        (Gümbel's π-film condition, Π ≥ 0 of (3.5)).

    Returns
    -------
    ndarray
        Π0, broadcast over all arguments; p - p_a = Π·μ0ω0/Ψ² with Ψ = h0/R (3.6).

    Notes
    -----
    Valid for a short bearing (a ≲ 0.25 per the manual, where axial flow dominates (3.7)).
    The raw formula is antisymmetric in φ about π for E = 0; it is positive in the load
    zone φ ∈ (π, 2π) (3.11) when G > 0 and zero at the edges z = ±a.

    References
    ----------
    .. [1] Lab manual, lab work 3, (3.8)-(3.12).
    .. [2] F. W. Ocvirk, "Short-bearing approximation for full journal bearings",
       NACA TN 2808, 1952.
    """
    phi_ = finite("phi", phi)
    z_ = finite("z", z)
    chi_ = _chi(chi)
    a_ = positive("a", a)
    mu_ = positive("mu_bar", mu_bar)
    G_ = finite("G", G)
    E_ = finite("E", E)
    _half_width_check(z_, a_)
    film = 1.0 - chi_ * np.cos(phi_)
    squeeze_wedge = G_ * chi_ * np.sin(phi_) - E_ * np.cos(phi_)
    pressure = 3.0 * mu_ * a_**2 * squeeze_wedge / film**3 * ((z_ / a_) ** 2 - 1.0)
    return _clip(np.asarray(pressure, dtype=np.float64), cavitated)


def long_bearing_pressure(
    *,
    phi: ArrayLike,
    chi: ArrayLike,
    mu_bar: ArrayLike,
    G: ArrayLike,
    cavitated: bool = False,
) -> FloatArray:
    """Dimensionless pressure of an infinitely long bearing, steady load (3.15).

    .. math:: Π_∞ = \\frac{6χ\\bar μ}{2 + χ^2}\\frac{2 - χ\\cos φ}{(1 - χ\\cos φ)^2}(-G\\sin φ)

    Parameters
    ----------
    phi : array_like
        Angular coordinate φ, rad, from the widest gap of the film.
    chi : array_like
        Eccentricity ratio χ, in [0, 1).
    mu_bar : array_like
        Dimensionless mean viscosity μ̄ (> 0).
    G : array_like
        Dimensionless journal speed ω1/ω0.
    cavitated : bool, optional
        False (default): Sommerfeld's full (signed, antisymmetric) solution. True:
        negative pressures clipped to zero (Gümbel, half-Sommerfeld).

    Returns
    -------
    ndarray
        Π∞, broadcast over all arguments.

    Notes
    -----
    Same sign convention as (3.10): positive in φ ∈ (π, 2π) for G > 0, zero at φ = 0 and π,
    Π∞(2π - φ) = -Π∞(φ). It is Sommerfeld's solution with θ = φ - π (h = c(1 + ε cos θ)).
    Valid for a long bearing (no side leakage (3.13)).

    References
    ----------
    .. [1] Lab manual, lab work 3, (3.13)-(3.15).
    .. [2] A. Sommerfeld, "Zur hydrodynamischen Theorie der Schmiermittelreibung",
       Z. Math. Phys. 50 (1904) 97-155.
    """
    phi_ = finite("phi", phi)
    chi_ = _chi(chi)
    mu_ = positive("mu_bar", mu_bar)
    G_ = finite("G", G)
    cos_phi = np.cos(phi_)
    pressure = (
        6.0
        * chi_
        * mu_
        * (2.0 - chi_ * cos_phi)
        / ((2.0 + chi_**2) * (1.0 - chi_ * cos_phi) ** 2)
        * (-G_ * np.sin(phi_))
    )
    return _clip(np.asarray(pressure, dtype=np.float64), cavitated)


@dataclass(frozen=True, slots=True)
class ShortBearingIntegrals:
    """Integrals A_n^ij = ∫ sin^i φ cos^j φ / (1 - χ cos φ)^n dφ over φ ∈ (π, 2π) (4.5).

    All dimensionless.

    Attributes
    ----------
    a1_00 : ndarray
        A1^00 = π/√(1 - χ²).
    a2_00 : ndarray
        A2^00 = A1^00/(1 - χ²).
    a3_00 : ndarray
        A3^00 = (3A2^00 - A1^00)/(2(1 - χ²)).
    a3_02 : ndarray
        A3^02 (cos² weight), = (A1^00 - 2A2^00 + A3^00)/χ².
    a3_20 : ndarray
        A3^20 (sin² weight) = A3^00 - A3^02 = π/(2(1 - χ²)^1.5).
    a3_11 : ndarray
        A3^11 (sin·cos weight) = -2χ/(1 - χ²)² (listed in table 4.4, not printed in (4.5)).
    """

    a1_00: FloatArray
    a2_00: FloatArray
    a3_00: FloatArray
    a3_02: FloatArray
    a3_20: FloatArray
    a3_11: FloatArray


def short_bearing_integrals(*, chi: ArrayLike) -> ShortBearingIntegrals:
    """Integrals of the short-bearing method over the load zone φ_n = π .. 2π (4.5).

    Parameters
    ----------
    chi : array_like
        Eccentricity ratio χ, in [0, 1).

    Returns
    -------
    ShortBearingIntegrals
        A1^00, A2^00, A3^00, A3^02, A3^20, A3^11, broadcast over ``chi``.

    Notes
    -----
    A3^02 as printed in (4.5) is 0/0 at χ → 0 and loses digits for small χ. It is computed
    here as A3^00 - A3^20 with the closed form A3^20 = π/(2(1 - χ²)^1.5) (the sin²-weighted
    integral, exact), which is the same quantity and finite for every χ in [0, 1).
    A3^11 follows from the substitution u = 1 - χ cos φ.

    References
    ----------
    .. [1] Lab manual, lab work 4, (4.5) and table 4.4.
    """
    chi_ = _chi(chi)
    one_m = 1.0 - chi_**2
    a1 = np.pi / np.sqrt(one_m)
    a2 = a1 / one_m
    a3_00 = (3.0 * a2 - a1) / (2.0 * one_m)
    a3_20 = np.pi / (2.0 * one_m**1.5)
    return ShortBearingIntegrals(
        a1_00=a1,
        a2_00=a2,
        a3_00=a3_00,
        a3_02=a3_00 - a3_20,
        a3_20=a3_20,
        a3_11=-2.0 * chi_ / one_m**2,
    )


@dataclass(frozen=True, slots=True)
class _Geometry:
    chi: FloatArray
    omega: FloatArray
    viscosity: FloatArray
    radius: FloatArray
    width: FloatArray
    clearance: FloatArray

    @property
    def half_width(self) -> FloatArray:
        return self.width / (2.0 * self.radius)

    @property
    def psi(self) -> FloatArray:
        return self.clearance / self.radius


def _geometry(
    chi: ArrayLike,
    omega: ArrayLike,
    viscosity: ArrayLike,
    bearing_radius: ArrayLike,
    width: ArrayLike,
    clearance: ArrayLike,
) -> _Geometry:
    radius = positive("bearing_radius", bearing_radius)
    gap = positive("clearance", clearance)
    if np.any(gap >= radius):
        raise ModelInputError(
            f"clearance must be < bearing_radius ({np.max(radius)} m), got {np.max(gap)} m"
        )
    return _Geometry(
        chi=_chi(chi),
        omega=non_negative("omega", omega),
        viscosity=positive("viscosity", viscosity),
        radius=radius,
        width=positive("width", width),
        clearance=gap,
    )


@dataclass(frozen=True, slots=True)
class _Projections:
    force_scale: FloatArray  # P* at μ0 = μ, ω0 = ω
    tangential: FloatArray  # P_τ
    radial: FloatArray  # P_r


def _projections(g: _Geometry) -> _Projections:
    """P_τ = P*·V (4.2)-(4.4) and P_r likewise with A3^11, at μ̄ = G = 1."""
    integrals = short_bearing_integrals(chi=g.chi)
    a = g.half_width
    scale = 2.0 * g.width * g.radius * g.viscosity * g.omega / g.psi**2
    return _Projections(
        force_scale=scale,
        tangential=scale * (-g.chi * a**2 * integrals.a3_20),
        radial=scale * (-g.chi * a**2 * integrals.a3_11),
    )


@dataclass(frozen=True, slots=True)
class ShortBearingLoad:
    """Film force of a short bearing over the load zone (π-film).

    Attributes
    ----------
    tangential : ndarray
        P_τ = ∫∫ p sin φ dA = P*·V (4.2), N; negative for ω > 0. Its magnitude is Ocvirk's
        μωR·B³·πχ/(4h0²(1 - χ²)^1.5).
    radial : ndarray
        P_r = ∫∫ p cos φ dA along the line of centres, N; = μωR·B³χ²/(h0²(1 - χ²)²).
    resultant : ndarray
        |P| = √(P_τ² + P_r²), N: the load the film carries.
    attitude_angle : ndarray
        Angle between the line of centres and the load, rad;
        tan = π√(1 - χ²)/(4χ); π/2 at χ = 0.
    """

    tangential: FloatArray
    radial: FloatArray
    resultant: FloatArray
    attitude_angle: FloatArray


def short_bearing_load(
    *,
    chi: ArrayLike,
    omega: ArrayLike,
    viscosity: ArrayLike,
    bearing_radius: ArrayLike,
    width: ArrayLike,
    clearance: ArrayLike,
) -> ShortBearingLoad:
    """Film force of a short bearing, steady load (integral of (3.12); (4.2)-(4.4)).

    .. math:: P_τ = P^* V = -\\frac{μωR B^3}{4h_0^2}\\frac{πχ}{(1 - χ^2)^{3/2}},\\qquad
              P_r = \\frac{μωR B^3}{h_0^2}\\frac{χ^2}{(1 - χ^2)^2}

    Parameters
    ----------
    chi : array_like
        Eccentricity ratio χ, in [0, 1).
    omega : array_like
        Journal angular speed ω, rad/s (>= 0).
    viscosity : array_like
        Mean film viscosity μ, Pa·s (> 0).
    bearing_radius : array_like
        Bearing radius R, m (> clearance).
    width : array_like
        Bearing width B, m (> 0).
    clearance : array_like
        Radial clearance h0, m (> 0).

    Returns
    -------
    ShortBearingLoad
        Projections, resultant (N) and attitude angle (rad).

    Notes
    -----
    μ0 and ω0 cancel in P*·V. a = B/(2R) (correction E3): only this half-width makes P*·V
    equal the integral of (3.12) and Ocvirk's force. The short-bearing theory does not
    distinguish journal and bearing radii (h0 ≪ R); R is the bearing radius, as in (4.3).

    References
    ----------
    .. [1] Lab manual, (3.12), (4.2)-(4.5).
    .. [2] G. B. DuBois, F. W. Ocvirk, "Analytical derivation and experimental evaluation of
       short-bearing approximation for full journal bearings", NACA Report 1157, 1953.
    """
    g = _geometry(chi, omega, viscosity, bearing_radius, width, clearance)
    proj = _projections(g)
    return ShortBearingLoad(
        tangential=proj.tangential,
        radial=proj.radial,
        resultant=np.hypot(proj.tangential, proj.radial),
        attitude_angle=np.arctan2(-proj.tangential, proj.radial),
    )


@dataclass(frozen=True, slots=True)
class EccentricitySolution:
    """Eccentricity ratio at which the short-bearing film carries a given load.

    Attributes
    ----------
    chi : float
        Eccentricity ratio χ (dimensionless); the bracket top if not converged.
    converged : bool
        Whether the root was found within the bracket [0, 1 - 1e-12].
    iterations : int
        Solver iterations.
    message : str
        Solver status in words.
    """

    chi: float
    converged: bool
    iterations: int
    message: str


def short_bearing_eccentricity(
    *,
    load: float,
    omega: float,
    viscosity: float,
    bearing_radius: float,
    width: float,
    clearance: float,
) -> EccentricitySolution:
    """Eccentricity ratio χ whose short-bearing resultant force equals ``load``.

    Solves ``short_bearing_load(chi=χ, ...).resultant = load`` with Brent's method.

    Parameters
    ----------
    load : float
        Applied radial load, N (>= 0).
    omega : float
        Journal angular speed, rad/s (> 0).
    viscosity : float
        Mean film viscosity, Pa·s (> 0).
    bearing_radius, width, clearance : float
        R, B, h0 in m, as in :func:`short_bearing_load`.

    Returns
    -------
    EccentricitySolution
        χ and the solver status; not converged when the load exceeds the film force at
        χ = 1 - 1e-12 (the film cannot carry it).

    Notes
    -----
    The load balances the resultant (not the tangential projection alone): the resultant
    grows monotonically from 0 at χ = 0 to infinity at χ → 1, so the root is unique.
    """
    load_ = float(non_negative("load", load))
    omega_ = float(positive("omega", omega))

    def resultant(chi: float) -> float:
        return float(
            short_bearing_load(
                chi=chi,
                omega=omega_,
                viscosity=viscosity,
                bearing_radius=bearing_radius,
                width=width,
                clearance=clearance,
            ).resultant
        )

    if load_ == 0.0:
        return EccentricitySolution(chi=0.0, converged=True, iterations=0, message="zero load")
    top = resultant(CHI_BRACKET_TOP)
    if top < load_:
        return EccentricitySolution(
            chi=CHI_BRACKET_TOP,
            converged=False,
            iterations=0,
            message=f"load {load_} N exceeds the film force {top:.6g} N at chi = 1 - 1e-12",
        )
    root, info = brentq(
        lambda c: resultant(c) - load_,
        0.0,
        CHI_BRACKET_TOP,
        xtol=1e-14,
        rtol=4.0 * np.finfo(float).eps,
        full_output=True,
        disp=False,
    )
    return EccentricitySolution(
        chi=float(root),
        converged=bool(info.converged),
        iterations=int(info.iterations),
        message=str(info.flag),
    )


@dataclass(frozen=True, slots=True)
class FrictionMoment:
    """Theoretical friction moment of a journal bearing in fluid film (4.1)-(4.9).

    Attributes
    ----------
    moment : ndarray
        M_tr = pressure_term + shear_term, N·m.
    pressure_term : ndarray
        -½·P_τ·e, N·m.
    shear_term : ndarray
        ω·μ·R1³·2πB/√(h0² - e²), N·m (Petroff's moment at χ = 0).
    tangential_force : ndarray
        P_τ = P*·V (4.2), N (negative for ω > 0).
    force_scale : ndarray
        P* = 2BRμ0ω0/ψ² (4.3), N.
    v : ndarray
        V = -χa²μ̄A3^20·G (4.4), dimensionless.
    half_width : ndarray
        a = B/(2R), dimensionless (correction E3).
    """

    moment: FloatArray
    pressure_term: FloatArray
    shear_term: FloatArray
    tangential_force: FloatArray
    force_scale: FloatArray
    v: FloatArray
    half_width: FloatArray


def friction_moment_theoretical(
    *,
    chi: ArrayLike,
    omega: ArrayLike,
    viscosity: ArrayLike,
    bearing_radius: ArrayLike,
    width: ArrayLike,
    clearance: ArrayLike,
    reference_viscosity: ArrayLike | None = None,
    reference_omega: ArrayLike = 100.0,
) -> FrictionMoment:
    """Friction moment of a journal bearing by the short-bearing method (4.1)-(4.9).

    .. math:: M_{тр} = -\\tfrac12 P_τ e + ωμ_* R_1^3\\frac{2πB}{\\sqrt{h_0^2 - e^2}},\\quad
              P_τ = P^* V,\\ P^* = \\frac{2BRμ_0ω_0}{ψ^2},\\ V = -χa^2\\bar μ A_3^{20} G

    Parameters
    ----------
    chi : array_like
        Eccentricity ratio χ = e/h0 (measured), in [0, 1).
    omega : array_like
        Journal angular speed ω, rad/s (>= 0).
    viscosity : array_like
        Mean film viscosity μ_* = μ_t, Pa·s (> 0).
    bearing_radius : array_like
        Bearing radius R, m; the journal radius is R1 = R - h0.
    width : array_like
        Bearing width B, m.
    clearance : array_like
        Radial clearance h0, m (< R).
    reference_viscosity : array_like, optional
        μ0 of (4.3), Pa·s (the manual takes μ at 50 °C); defaults to ``viscosity`` (μ̄ = 1).
        Only P* and V depend on it.
    reference_omega : array_like, optional
        ω0 of (4.3), rad/s; the manual's 100 1/s. Only P* and V depend on it.

    Returns
    -------
    FrictionMoment
        Moment and its two terms (N·m), P_τ and P* (N), V and a.

    Notes
    -----
    a = B/(2R) (correction E3; the print of (4.8) and (4.20) has B/(4R) = B/(2D)).
    μ̄ = μ/μ0 and G = ω/ω0, so μ0 and ω0 cancel in P_τ = P*·V and in the moment. The shear
    term integrates the Couette stress over the full circumference, as the manual does.
    Valid for a short bearing in the fluid-film regime.

    References
    ----------
    .. [1] Lab manual, lab work 4, (4.1)-(4.9).
    """
    g = _geometry(chi, omega, viscosity, bearing_radius, width, clearance)
    mu0 = (
        g.viscosity
        if reference_viscosity is None
        else positive("reference_viscosity", reference_viscosity)
    )
    omega0 = positive("reference_omega", reference_omega)
    proj = _projections(g)
    journal_radius = g.radius - g.clearance
    eccentricity = g.chi * g.clearance
    pressure_term = -0.5 * proj.tangential * eccentricity
    shear_term = (
        g.omega
        * g.viscosity
        * journal_radius**3
        * 2.0
        * np.pi
        * g.width
        / (g.clearance * np.sqrt(1.0 - g.chi**2))
    )
    force_scale = 2.0 * g.width * g.radius * mu0 * omega0 / g.psi**2
    return FrictionMoment(
        moment=pressure_term + shear_term,
        pressure_term=pressure_term,
        shear_term=shear_term,
        tangential_force=proj.tangential,
        force_scale=force_scale,
        v=proj.tangential / force_scale,
        half_width=g.half_width,
    )


def friction_coefficient_theoretical(
    *,
    chi: ArrayLike,
    omega: ArrayLike,
    viscosity: ArrayLike,
    bearing_radius: ArrayLike,
    width: ArrayLike,
    clearance: ArrayLike,
    load: ArrayLike,
) -> FloatArray:
    """Theoretical friction coefficient of a journal bearing (4.10).

    .. math:: f_T = \\frac{M_{тр}}{F R_1}

    Parameters
    ----------
    chi, omega, viscosity, bearing_radius, width, clearance : array_like
        As in :func:`friction_moment_theoretical`.
    load : array_like
        F of (4.10): the external load on the bearing, N (> 0); on the MTOS stand the
        dynamometer load N (not the spring force F = kΔl of (4.13), not the computed
        film force).

    Returns
    -------
    ndarray
        f_T, dimensionless.

    Notes
    -----
    The manual computes f_T with the measured χ and μ_t/μ0 at each load N_i (lab 4,
    processing item 6), so F is the applied load.

    References
    ----------
    .. [1] Lab manual, lab work 4, (4.10).
    """
    load_ = positive("load", load)
    result = friction_moment_theoretical(
        chi=chi,
        omega=omega,
        viscosity=viscosity,
        bearing_radius=bearing_radius,
        width=width,
        clearance=clearance,
    )
    journal_radius = positive("bearing_radius", bearing_radius) - finite("clearance", clearance)
    return np.asarray(result.moment / (load_ * journal_radius), dtype=np.float64)


#: Pressure below this share of the load zone's peak counts as the ruptured film.
RUPTURE_SHARE = 1e-3


def rupture_angle_deg(
    *, pressure: Callable[[FloatArray], FloatArray], step_deg: float = 0.1
) -> float:
    """φ_r: how far past the thinnest film (φ = 2π ≡ 0) the film keeps its pressure, degrees.

    The first angle φ >= 0 (model frame, thinnest film at φ = 0 as in (3.11)) where the
    pressure falls to :data:`RUPTURE_SHARE` of its peak over the load zone π..2π. Zero for
    the asymptotes (3.10) and (3.15), whose load zone ends at the thinnest film; a few
    degrees up to ~20° for the finite film with the Reynolds condition.

    Parameters
    ----------
    pressure : callable
        p(φ) along the meridional plane (any unit), φ in rad of the model frame.
    step_deg : float
        Resolution of the search, degrees (> 0).

    Returns
    -------
    float
        φ_r in [0, 90) degrees, a multiple of ``step_deg``; 0 when no rupture is found there.
    """
    step = float(positive("step_deg", step_deg))
    phi = np.radians(np.arange(0.0, 90.0, step))
    peak = float(np.max(pressure(np.radians(np.arange(180.0, 360.0, step / 2.0)))))
    low = np.flatnonzero(pressure(phi) <= RUPTURE_SHARE * peak)
    return float(np.degrees(phi[low[0]])) if low.size else 0.0
