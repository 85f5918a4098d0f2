"""The article's worked mechanism: a three-link anthropomorphic arm with ball-screw drives.

Seed 000, (7)-(18): shoulder I, forearm II and gripper III in a plane, the shoulder and
the forearm each driven by a ball-screw mechanism (links IV and V). The generalised
coordinates are q1 (shoulder angle from the x axis), q2 (forearm relative to the
shoulder) and q3 (gripper relative to the forearm); the drive angles q4, q5 follow from
the constraint equations (7)-(8).

Geometry (fig. 1 of the article is not reproduced; this is the frame used here)
---------------------------------------------------------------------------------
Each drive is a triangle O-P-R: O the joint of the driven link, P the pivot of the screw
on the carrying body at |OP| = a_i, R the nut's attachment on the driven link at
|OR| = c_i, ψ_i the angle at O from OP to OR, and b_i = |PR| the screw length (8).
Shoulder drive IV: O = O1, P1 on the base in the direction γ from the x axis, R1 on the
shoulder at the angle β from its axis, so ψ1 = q1 + β - γ (8). Forearm drive V: O = O2
(the elbow), P2 on the shoulder at the angle γ1 from its axis, R2 on the forearm at the
angle π - ψ0 from its axis, so ψ2 = π + q2 - γ1 - ψ0 (8). The screw's angle at its
pivot is F_i = arcsin φ_i, φ_i = (c_i/b_i) sin ψ_i (8), and its direction is that of PO
turned by -F_i, so the screws turn with q̇4 = -F1' q̇1 (absolute) and q̇5 = -F2' q̇2
(relative to the shoulder), as (7) up to the constants and the sign of the figure.
Centres of mass lie on the link axes at d_i from the joint (from the pivot for IV, V).

The kinetic energy T = ½ q̇ᵀA(q)q̇ then gives A in closed form (:meth:`inertia_matrix`),
with ω = S q̇ the absolute rates of I-III (S lower triangular of ones):
A = SᵀWS + I5 u uᵀ + m5 d5 k5 (e1 uᵀ + u e1ᵀ), u = (1, -F2', 0),
W11 = J1 + m1 d1² + (m2 + m3) l1² + m5 |O1P2|² + (J4 + m4 d4²) F1'²,
W22 = J2 + m2 d2² + m3 l2², W33 = J3 + m3 d3², W12 = (m2 d2 + m3 l2) l1 cos q2,
W13 = m3 l1 d3 cos(q2 + q3), W23 = m3 l2 d3 cos q3, I5 = J5 + m5 d5²,
k5 = -[l1 cos(F2 - γ1) + a2 cos F2], |O1P2|² = l1² + a2² + 2 l1 a2 cos γ1.
This has the structure of the printed (10), whose misprints are: cos q1 for cos q2 (A11,
A12), l1 l2 for l2 d3 in the last cos q3 term of A11, q1 + q3 for q2 + q3 (A12), and no
factor 2 on the m5 d5 term of A11; the signs of its F2' terms depend on the figure's
orientation of q5. (11)-(13) are replaced by :meth:`AnthropomorphicArm.inertia_derivatives`.
Gravity is not in the article's model and not here.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rigserver.core._checks import finite, non_negative, positive
from rigserver.core.errors import ModelInputError, ModelUndefinedError
from rigserver.core.mechanism import (
    DynamicErrors,
    InertiaDerivatives,
    Program,
    dynamic_errors,
)

FloatArray = NDArray[np.float64]

#: Newton iterations allowed in :func:`ball_screw_force` (it converges in fewer than 10).
BALL_SCREW_MAX_ITERATIONS = 60


@dataclass(frozen=True, slots=True)
class ScrewLinkage:
    """Kinematics of a ball-screw drive triangle, (8)-(9) with correction E6.

    All derivatives are with respect to the joint angle q_i (dψ_i/dq_i = 1).

    Attributes
    ----------
    b : ndarray
        Screw length b_i (8), m.
    phi, phi_q, phi_qq, phi_qqq : ndarray
        φ_i = (c_i/b_i) sin ψ_i (8), dimensionless, and its first three derivatives (9),
        per rad, rad⁻², rad⁻³.
    F, F_q, F_qq, F_qqq : ndarray
        Screw angle at its pivot F_i = arcsin φ_i (8), rad, and its derivatives (9), E6.
    lever_arm : ndarray
        h_i = ∂b_i/∂q_i = a_i φ_i, m: the arm of the screw force about the joint and the
        screw's elongation per radian (15)-(16).
    """

    b: FloatArray
    phi: FloatArray
    phi_q: FloatArray
    phi_qq: FloatArray
    phi_qqq: FloatArray
    F: FloatArray
    F_q: FloatArray
    F_qq: FloatArray
    F_qqq: FloatArray
    lever_arm: FloatArray


def screw_linkage(*, a: ArrayLike, c: ArrayLike, psi: ArrayLike) -> ScrewLinkage:
    """Screw length, φ, F = arcsin φ and their derivatives for a drive triangle, (8)-(9).

    .. math:: b = \\sqrt{a^2 + c^2 - 2ac\\cos ψ},\\quad φ = \\frac{c}{b}\\sin ψ,\\quad
              \\frac{∂φ}{∂q} = \\frac{c\\cos ψ - aφ^2}{b},\\quad
              \\frac{∂F}{∂q} = (1 - φ^2)^{-1/2}\\frac{∂φ}{∂q}

    Parameters
    ----------
    a : array_like
        Distance a_i from the joint to the screw's pivot, m (> 0).
    c : array_like
        Distance c_i from the joint to the nut's attachment, m (> 0).
    psi : array_like
        Angle ψ_i at the joint between the two (8), rad.

    Returns
    -------
    ScrewLinkage
        b, φ, F, their derivatives (9) and the lever arm h = a φ.

    Raises
    ------
    ModelUndefinedError
        Where a <= c cos ψ: the angle at the pivot is then not acute and is not arcsin φ.

    Notes
    -----
    Correction E6: ∂F/∂q = (1 - φ²)^(-1/2)·∂φ/∂q, a product (chain rule of arcsin); the
    print of (9) has a sum. The other formulas of (9) are as printed. Lever arm: the
    distance from the joint to the screw line is 2·area/b = a c sin ψ / b = a φ, which is
    also ∂b/∂ψ, so h_i = a_i φ_i; the print of (15) has c_i φ_i, which agrees only when
    a_i = c_i (a misprint not yet listed among the corrections of docs/models.md).

    References
    ----------
    .. [1] Seed 000, (7)-(9), (15)-(16).
    """
    a_ = positive("a", a)
    c_ = positive("c", c)
    psi_ = finite("psi", psi)
    a_, c_, psi_ = np.broadcast_arrays(a_, c_, psi_)
    return _linkage(a_, c_, psi_)


def _linkage(a: FloatArray, c: FloatArray, psi: FloatArray) -> ScrewLinkage:
    """(8)-(9) for checked a, c, psi (arrays of one shape, or 0-d)."""
    cos_psi = np.cos(psi)
    acute = a - c * cos_psi
    if np.any(acute <= 0):
        a_, c_, p_ = (np.atleast_1d(x).reshape(-1) for x in np.broadcast_arrays(a, c, psi))
        bad = int(np.flatnonzero(a_ - c_ * np.cos(p_) <= 0)[0])
        raise ModelUndefinedError(
            f"psi = {p_[bad]} rad puts the screw pivot angle at or beyond 90° (needs "
            f"a > c·cos ψ, got a = {a_[bad]}, c·cos ψ = {c_[bad] * np.cos(p_[bad])})"
        )
    b = np.sqrt(a**2 + c**2 - 2.0 * a * c * cos_psi)
    phi = c * np.sin(psi) / b
    phi_q = (c * cos_psi - a * phi**2) / b
    phi_qq = -phi * (3.0 * a * phi_q / b + 1.0)
    phi_qqq = -(4.0 * a * phi * phi_qq + 3.0 * a * phi_q**2 + c * cos_psi) / b
    root = 1.0 / np.sqrt(1.0 - phi**2)
    F_q = root * phi_q
    F_qq = root * (phi * F_q**2 + phi_qq)
    F_qqq = root * (3.0 * phi * F_q * F_qq + phi_q * F_q**2 + phi_qqq)
    return ScrewLinkage(
        b=b,
        phi=phi,
        phi_q=phi_q,
        phi_qq=phi_qq,
        phi_qqq=phi_qqq,
        F=np.arcsin(phi),
        F_q=F_q,
        F_qq=F_qq,
        F_qqq=F_qqq,
        lever_arm=a * phi,
    )


def ball_screw_force(*, deformation: ArrayLike, alpha: ArrayLike, lam: ArrayLike) -> FloatArray:
    """Modulus Q of the elastic reaction of a ball-screw pair from its deformation (17).

    .. math:: |W| - α Q = λ Q^{2/3}

    Parameters
    ----------
    deformation : array_like
        Elastic axial deformation W of the screw-nut pair, m (its modulus is used).
    alpha : array_like
        Linear compliance α of the screw, m/N (>= 0).
    lam : array_like
        Contact compliance λ of the balls, m/N^(2/3) (>= 0); not both α and λ zero.

    Returns
    -------
    ndarray
        Q >= 0, N, broadcast over the arguments; Q = 0 where W = 0.

    Notes
    -----
    With u = Q^(1/3) the equation is the cubic α u³ + λ u² - |W| = 0, which has exactly
    one non-negative root (one sign change; the left side grows from -|W|). It is found
    by Newton's method from the upper bound min((|W|/α)^(1/3), (|W|/λ)^(1/2)): the cubic
    is convex and increasing for u >= 0, so the iterates fall monotonically to the root.
    α, λ depend on the screw and nut and on the current b (the article, after (17));
    they are taken as given here.

    References
    ----------
    .. [1] Seed 000, (17)-(18); B. I. Pavlov, Ball-screw mechanisms in instrument making,
       Leningrad, 1968.
    """
    w = np.abs(finite("deformation", deformation))
    al = non_negative("alpha", alpha)
    la = non_negative("lam", lam)
    w, al, la = np.broadcast_arrays(w, al, la)
    if np.any((al == 0) & (la == 0)):
        raise ModelInputError("alpha and lam must not both be 0 (a rigid screw has no law (17))")
    return _ball_screw_force(w, al, la)


def _ball_screw_force(w: FloatArray, al: FloatArray, la: FloatArray) -> FloatArray:
    """Root Q of (17) for checked |W| >= 0, α, λ >= 0 (not both 0) of one shape."""
    u = np.zeros(w.shape)
    loaded = w > 0
    wl, al_, la_ = w[loaded], al[loaded], la[loaded]
    with np.errstate(divide="ignore"):
        root = np.minimum(np.cbrt(wl / al_), np.sqrt(wl / la_))  # an upper bound
    for _ in range(BALL_SCREW_MAX_ITERATIONS):
        step = ((al_ * root + la_) * root**2 - wl) / ((3.0 * al_ * root + 2.0 * la_) * root)
        root = root - step
        if np.all(np.abs(step) <= 4.0 * np.finfo(np.float64).eps * root):
            break
    u[loaded] = root
    return np.asarray(u**3, dtype=np.float64)


def _sym(x: FloatArray, y: FloatArray) -> FloatArray:
    return np.asarray(np.outer(x, y) + np.outer(y, x), dtype=np.float64)


_S = np.tril(np.ones((3, 3)))
_E1 = np.array([1.0, 0.0, 0.0])
_E2 = np.array([0.0, 1.0, 0.0])


@dataclass(frozen=True, slots=True)
class AnthropomorphicArm:
    """Parameters of the article's arm, SI units (seed 000, fig. 1 and (7)-(18)).

    The article gives no numbers; the defaults are plausible values for a light handling
    robot (links of 0.5 m and 0.4 m, steel ball screws with 20 mm shafts) and should be
    replaced by the stand's data.

    Attributes
    ----------
    m1, m2, m3, m4, m5 : float
        Masses of the shoulder, forearm, gripper (with payload), drives IV and V, kg.
    J1, J2, J3, J4, J5 : float
        Moments of inertia about their centres of mass, kg·m².
    d1, d2, d3, d4, d5 : float
        Distances from the joint (IV, V: from the screw pivot) to the centre of mass, m.
    l1, l2 : float
        Shoulder and forearm lengths (joint to joint), m.
    a1, c1, beta, gamma : float
        Shoulder drive IV: |O1P1|, |O1R1| (m), the angle of R1 from the shoulder axis and
        the direction of P1 from the x axis (rad); ψ1 = q1 + β - γ (8).
    a2, c2, gamma1, psi0 : float
        Forearm drive V: |O2P2|, |O2R2| (m), the angle of P2 from the shoulder axis and
        π minus the angle of R2 from the forearm axis (rad); ψ2 = π + q2 - γ1 - ψ0 (8).
    alpha1, alpha2 : float
        Linear compliances α_k of the ball-screw pairs (17), m/N.
    lam1, lam2 : float
        Contact compliances λ_k of the ball-screw pairs (17), m/N^(2/3).
    c33 : float
        Stiffness of the gripper joint, N·m/rad (the third equation of the final system).
    b11, b22, b33 : float
        Damping of the three joints, N·m·s/rad.
    """

    m1: float = 12.0
    m2: float = 8.0
    m3: float = 3.0
    m4: float = 4.0
    m5: float = 3.0
    J1: float = 0.25
    J2: float = 0.11
    J3: float = 0.005
    J4: float = 0.03
    J5: float = 0.02
    d1: float = 0.25
    d2: float = 0.2
    d3: float = 0.06
    d4: float = 0.15
    d5: float = 0.12
    l1: float = 0.5
    l2: float = 0.4
    a1: float = 0.3
    c1: float = 0.12
    beta: float = 0.0
    gamma: float = -np.pi / 2
    a2: float = 0.25
    c2: float = 0.08
    gamma1: float = 2.9
    psi0: float = -1.3
    alpha1: float = 5e-9
    alpha2: float = 5e-9
    lam1: float = 5e-8
    lam2: float = 5e-8
    c33: float = 5e3
    b11: float = 200.0
    b22: float = 200.0
    b33: float = 1.0

    def __post_init__(self) -> None:
        angles = {"beta", "gamma", "gamma1", "psi0"}
        may_be_zero = {"J1", "J2", "J3", "J4", "J5", "m4", "m5", "d4", "d5", "alpha1"}
        may_be_zero |= {"alpha2", "lam1", "lam2", "c33", "b11", "b22", "b33"}
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in angles:
                finite(f.name, value)
            elif f.name in may_be_zero:
                non_negative(f.name, value)
            else:
                positive(f.name, value)
        for k in (1, 2):
            if getattr(self, f"alpha{k}") == 0 and getattr(self, f"lam{k}") == 0:
                raise ModelInputError(f"alpha{k} and lam{k} must not both be 0")

    def linkages(self, q: ArrayLike) -> tuple[ScrewLinkage, ScrewLinkage]:
        """The drive triangles IV and V at coordinates q (rad), (8)-(9)."""
        return self._linkages(_coordinates(q))

    def _linkages(self, q: FloatArray) -> tuple[ScrewLinkage, ScrewLinkage]:
        psi1 = np.asarray(q[0] + self.beta - self.gamma)
        psi2 = np.asarray(np.pi + q[1] - self.gamma1 - self.psi0)
        return (
            _linkage(np.asarray(self.a1), np.asarray(self.c1), psi1),
            _linkage(np.asarray(self.a2), np.asarray(self.c2), psi2),
        )

    def _parts(self, q: FloatArray) -> tuple[FloatArray, ScrewLinkage, ScrewLinkage]:
        """W(q) and the two drive triangles; cached, as A, ∂A and the moments share them."""
        return _arm_parts(self, float(q[0]), float(q[1]), float(q[2]))

    def _screw_v(self, s2: ScrewLinkage) -> tuple[float, float, float]:
        """k5 = -[l1 cos(F2 - γ1) + a2 cos F2] and its first two derivatives in q2."""
        F, F_q, F_qq = float(s2.F), float(s2.F_q), float(s2.F_qq)
        cos_part = self.l1 * np.cos(F - self.gamma1) + self.a2 * np.cos(F)
        sin_part = self.l1 * np.sin(F - self.gamma1) + self.a2 * np.sin(F)
        return -cos_part, sin_part * F_q, cos_part * F_q**2 + sin_part * F_qq

    def inertia_matrix(self, q: ArrayLike) -> FloatArray:
        """Kinetic-energy matrix A(q) (3 x 3) of (10), kg·m², derived from the kinematics.

        Parameters
        ----------
        q : array_like, shape (3,)
            Shoulder, forearm and gripper angles q1, q2, q3, rad.

        Returns
        -------
        ndarray, shape (3, 3)
            A_jk with T = ½ Σ A_jk q̇_j q̇_k (3); the closed form is in the module docstring.
        """
        q_ = _coordinates(q)
        W, _, s2 = self._parts(q_)
        u = np.array([1.0, -float(s2.F_q), 0.0])
        k5 = self._screw_v(s2)[0]
        I5 = self.J5 + self.m5 * self.d5**2
        A = _S.T @ W @ _S + I5 * np.outer(u, u) + self.m5 * self.d5 * k5 * _sym(_E1, u)
        return np.asarray(0.5 * (A + A.T), dtype=np.float64)  # symmetric to the last bit

    def inertia_derivatives(self, q: ArrayLike) -> InertiaDerivatives:
        """Closed-form ∂A/∂q and ∂²A/∂q∂q of the arm, in place of the misprinted (11)-(13).

        Parameters
        ----------
        q : array_like, shape (3,)
            Shoulder, forearm and gripper angles, rad.

        Returns
        -------
        InertiaDerivatives
            ``first[k, m, l]`` = ∂A_km/∂q_l, ``second[k, m, l, s]`` = ∂²A_km/∂q_l∂q_s,
            kg·m² per rad and per rad².

        Notes
        -----
        Uses the derivatives of F_i up to the third (9, with E6). Checked against central
        differences of :meth:`inertia_matrix` in the tests.
        """
        q_ = _coordinates(q)
        _, s1, s2 = self._parts(q_)
        m3, l1, l2, d3 = self.m3, self.l1, self.l2, self.d3
        I4 = self.J4 + self.m4 * self.d4**2
        I5 = self.J5 + self.m5 * self.d5**2
        c12 = (self.m2 * self.d2 + m3 * l2) * l1
        dW = np.zeros((3, 3, 3))  # dW[l] = ∂W/∂q_l
        d2W = np.zeros((3, 3, 3, 3))  # d2W[l, s] = ∂²W/∂q_l∂q_s
        dF1, d2F1, d3F1 = float(s1.F_q), float(s1.F_qq), float(s1.F_qqq)
        dW[0, 0, 0] = 2.0 * I4 * dF1 * d2F1
        d2W[0, 0, 0, 0] = 2.0 * I4 * (d2F1**2 + dF1 * d3F1)
        # (W_ij, its coefficient, its angle, the coordinates the angle depends on)
        cosines = (
            (0, 1, c12, q_[1], (1,)),
            (0, 2, m3 * l1 * d3, q_[1] + q_[2], (1, 2)),
            (1, 2, m3 * l2 * d3, q_[2], (2,)),
        )
        for i, j, coef, angle, wrt in cosines:
            for l in wrt:  # noqa: E741 (the article's index)
                dW[l, i, j] = dW[l, j, i] = -coef * np.sin(angle)
                for s in wrt:
                    d2W[l, s, i, j] = d2W[l, s, j, i] = -coef * np.cos(angle)
        first = np.einsum("ai,lab,bj->ijl", _S, dW, _S)
        second = np.einsum("ai,lsab,bj->ijls", _S, d2W, _S)
        # forearm drive V: depends on q2 only, through F2
        u = np.array([1.0, -float(s2.F_q), 0.0])
        du = -float(s2.F_qq) * _E2
        d2u = -float(s2.F_qqq) * _E2
        k5, dk5, d2k5 = self._screw_v(s2)
        md = self.m5 * self.d5
        first[:, :, 1] += I5 * _sym(du, u) + md * (dk5 * _sym(_E1, u) + k5 * _sym(_E1, du))
        second[:, :, 1, 1] += I5 * (_sym(d2u, u) + 2.0 * np.outer(du, du)) + md * (
            d2k5 * _sym(_E1, u) + 2.0 * dk5 * _sym(_E1, du) + k5 * _sym(_E1, d2u)
        )
        return InertiaDerivatives(
            first=0.5 * (first + first.transpose(1, 0, 2)),
            second=0.5 * (second + second.transpose(1, 0, 2, 3)),
        )

    def restoring_moments(self, q: ArrayLike, xi: ArrayLike) -> FloatArray:
        """Restoring moments of the ball-screw pairs on joints 1, 2 (14)-(18), N·m.

        .. math:: M_k = h_k Q_k \\operatorname{sign} ξ_k,\\quad
                  |h_k ξ_k| - α_k Q_k = λ_k Q_k^{2/3}

        Parameters
        ----------
        q : array_like, shape (3,)
            Programmed angles, rad.
        xi : array_like, shape (3,)
            Dynamic errors ξ, rad.

        Returns
        -------
        ndarray, shape (3,)
            (M1, M2, 0): generalised forces added to the left of (6); M_k ξ_k >= 0.

        Notes
        -----
        The screw's elongation is W_k = h_k ξ_k (16) with h_k = a_k φ_k = ∂b_k/∂q_k (the
        print of (15) has c_k φ_k, see :func:`screw_linkage`); M_k = |h_k| Q_k sign ξ_k,
        which is (14) for h_k > 0 and keeps M_k opposing ξ_k in a mirrored drive.
        """
        return self._moments(self._lever_arms(_coordinates(q)), _coordinates(xi, name="xi"))

    def _lever_arms(self, q: FloatArray) -> FloatArray:
        _, s1, s2 = self._parts(q)
        return np.array([float(s1.lever_arm), float(s2.lever_arm)])

    def _moments(self, h: FloatArray, xi: FloatArray) -> FloatArray:
        Q = _ball_screw_force(
            np.abs(h * xi[:2]),
            np.array([self.alpha1, self.alpha2]),
            np.array([self.lam1, self.lam2]),
        )
        return np.concatenate([np.abs(h) * Q * np.sign(xi[:2]), [0.0]])


@lru_cache(maxsize=256)
def _arm_parts(
    arm: AnthropomorphicArm, q1: float, q2: float, q3: float
) -> tuple[FloatArray, ScrewLinkage, ScrewLinkage]:
    """W of the module docstring and the drive triangles at (q1, q2, q3); not to be mutated."""
    s1, s2 = arm._linkages(np.array([q1, q2, q3]))
    m2, m3, m5, l1, l2 = arm.m2, arm.m3, arm.m5, arm.l1, arm.l2
    W = np.zeros((3, 3))
    W[0, 0] = (
        arm.J1
        + arm.m1 * arm.d1**2
        + (m2 + m3) * l1**2
        + m5 * (l1**2 + arm.a2**2 + 2.0 * l1 * arm.a2 * np.cos(arm.gamma1))
        + (arm.J4 + arm.m4 * arm.d4**2) * float(s1.F_q) ** 2
    )
    W[1, 1] = arm.J2 + m2 * arm.d2**2 + m3 * l2**2
    W[2, 2] = arm.J3 + m3 * arm.d3**2
    W[0, 1] = W[1, 0] = (m2 * arm.d2 + m3 * l2) * l1 * np.cos(q2)
    W[0, 2] = W[2, 0] = m3 * l1 * arm.d3 * np.cos(q2 + q3)
    W[1, 2] = W[2, 1] = m3 * l2 * arm.d3 * np.cos(q3)
    W.flags.writeable = False
    return W, s1, s2


def _coordinates(q: ArrayLike, name: str = "q") -> FloatArray:
    arr = finite(name, q).reshape(-1)
    if arr.size != 3:
        raise ModelInputError(f"{name} must hold the 3 angles q1, q2, q3, got {arr.size} values")
    return arr


def arm_dynamic_errors(
    *,
    arm: AnthropomorphicArm,
    program: Program,
    t_eval: ArrayLike,
    method: str = "LSODA",
    rtol: float = 1e-6,
    atol: float = 1e-12,
) -> DynamicErrors:
    """Dynamic errors of the arm's programmed motion: the final system of seed 000.

    .. math:: Σ_m A_{km}\\ddot ξ_m + Σ_{m,l}γ_{mlk}\\dot q_m\\dot ξ_l + b_{kk}\\dot ξ_k
              + Σ_l K_{kl}ξ_l + M_k = f_k \\;(k = 1, 2),\\qquad
              \\ldots + c_{33}ξ_3 = f_3

    Parameters
    ----------
    arm : AnthropomorphicArm
        The arm's parameters.
    program : callable
        ``program(t)`` returning (q, q', q'') of the three joints, rad, rad/s, rad/s²; e.g.
        :func:`rigserver.core.mechanism.point_to_point`.
    t_eval : array_like
        Output times, s, strictly increasing.
    method, rtol, atol
        As in :func:`rigserver.core.mechanism.dynamic_errors`.

    Returns
    -------
    DynamicErrors
        ξ(t), ξ'(t) of the three joints (rad), their largest moduli and the solver status.

    Notes
    -----
    The first two joints are held by the ball-screw pairs (restoring moments (14)-(18) in
    place of c ξ), the gripper joint by the linear stiffness c33; damping is diagonal.
    The closed-form :meth:`AnthropomorphicArm.inertia_derivatives` are used (checked
    against central differences by :func:`dynamic_errors`). Corrections E6, E7, E8.

    References
    ----------
    .. [1] Seed 000, (6), (14)-(18) and the final system.
    """

    @lru_cache(maxsize=64)
    def lever_arms(t: float) -> FloatArray:
        return arm._lever_arms(np.asarray(program(t)[0], dtype=np.float64).reshape(-1))

    def restoring(xi: FloatArray, xi_dot: FloatArray, t: float) -> FloatArray:
        return arm._moments(lever_arms(t), xi)

    return dynamic_errors(
        arm.inertia_matrix,
        np.diag([0.0, 0.0, arm.c33]),
        np.diag([arm.b11, arm.b22, arm.b33]),
        program,
        t_eval,
        restoring,
        method=method,
        rtol=rtol,
        atol=atol,
        derivative=arm.inertia_derivatives,
    )
