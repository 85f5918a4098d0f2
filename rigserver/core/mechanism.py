"""Dynamic errors of the programmed motion of a lever mechanism, seed 000 (1)-(6).

A stationary mechanism with n degrees of freedom follows a programmed motion q(t); the
elasticity left out of the programme lets the actual coordinates be p = q + ξ, and the
dynamic errors ξ(t) obey linear equations with time-varying coefficients built from the
kinetic-energy matrix A(q) of (1), the stiffness c and damping b of (4).

Derivation (checks the corrected forms E7, E8 of ``docs/models.md``)
-----------------------------------------------------------------------
With T = ½ ṗᵀA(p)ṗ (1), π = ½ ξᵀcξ and Φ = ½ ξ̇ᵀbξ̇ (4), and q(t) given, Lagrange's
equations for ξ are those of the links in p, loaded by the elastic drives:

    Σ_m A_km(p) p̈_m + Σ_m,l θ_kml(p) ṗ_m ṗ_l + (cξ)_k + (bξ̇)_k = 0,
    θ_kml = λ_klm - λ_mkl/2,   λ_klm = ∂A_km/∂q_l.

Expanding about p = q to first order in ξ:

- order zero gives the right side of (6), -A q̈ - θ q̇q̇: the inertial load of the
  programme that deflects the elastic drives;
- A(p)p̈ gives A ξ̈ + Σ λ_klm q̈_m ξ_l;
- ṗ_m ṗ_l gives Σ (θ_kml + θ_klm) q̇_m ξ̇_l = Σ γ_mlk q̇_m ξ̇_l with
  γ_mlk = λ_kml + λ_klm - λ_lkm (the left side of the second definition in (5) is γ, E7,
  and the term multiplies the velocity ξ̇_l, E8);
- θ(p) gives Σ ∂θ_kms/∂q_l q̇_m q̇_s ξ_l = Σ μ_kmsl q̇_m q̇_s ξ_l, with μ as defined in
  (5): μ_kmls = ∂²A_km/∂q_l∂q_s - ½ ∂²A_ml/∂q_k∂q_s = ∂θ_kml/∂q_s.

So the equations solved here are

    A ξ̈ + (G + b) ξ̇ + (K + c) ξ + R(ξ, ξ̇, t) = f,
    G_kl = Σ_m γ_mlk q̇_m,  K_kl = Σ_m λ_klm q̈_m + Σ_m,s μ_kmsl q̇_m q̇_s,
    f_k = -Σ_m A_km q̈_m - Σ_m,l θ_kml q̇_m q̇_l,

R being optional nonlinear restoring forces (e.g. the ball-screw moments (14)-(18)). The
index order of μ in the ξ term is μ_kmsl (differentiating index last, paired with ξ_l);
the print of (6) has μ_klms, which is a different tensor (see :func:`error_equation_coefficients`).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

from rigserver.core._checks import finite, one_of, positive, within
from rigserver.core.errors import ModelInputError, ModelUndefinedError

FloatArray = NDArray[np.float64]
#: ``inertia_matrix(q)``: the kinetic-energy matrix A (n x n) of (1) at coordinates q.
InertiaMatrix = Callable[[FloatArray], ArrayLike]
#: ``program(t)``: the programmed (q, q', q'') at time t, each of length n.
Program = Callable[[float], tuple[ArrayLike, ArrayLike, ArrayLike]]
#: ``restoring(xi, xi_dot, t)``: generalised restoring forces, added to c·ξ on the left.
Restoring = Callable[[FloatArray, FloatArray, float], ArrayLike]

#: Integrators of :func:`scipy.integrate.solve_ivp` that use a Jacobian (stiff problems).
IMPLICIT_METHODS = ("Radau", "BDF", "LSODA")
#: Explicit Runge-Kutta integrators of :func:`scipy.integrate.solve_ivp`.
EXPLICIT_METHODS = ("RK45", "RK23", "DOP853")
#: Relative tolerance of the check of closed-form ∂A/∂q against central differences.
FIRST_DERIVATIVE_CHECK_RTOL = 1e-5
#: Relative tolerance of the check of closed-form ∂²A/∂q∂q against central differences.
SECOND_DERIVATIVE_CHECK_RTOL = 1e-4

#: Fraction of a segment between breakpoints by which the programme is read inside it.
SEGMENT_INSET = 1e-10

_EPS = float(np.finfo(np.float64).eps)
_Fun = Callable[[float, FloatArray], FloatArray]


@dataclass(frozen=True, slots=True)
class InertiaDerivatives:
    """First and second derivatives of the kinetic-energy matrix A(q).

    Attributes
    ----------
    first : ndarray, shape (n, n, n)
        ``first[k, m, l]`` = ∂A_km/∂q_l, i.e. λ_klm of (5); units of A per unit of q.
    second : ndarray, shape (n, n, n, n)
        ``second[k, m, l, s]`` = ∂²A_km/∂q_l∂q_s.
    """

    first: FloatArray
    second: FloatArray


#: ``derivative(q)``: closed-form :class:`InertiaDerivatives` of A at q.
Derivative = Callable[[FloatArray], InertiaDerivatives]


@dataclass(frozen=True, slots=True)
class ErrorEquationCoefficients:
    """The coefficients (5) and the assembled terms of the error equations (6) at one instant.

    Attributes
    ----------
    A : ndarray, shape (n, n)
        Kinetic-energy matrix A_km(q) of (1) (kg·m² for angles).
    lam : ndarray, shape (n, n, n)
        ``lam[k, l, m]`` = λ_klm = ∂A_km/∂q_l (5).
    gamma : ndarray, shape (n, n, n)
        ``gamma[m, l, k]`` = γ_mlk = λ_kml + λ_klm - λ_lkm (5), corrected E7.
    theta : ndarray, shape (n, n, n)
        ``theta[k, m, l]`` = θ_kml = λ_klm - λ_mkl/2 (5).
    mu : ndarray, shape (n, n, n, n)
        ``mu[k, m, l, s]`` = μ_kmls = ∂²A_km/∂q_l∂q_s - ½ ∂²A_ml/∂q_k∂q_s (5).
    velocity : ndarray, shape (n, n)
        G_kl = Σ_m γ_mlk q̇_m, the coefficient of ξ̇_l in row k (without damping), E8.
    position : ndarray, shape (n, n)
        K_kl = Σ_m λ_klm q̈_m + Σ_m,s μ_kmsl q̇_m q̇_s, the coefficient of ξ_l (without
        stiffness).
    load : ndarray, shape (n,)
        f_k = -Σ_m A_km q̈_m - Σ_m,l θ_kml q̇_m q̇_l, the inertial load of the programme
        (N·m for angles).
    """

    A: FloatArray
    lam: FloatArray
    gamma: FloatArray
    theta: FloatArray
    mu: FloatArray
    velocity: FloatArray
    position: FloatArray
    load: FloatArray


@dataclass(frozen=True, slots=True)
class ProgrammedMotion:
    """A programmed motion q(t) with its derivatives, callable as ``program(t)``.

    Attributes
    ----------
    evaluate : callable
        ``evaluate(t)`` returns (q, q', q'') at time t (s), each an array of length n.
    breakpoints : tuple of float
        Times (s) where q'' (or a higher derivative) jumps; :func:`dynamic_errors` restarts
        the integration there.
    domain : tuple of float
        Times (s) where the motion is defined; outside it the call raises.
    """

    evaluate: Callable[[float], tuple[FloatArray, FloatArray, FloatArray]]
    breakpoints: tuple[float, ...] = ()
    domain: tuple[float, float] = (-math.inf, math.inf)

    def __call__(self, t: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Return (q, q', q'') at time ``t`` (s)."""
        low, high = self.domain
        slack = 1e-12 * max(1.0, abs(low), abs(high)) if math.isfinite(high - low) else 0.0
        if not low - slack <= t <= high + slack:
            raise ModelInputError(
                f"t must lie in [{low}, {high}] (the programme's time range), got {t}"
            )
        return self.evaluate(t)


@dataclass(frozen=True, slots=True)
class DynamicErrors:
    """Dynamic errors of a programmed motion, the solution of (6).

    Attributes
    ----------
    t : ndarray, shape (N,)
        Output times, s (those of ``t_eval`` reached; all of them when ``success``).
    xi : ndarray, shape (n, N)
        Dynamic errors ξ(t), in the units of each coordinate q (rad for joint angles).
    xi_dot : ndarray, shape (n, N)
        Their rates ξ'(t), units of q per second.
    max_abs : ndarray, shape (n,)
        The largest |ξ_k| over ``t``, units of q.
    success : bool
        Whether the integrator reached the last time of ``t_eval``.
    message : str
        The integrator's report (where it stopped, if it failed).
    nfev : int
        Evaluations of the right-hand side.
    """

    t: FloatArray
    xi: FloatArray
    xi_dot: FloatArray
    max_abs: FloatArray
    success: bool
    message: str
    nfev: int


def _steps(q: FloatArray, power: float) -> FloatArray:
    """Central-difference steps eps^power scaled to |q|, exactly representable about q."""
    h: FloatArray = _EPS**power * np.maximum(1.0, np.abs(q))
    return (q + h) - q


def _matrix(inertia_matrix: InertiaMatrix, q: FloatArray) -> FloatArray:
    return np.asarray(inertia_matrix(q), dtype=np.float64)


def numerical_inertia_derivatives(
    inertia_matrix: InertiaMatrix, *, q: ArrayLike
) -> InertiaDerivatives:
    """First and second derivatives of A(q) by central differences.

    .. math:: \\frac{∂A}{∂q_l} ≈ \\frac{A(q + h_l e_l) - A(q - h_l e_l)}{2h_l},\\quad
              \\frac{∂^2A}{∂q_l∂q_s} ≈ \\frac{A(q^{++}) - A(q^{+-}) - A(q^{-+}) + A(q^{--})}
              {4h_l h_s}

    Parameters
    ----------
    inertia_matrix : callable
        ``inertia_matrix(q)`` returns the kinetic-energy matrix A (n x n) of (1).
    q : array_like, shape (n,)
        Generalised coordinates (rad for angles).

    Returns
    -------
    InertiaDerivatives
        ``first[k, m, l]`` = ∂A_km/∂q_l, ``second[k, m, l, s]`` = ∂²A_km/∂q_l∂q_s.

    Notes
    -----
    Steps h = ε^(1/3)·max(1, |q_l|) for the first derivatives and ε^(1/4)·max(1, |q_l|)
    for the second (ε the machine epsilon), which balance truncation and rounding for
    coordinates of order one (radians); the results are accurate to about 1e-10 and 1e-7
    of |A| respectively. Costs 2n + 2n + 2n(n - 1) + 1 evaluations of A.
    """
    q0 = finite("q", q).reshape(-1)
    n = q0.size
    a0 = _matrix(inertia_matrix, q0)
    h1 = _steps(q0, 1.0 / 3.0)
    h2 = _steps(q0, 1.0 / 4.0)
    first = np.empty((n, n, n))
    second = np.empty((n, n, n, n))
    eye = np.eye(n)
    for l in range(n):  # noqa: E741 (the article's index)
        up = _matrix(inertia_matrix, q0 + h1[l] * eye[l])
        down = _matrix(inertia_matrix, q0 - h1[l] * eye[l])
        first[:, :, l] = (up - down) / (2.0 * h1[l])
        up2 = _matrix(inertia_matrix, q0 + h2[l] * eye[l])
        down2 = _matrix(inertia_matrix, q0 - h2[l] * eye[l])
        second[:, :, l, l] = (up2 - 2.0 * a0 + down2) / h2[l] ** 2
        for s in range(l):
            dl, ds = h2[l] * eye[l], h2[s] * eye[s]
            mixed = (
                _matrix(inertia_matrix, q0 + dl + ds)
                - _matrix(inertia_matrix, q0 + dl - ds)
                - _matrix(inertia_matrix, q0 - dl + ds)
                + _matrix(inertia_matrix, q0 - dl - ds)
            ) / (4.0 * h2[l] * h2[s])
            second[:, :, l, s] = mixed
            second[:, :, s, l] = mixed
    return InertiaDerivatives(first=first, second=second)


def _derivatives(
    inertia_matrix: InertiaMatrix, q: FloatArray, derivative: str | Derivative
) -> InertiaDerivatives:
    if isinstance(derivative, str):
        return numerical_inertia_derivatives(inertia_matrix, q=q)
    return derivative(q)


def _assemble(
    A: FloatArray,
    d: InertiaDerivatives,
    q_dot: FloatArray,
    q_ddot: FloatArray,
) -> ErrorEquationCoefficients:
    lam = d.first.transpose(0, 2, 1)  # lam[k, l, m] = λ_klm = ∂A_km/∂q_l
    # γ_mlk = λ_kml + λ_klm - λ_lkm, stored as gamma[m, l, k] (5), E7
    gamma = lam.transpose(1, 2, 0) + lam.transpose(2, 1, 0) - lam.transpose(2, 0, 1)
    theta = lam.transpose(0, 2, 1) - 0.5 * lam.transpose(1, 0, 2)  # θ_kml = λ_klm - λ_mkl/2
    mu = d.second - 0.5 * d.second.transpose(2, 0, 1, 3)  # μ_kmls (5)
    velocity = gamma.transpose(2, 1, 0) @ q_dot  # [k, l] = Σ_m γ_mlk q̇_m
    # [k, l] = Σ_m λ_klm q̈_m + Σ_m,s μ_kmsl q̇_m q̇_s
    position = lam @ q_ddot + (mu.transpose(0, 3, 1, 2) @ q_dot) @ q_dot
    load = -A @ q_ddot - (theta @ q_dot) @ q_dot  # -Σ A_km q̈_m - Σ θ_kml q̇_m q̇_l
    return ErrorEquationCoefficients(
        A=A,
        lam=lam,
        gamma=gamma,
        theta=theta,
        mu=mu,
        velocity=velocity,
        position=position,
        load=load,
    )


def _derivative_option(derivative: str | Derivative) -> str | Derivative:
    if isinstance(derivative, str):
        one_of("derivative", derivative, ("numerical",))
    elif not callable(derivative):
        raise ModelInputError(
            f"derivative must be 'numerical' or a callable q -> InertiaDerivatives, "
            f"got {derivative!r}"
        )
    return derivative


def error_equation_coefficients(
    inertia_matrix: InertiaMatrix,
    *,
    q: ArrayLike,
    q_dot: ArrayLike,
    q_ddot: ArrayLike,
    derivative: str | Derivative = "numerical",
) -> ErrorEquationCoefficients:
    """Coefficients λ, γ, θ, μ (5) and the terms of the error equations (6) at one instant.

    .. math:: λ_{klm} = \\frac{∂A_{km}}{∂q_l},\\;
              γ_{mlk} = λ_{kml} + λ_{klm} - λ_{lkm},\\;
              θ_{kml} = λ_{klm} - \\tfrac12 λ_{mkl},\\;
              μ_{kmls} = \\frac{∂^2 A_{km}}{∂q_l∂q_s} - \\frac12\\frac{∂^2 A_{ml}}{∂q_k∂q_s}

    Parameters
    ----------
    inertia_matrix : callable
        ``inertia_matrix(q)`` returns A (n x n) of (1).
    q, q_dot, q_ddot : array_like, shape (n,)
        The programmed coordinates (rad), velocities (rad/s) and accelerations (rad/s²).
    derivative : 'numerical' or callable, optional
        'numerical' (default): central differences of ``inertia_matrix``
        (:func:`numerical_inertia_derivatives`); or ``derivative(q)`` returning the
        closed-form :class:`InertiaDerivatives`.

    Returns
    -------
    ErrorEquationCoefficients
        λ, γ, θ, μ and the assembled velocity and position matrices and the load of (6).

    Notes
    -----
    Correction E7: the second definition of (5) defines γ_mlk (the print has λ_mlk on its
    left). Correction E8: the γ term multiplies ξ̇_l. The ξ term uses μ_kmsl q̇_m q̇_s ξ_l,
    i.e. ∂θ_kms/∂q_l (module docstring); the print of (6) has μ_klms there, which differs
    from the Lagrange linearisation unless A is constant.

    References
    ----------
    .. [1] V. B. Zelenskii et al., "Estimation of dynamic errors of a lever mechanism",
       NTU KhPI (2011), seed 000, (1)-(6).
    """
    deriv = _derivative_option(derivative)
    q_ = finite("q", q).reshape(-1)
    qd = finite("q_dot", q_dot).reshape(-1)
    qdd = finite("q_ddot", q_ddot).reshape(-1)
    A = _checked_inertia(inertia_matrix, q_, where="")
    n = A.shape[0]
    for name, arr in (("q", q_), ("q_dot", qd), ("q_ddot", qdd)):
        if arr.size != n:
            raise ModelInputError(f"{name} must have length {n} (the size of A), got {arr.size}")
    return _assemble(A, _derivatives(inertia_matrix, q_, deriv), qd, qdd)


def _checked_inertia(inertia_matrix: InertiaMatrix, q: FloatArray, *, where: str) -> FloatArray:
    """A(q), refused unless square, finite, symmetric and positive definite."""
    A = _matrix(inertia_matrix, q)
    n = q.size
    if A.shape != (n, n):
        raise ModelInputError(f"inertia_matrix must return an {n} x {n} array, got {A.shape}")
    finite("inertia_matrix", A)
    scale = float(np.max(np.abs(A)))
    asym = float(np.max(np.abs(A - A.T)))
    if asym > 1e-10 * scale:
        raise ModelInputError(
            f"inertia_matrix must be symmetric, got |A - Aᵀ| = {asym:.3g}{where} at q = {q}"
        )
    if float(np.min(np.linalg.eigvalsh(A))) <= 1e-14 * scale:
        raise ModelUndefinedError(
            f"inertia_matrix must be positive definite, got eigenvalues "
            f"{np.linalg.eigvalsh(A)}{where} at q = {q}"
        )
    return A


def _symmetric_psd(name: str, value: ArrayLike, n: int) -> FloatArray:
    arr = finite(name, value)
    if arr.shape != (n, n):
        raise ModelInputError(f"{name} must be an {n} x {n} array, got shape {arr.shape}")
    scale = max(float(np.max(np.abs(arr))), 1e-300)
    if float(np.max(np.abs(arr - arr.T))) > 1e-12 * scale:
        raise ModelInputError(f"{name} must be symmetric ({name}_jk = {name}_kj of (4))")
    smallest = float(np.min(np.linalg.eigvalsh(arr)))
    if smallest < -1e-12 * scale:
        raise ModelInputError(
            f"{name} must be positive semi-definite (a non-negative form (4)), "
            f"got smallest eigenvalue {smallest:.6g}"
        )
    return arr


def _program_at(program: Program, t: float, n: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    out = [np.asarray(v, dtype=np.float64).reshape(-1) for v in program(t)]
    for name, arr in zip(("q", "q'", "q''"), out, strict=True):
        if arr.size != n:
            raise ModelInputError(f"program(t) must return {name} of length {n}, got {arr.size}")
    if not np.isfinite(np.concatenate(out)).all():
        raise ModelInputError(f"program(t) must return finite values, got {out} at t = {t} s")
    return out[0], out[1], out[2]


def _check_closed_form(
    inertia_matrix: InertiaMatrix, derivative: Derivative, q: FloatArray, t: float
) -> None:
    """Refuse a closed-form derivative that disagrees with central differences of A."""
    closed = derivative(q)
    numeric = numerical_inertia_derivatives(inertia_matrix, q=q)
    scale_a = float(np.max(np.abs(_matrix(inertia_matrix, q))))
    for label, given, m, rtol in (
        ("∂A/∂q", closed.first, numeric.first, FIRST_DERIVATIVE_CHECK_RTOL),
        ("∂²A/∂q²", closed.second, numeric.second, SECOND_DERIVATIVE_CHECK_RTOL),
    ):
        d = np.asarray(given, dtype=np.float64)
        if d.shape != m.shape:
            raise ModelInputError(
                f"derivative must return {label} of shape {m.shape}, got {d.shape}"
            )
        gap = float(np.max(np.abs(d - m)))
        limit = rtol * max(scale_a, float(np.max(np.abs(m))))
        if not gap <= limit:
            raise ModelInputError(
                f"derivative: {label} disagrees with central differences of inertia_matrix "
                f"at t = {t} s (q = {q}): max difference {gap:.3g} > {limit:.3g}"
            )


def dynamic_errors(
    inertia_matrix: InertiaMatrix,
    stiffness: ArrayLike,
    damping: ArrayLike,
    program: Program,
    t_eval: ArrayLike,
    restoring: Restoring | None = None,
    *,
    method: str = "LSODA",
    rtol: float = 1e-6,
    atol: float = 1e-12,
    derivative: str | Derivative = "numerical",
    xi0: ArrayLike | None = None,
    xi_dot0: ArrayLike | None = None,
) -> DynamicErrors:
    """Dynamic errors ξ(t) of a programmed motion q(t): the linear equations (6).

    .. math:: Σ_m A_{km}\\ddot ξ_m + Σ_{l,m}(γ_{mlk}\\dot q_m + δ_{lm}b_{lk})\\dot ξ_l
              + Σ_{l}\\Big(Σ_m λ_{klm}\\ddot q_m + Σ_{m,s} μ_{kmsl}\\dot q_m\\dot q_s
              + c_{lk}\\Big)ξ_l + R_k = -Σ_m A_{km}\\ddot q_m - Σ_{m,l}θ_{kml}\\dot q_m\\dot q_l

    Parameters
    ----------
    inertia_matrix : callable
        ``inertia_matrix(q)`` returns the kinetic-energy matrix A (n x n) of (1),
        symmetric positive definite (kg·m² for angles, kg for lengths).
    stiffness : array_like, shape (n, n)
        Generalised stiffness c_jk of (4), symmetric positive semi-definite (N·m/rad).
    damping : array_like, shape (n, n)
        Damping b_jk of (4), symmetric positive semi-definite (N·m·s/rad).
    program : callable
        ``program(t)`` returns (q, q', q'') of the programmed motion, each of length n
        (rad, rad/s, rad/s²); e.g. :func:`point_to_point` or :func:`program_from_samples`.
        A :class:`ProgrammedMotion` also declares its breakpoints and time range.
    t_eval : array_like
        Output times, s, strictly increasing (at least two); integration starts at the
        first.
    restoring : callable, optional
        ``restoring(xi, xi_dot, t)`` returns generalised restoring forces R (length n,
        N·m for angles), added to c·ξ on the left side, i.e. R opposes ξ when R·ξ > 0;
        e.g. the ball-screw moments (14) of :mod:`rigserver.core.arm`.
    method : str, optional
        solve_ivp integrator: 'LSODA' (default; Adams or BDF, switched by stiffness),
        'Radau', 'BDF' (stiff; all three get the exact Jacobian of the linear part) or
        'RK45', 'RK23', 'DOP853'.
    rtol, atol : float, optional
        Integrator tolerances; ``atol`` in the units of ξ (default 1e-12 rad).
    derivative : 'numerical' or callable, optional
        How λ and μ are obtained from A: 'numerical' (central differences, default) or
        ``derivative(q)`` returning closed-form :class:`InertiaDerivatives`, which is
        first checked against central differences at the start, middle and end.
    xi0, xi_dot0 : array_like, optional
        Initial ξ and ξ' at ``t_eval[0]`` (default zero: the drives start undeformed).

    Returns
    -------
    DynamicErrors
        ``t``, ``xi`` and ``xi_dot`` (n x len(t)), ``max_abs`` (n), and the integrator's
        ``success``, ``message`` and ``nfev``. Non-convergence is reported, not raised.

    Raises
    ------
    ModelInputError
        Bad shapes, non-finite values, asymmetric or indefinite c or b, an asymmetric A,
        ``t_eval`` outside the programme's range, a closed-form derivative that disagrees
        with central differences.
    ModelUndefinedError
        A(q) not positive definite at an output time, or singular during the integration.

    Notes
    -----
    Valid while ξ is small: the neglected terms are of second order in ξ, ξ' (the
    linearisation of Lagrange's equations about q(t), module docstring). Corrections E7
    (γ on the left of (5)) and E8 (γ q̇ multiplies ξ̇) are applied; the μ term uses
    μ_kmsl (see :func:`error_equation_coefficients`). A(q) is checked to be symmetric
    positive definite at every output time. The coefficients are evaluated once per
    time and cached, so Newton iterations of the implicit methods are cheap.

    Integrator: the errors are vibrations of the elastic drives that the output has to
    resolve, so the problem is rarely stiff at the accuracy asked for; LSODA then runs
    high-order Adams steps and needs several times fewer evaluations than Radau (an
    order-5 method), and it turns to BDF by itself when heavy damping makes it stiff.

    References
    ----------
    .. [1] V. B. Zelenskii et al., "Estimation of dynamic errors of a lever mechanism",
       NTU KhPI (2011), seed 000, (1)-(6).
    .. [2] L. Petzold, "Automatic selection of methods for solving stiff and nonstiff
       systems of ordinary differential equations", SIAM J. Sci. Stat. Comput. 4 (1983)
       (LSODA); E. Hairer, G. Wanner, Solving Ordinary Differential Equations II, 1996
       (Radau IIA).
    """
    one_of("method", method, IMPLICIT_METHODS + EXPLICIT_METHODS)
    positive("rtol", rtol)
    positive("atol", atol)
    deriv = _derivative_option(derivative)
    times = finite("t_eval", t_eval).reshape(-1)
    if times.size < 2:
        raise ModelInputError(f"t_eval must hold at least 2 times, got {times.size}")
    if np.any(np.diff(times) <= 0):
        raise ModelInputError("t_eval must be strictly increasing")
    t0, t_end = float(times[0]), float(times[-1])
    breakpoints: tuple[float, ...] = ()
    if isinstance(program, ProgrammedMotion):
        low, high = program.domain
        within("t_eval", times, low, high)
        breakpoints = tuple(sorted({b for b in program.breakpoints if t0 < b < t_end}))

    q_start = np.asarray(program(t0)[0], dtype=np.float64).reshape(-1)
    n = q_start.size
    for t_i in times:
        q_t = _program_at(program, float(t_i), n)[0]
        _checked_inertia(inertia_matrix, q_t, where=f" at t = {t_i} s")
    c = _symmetric_psd("stiffness", stiffness, n)
    b = _symmetric_psd("damping", damping, n)
    if not isinstance(deriv, str):
        for t_check in (t0, 0.5 * (t0 + t_end), t_end):
            q_check = _program_at(program, t_check, n)[0]
            _check_closed_form(inertia_matrix, deriv, q_check, t_check)
    y0 = np.concatenate(
        [
            np.zeros(n) if xi0 is None else _vector("xi0", xi0, n),
            np.zeros(n) if xi_dot0 is None else _vector("xi_dot0", xi_dot0, n),
        ]
    )
    if restoring is not None:
        _vector("restoring(xi, xi_dot, t)", restoring(y0[:n], y0[n:], t0), n)

    @lru_cache(maxsize=64)
    def terms(t: float) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        q, qd, qdd = _program_at(program, t, n)
        A = _matrix(inertia_matrix, q)
        co = _assemble(A, _derivatives(inertia_matrix, q, deriv), qd, qdd)
        rhs_columns = np.column_stack([co.load, co.velocity + b, co.position + c])
        solved = np.asarray(np.linalg.solve(A, rhs_columns), dtype=np.float64)
        return A, solved[:, 0], solved[:, 1 : n + 1], solved[:, n + 1 :]

    def segment(start: float, stop: float) -> tuple[_Fun, _Fun]:
        # The programme is read a hair inside the segment, so that at a breakpoint q''
        # takes the one-sided value of this segment.
        inset = SEGMENT_INSET * (stop - start)
        low, high = start + inset, stop - inset

        def rhs(t: float, y: FloatArray) -> FloatArray:
            A, load, vel, pos = terms(min(max(float(t), low), high))
            xi, xd = y[:n], y[n:]
            acc = load - vel @ xd - pos @ xi
            if restoring is not None:
                force = np.asarray(restoring(xi, xd, float(t)), dtype=np.float64)
                acc = acc - np.linalg.solve(A, force)
            return np.concatenate([xd, acc])

        def jac(t: float, y: FloatArray) -> FloatArray:
            _, _, vel, pos = terms(min(max(float(t), low), high))
            return np.block([[np.zeros((n, n)), np.eye(n)], [-pos, -vel]])

        return rhs, jac

    options: dict[str, object] = {"method": method, "rtol": rtol, "atol": atol}
    use_jac = method in IMPLICIT_METHODS and restoring is None
    t_all, y_all, success, message, nfev = _integrate(
        segment, [t0, *breakpoints, t_end], times, y0, options, use_jac
    )
    xi_all = y_all[:n]
    return DynamicErrors(
        t=t_all,
        xi=xi_all,
        xi_dot=y_all[n:],
        max_abs=np.max(np.abs(xi_all), axis=1) if t_all.size else np.zeros(n),
        success=success,
        message=message,
        nfev=nfev,
    )


def _integrate(
    segment: Callable[[float, float], tuple[_Fun, _Fun]],
    edges: list[float],
    times: FloatArray,
    y0: FloatArray,
    options: dict[str, object],
    use_jac: bool,
) -> tuple[FloatArray, FloatArray, bool, str, int]:
    """solve_ivp from breakpoint to breakpoint; (t, y, success, message, nfev) at ``times``."""
    t_out: list[FloatArray] = []
    y_out: list[FloatArray] = []
    nfev = 0
    y = y0
    for i, (start, stop) in enumerate(itertools.pairwise(edges)):
        wanted = times[((times >= start) if i == 0 else (times > start)) & (times <= stop)]
        rhs, jac = segment(start, stop)
        try:
            sol = solve_ivp(
                rhs,
                (start, stop),
                y,
                t_eval=np.union1d(wanted, [start, stop] if i == 0 else [stop]),
                **(options | {"jac": jac} if use_jac else options),
            )
        except np.linalg.LinAlgError as exc:
            raise ModelUndefinedError(
                f"inertia_matrix is singular between t = {start} s and t = {stop} s"
            ) from exc
        nfev += int(sol.nfev)
        keep = np.isin(sol.t, wanted)
        t_out.append(sol.t[keep])
        y_out.append(sol.y[:, keep])
        if not sol.success:
            message = f"stopped in [{start}, {stop}] s: {sol.message}"
            return np.concatenate(t_out), np.concatenate(y_out, axis=1), False, message, nfev
        y = sol.y[:, -1]
    return np.concatenate(t_out), np.concatenate(y_out, axis=1), True, str(sol.message), nfev


def _vector(name: str, value: ArrayLike, n: int) -> FloatArray:
    arr = finite(name, value).reshape(-1)
    if arr.size != n:
        raise ModelInputError(f"{name} must have length {n}, got {arr.size}")
    return arr


def _trapezoid(tau: float, ramp: float) -> tuple[float, float, float]:
    """Normalised trapezoidal-velocity move s(τ), s', s'' on τ ∈ [0, 1]."""
    v = 1.0 / (1.0 - ramp)
    a = v / ramp
    if tau < ramp:
        return 0.5 * a * tau**2, a * tau, a
    if tau <= 1.0 - ramp:
        return 0.5 * a * ramp**2 + v * (tau - ramp), v, 0.0
    rest = 1.0 - tau
    return 1.0 - 0.5 * a * rest**2, a * rest, -a


def _quintic(tau: float) -> tuple[float, float, float]:
    """Normalised minimum-jerk move s = 10τ³ - 15τ⁴ + 6τ⁵ and its derivatives."""
    return (
        tau**3 * (10.0 - 15.0 * tau + 6.0 * tau**2),
        30.0 * tau**2 * (1.0 - tau) ** 2,
        60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau),
    )


def point_to_point(
    *,
    q_start: ArrayLike,
    q_end: ArrayLike,
    duration: float,
    profile: str = "trapezoidal",
    t_start: float = 0.0,
    accel_fraction: float = 0.25,
) -> ProgrammedMotion:
    """A synchronous point-to-point move of every joint, at rest before and after.

    .. math:: q(t) = q_0 + (q_1 - q_0)\\,s\\!\\left(\\frac{t - t_0}{T}\\right)

    Parameters
    ----------
    q_start, q_end : array_like, shape (n,)
        Start and end coordinates (rad).
    duration : float
        Move time T, s (> 0).
    profile : {'trapezoidal', 'quintic'}, optional
        'trapezoidal' (default): constant acceleration for ``accel_fraction``·T, constant
        velocity, constant deceleration (q'' jumps at four breakpoints). 'quintic':
        s = 10τ³ - 15τ⁴ + 6τ⁵, q'' continuous and zero at both ends.
    t_start : float, optional
        Start time t_0 of the move, s (default 0).
    accel_fraction : float, optional
        Acceleration (and deceleration) time as a fraction of T, in (0, 0.5]
        (default 0.25; 0.5 is the triangular profile). Used by 'trapezoidal' only.

    Returns
    -------
    ProgrammedMotion
        ``program(t)`` returning (q, q', q''), with the breakpoints where q'' or q''' jumps.
    """
    one_of("profile", profile, ("trapezoidal", "quintic"))
    q0 = finite("q_start", q_start).reshape(-1)
    q1 = finite("q_end", q_end).reshape(-1)
    if q0.shape != q1.shape:
        raise ModelInputError(f"q_end must have the length of q_start ({q0.size}), got {q1.size}")
    T = float(positive("duration", duration))
    t0 = float(finite("t_start", t_start))
    ramp = float(within("accel_fraction", accel_fraction, 0.0, 0.5, closed=(False, True)))
    delta = q1 - q0

    def evaluate(t: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        tau = min(max((t - t0) / T, 0.0), 1.0)
        s, ds, dds = _trapezoid(tau, ramp) if profile == "trapezoidal" else _quintic(tau)
        moving = 0.0 < (t - t0) / T < 1.0
        return (
            q0 + delta * s,
            delta * (ds / T if moving else 0.0),
            delta * (dds / T**2 if moving else 0.0),
        )

    knots: tuple[float, ...] = (t0, t0 + T)
    if profile == "trapezoidal":
        knots = (t0, t0 + ramp * T, t0 + (1.0 - ramp) * T, t0 + T)
    return ProgrammedMotion(evaluate=evaluate, breakpoints=tuple(sorted(set(knots))))


def program_from_samples(
    *, t: ArrayLike, q: ArrayLike, bc_type: str = "not-a-knot"
) -> ProgrammedMotion:
    """A programmed motion interpolated from samples by a cubic spline (C² in time).

    Parameters
    ----------
    t : array_like, shape (N,)
        Sample times, s, strictly increasing, N >= 4.
    q : array_like, shape (n, N) or (N,)
        Sampled coordinates (rad), one row per coordinate.
    bc_type : {'not-a-knot', 'clamped', 'natural'}, optional
        End conditions of :class:`scipy.interpolate.CubicSpline`: 'clamped' sets q' = 0 at
        both ends (a move from rest to rest), 'natural' q'' = 0.

    Returns
    -------
    ProgrammedMotion
        ``program(t)`` returning (q, q', q'') from the spline and its derivatives, defined
        on [t[0], t[-1]] only (no extrapolation), with the sample times as breakpoints.

    Notes
    -----
    q'' of a cubic spline is continuous and piecewise linear, so the load of (6) is
    continuous, but q''' jumps at every knot: :func:`dynamic_errors` restarts there, which
    spares the integrator's error control. Noisy samples should be smoothed first, as q''
    amplifies noise.
    """
    one_of("bc_type", bc_type, ("not-a-knot", "clamped", "natural"))
    ts = finite("t", t).reshape(-1)
    qs = np.atleast_2d(finite("q", q))
    if ts.size < 4 or np.any(np.diff(ts) <= 0):
        raise ModelInputError(
            f"t must hold at least 4 strictly increasing sample times, got {ts.size} values"
        )
    if qs.ndim != 2 or qs.shape[1] != ts.size:
        raise ModelInputError(
            f"q must have shape (n, {ts.size}) (one row per coordinate), got {qs.shape}"
        )
    spline = CubicSpline(ts, qs, axis=1, bc_type=bc_type)

    def evaluate(time: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        return (
            np.asarray(spline(time), dtype=np.float64),
            np.asarray(spline(time, 1), dtype=np.float64),
            np.asarray(spline(time, 2), dtype=np.float64),
        )

    return ProgrammedMotion(
        evaluate=evaluate,
        breakpoints=tuple(float(x) for x in ts[1:-1]),
        domain=(float(ts[0]), float(ts[-1])),
    )
