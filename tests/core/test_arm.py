"""The article's three-link arm with ball-screw drives, seed 000 (7)-(18), correction E6."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from rigserver.core.arm import (
    AnthropomorphicArm,
    arm_dynamic_errors,
    ball_screw_force,
    screw_linkage,
)
from rigserver.core.errors import ModelInputError, ModelUndefinedError
from rigserver.core.mechanism import (
    dynamic_errors,
    numerical_inertia_derivatives,
    point_to_point,
)

F = NDArray[np.float64]
ARM = AnthropomorphicArm()


def central(f: Callable[[float], float], x: float, h: float = 1e-5) -> float:
    return (f(x + h) - f(x - h)) / (2 * h)


# --- the drive triangle (8)-(9) ----------------------------------------------------------
def triangle_points(a: float, c: float, psi: float) -> tuple[F, F, F]:
    """Joint O at the origin, screw pivot P on the x axis, nut attachment R at angle ψ."""
    return np.zeros(2), np.array([a, 0.0]), c * np.array([np.cos(psi), np.sin(psi)])


def pivot_angle(a: float, c: float, psi: float) -> float:
    """The angle at P turning PR onto PO, from the points (independent of (8))."""
    origin, P, R = triangle_points(a, c, psi)
    po, pr = origin - P, R - P
    return float(np.arctan2(pr[0] * po[1] - pr[1] * po[0], pr @ po))


triangles = st.tuples(st.floats(0.1, 1.0), st.floats(0.05, 1.0), st.floats(-3.0, 3.0))


@settings(max_examples=40, deadline=None)
@given(abc=triangles)
def test_screw_kinematics_against_the_points_and_their_derivatives(
    abc: tuple[float, float, float],
) -> None:
    a, c, psi = abc
    assume(a - c * np.cos(psi) > 0.1 * a)  # the pivot angle stays clear of 90°
    s = screw_linkage(a=a, c=c, psi=psi)
    _, P, R = triangle_points(a, c, psi)
    assert float(s.b) == pytest.approx(np.linalg.norm(R - P), rel=1e-12)
    # F = arcsin φ is the screw's angle at its pivot, measured from PO (sign: R above PO)
    assert float(s.F) == pytest.approx(pivot_angle(a, c, psi), abs=1e-12)

    def field(name: str) -> Callable[[float], float]:
        return lambda x: float(getattr(screw_linkage(a=a, c=c, psi=x), name))

    for name, deriv in [
        ("phi", "phi_q"), ("phi_q", "phi_qq"), ("phi_qq", "phi_qqq"),
        ("F", "F_q"), ("F_q", "F_qq"), ("F_qq", "F_qqq"), ("b", "lever_arm"),
    ]:  # fmt: skip
        numeric = central(field(name), psi)
        scale = max(1.0, abs(numeric))
        assert float(getattr(s, deriv)) == pytest.approx(numeric, abs=1e-6 * scale), deriv


def test_e6_derivative_of_the_screw_angle_is_a_product() -> None:
    # a = 0.3 m, c = 0.12 m, ψ = 1.2 rad: a shoulder drive of the default arm
    a, c, psi = 0.3, 0.12, 1.2
    s = screw_linkage(a=a, c=c, psi=psi)
    b2 = a**2 + c**2 - 2 * a * c * np.cos(psi)
    closed = c * (a * np.cos(psi) - c) / b2  # d/dψ atan2(c sin ψ, a - c cos ψ)
    assert float(s.F_q) == pytest.approx(closed, rel=1e-12)
    printed = (1 - s.phi**2) ** -0.5 + s.phi_q  # (9) as printed: a sum
    assert abs(float(printed) - closed) > 0.5


def test_lever_arm_is_a_phi_not_the_printed_c_phi() -> None:
    # the distance from the joint to the screw line: |OP x PR| / |PR|
    a, c, psi = 0.3, 0.12, 1.2
    s = screw_linkage(a=a, c=c, psi=psi)
    origin, P, R = triangle_points(a, c, psi)
    pr, po = R - P, origin - P
    distance = abs(po[0] * pr[1] - po[1] * pr[0]) / np.linalg.norm(pr)
    assert float(s.lever_arm) == pytest.approx(distance, rel=1e-12)
    assert abs(c * float(s.phi) - distance) > 0.5 * distance  # (15) as printed, a ≠ c


def test_pivot_angle_beyond_ninety_degrees_is_refused() -> None:
    # a = 0.1 < c cos ψ = 0.2: the angle at P is obtuse and not arcsin φ
    with pytest.raises(ModelUndefinedError, match="needs a > c·cos ψ"):
        screw_linkage(a=0.1, c=0.2, psi=0.0)
    with pytest.raises(ModelInputError, match="a must be > 0"):
        screw_linkage(a=0.0, c=0.2, psi=1.0)


# --- the ball-screw law (17)-(18) --------------------------------------------------------
@settings(max_examples=60, deadline=None)
@given(
    w=st.one_of(st.just(0.0), st.floats(1e-12, 1e-3)),  # np.roots resolves u to ~1e-8·max
    alpha=st.one_of(st.just(0.0), st.floats(1e-12, 1e-7)),
    lam=st.one_of(st.just(0.0), st.floats(1e-10, 1e-6)),
)
def test_ball_screw_force_is_the_non_negative_root(w: float, alpha: float, lam: float) -> None:
    assume(alpha > 0 or lam > 0)
    Q = float(ball_screw_force(deformation=-w, alpha=alpha, lam=lam))  # the modulus |W| counts
    assert Q >= 0
    assert w - alpha * Q == pytest.approx(lam * Q ** (2 / 3), abs=1e-12 * w + 1e-300)
    # independent: the cubic α u³ + λ u² - |W| = 0 in u = Q^(1/3) has one root u >= 0
    roots = np.roots([alpha, lam, 0.0, -w])
    real = roots[np.abs(roots.imag) <= 1e-9 * np.abs(roots)].real
    u = np.max(real[real >= -1e-12 * max(1.0, np.max(np.abs(real)))], initial=0.0)
    assert max(u, 0.0) ** 3 == pytest.approx(Q, rel=1e-8, abs=1e-300)


def test_ball_screw_limits() -> None:
    w = np.array([0.0, 1e-6, 2e-5])
    # λ = 0: a linear spring, Q = |W|/α; α = 0: a Hertz contact, Q = (|W|/λ)^(3/2)
    np.testing.assert_allclose(ball_screw_force(deformation=w, alpha=5e-9, lam=0.0), w / 5e-9)
    np.testing.assert_allclose(
        ball_screw_force(deformation=w, alpha=0.0, lam=5e-8), (w / 5e-8) ** 1.5
    )
    with pytest.raises(ModelInputError, match="alpha and lam must not both be 0"):
        ball_screw_force(deformation=w, alpha=0.0, lam=0.0)
    with pytest.raises(ModelInputError, match="alpha must be >= 0"):
        ball_screw_force(deformation=w, alpha=-1.0, lam=1e-8)


# --- the arm's kinetic energy ------------------------------------------------------------
def e(angle: float) -> F:
    return np.array([np.cos(angle), np.sin(angle)])


def bodies(arm: AnthropomorphicArm, q: F) -> list[tuple[float, float, F, float]]:
    """(mass, central inertia, centre of mass, angle) of links I-V, built from the points.

    Independent of the module: the screw directions come from atan2 of R - P, not from F.
    """
    q1, q2, q3 = q
    O2 = arm.l1 * e(q1)
    O3 = O2 + arm.l2 * e(q1 + q2)
    P1, R1 = arm.a1 * e(arm.gamma), arm.c1 * e(q1 + arm.beta)
    P2 = O2 + arm.a2 * e(q1 + arm.gamma1)
    R2 = O2 + arm.c2 * e(q1 + q2 + np.pi - arm.psi0)
    th4 = float(np.arctan2(*(R1 - P1)[::-1]))
    th5 = float(np.arctan2(*(R2 - P2)[::-1]))
    return [
        (arm.m1, arm.J1, arm.d1 * e(q1), q1),
        (arm.m2, arm.J2, O2 + arm.d2 * e(q1 + q2), q1 + q2),
        (arm.m3, arm.J3, O3 + arm.d3 * e(q1 + q2 + q3), q1 + q2 + q3),
        (arm.m4, arm.J4, P1 + arm.d4 * e(th4), th4),
        (arm.m5, arm.J5, P2 + arm.d5 * e(th5), th5),
    ]


def kinetic_energy(arm: AnthropomorphicArm, q: F, qd: F, h: float = 1e-6) -> float:
    """T = Σ ½ m v² + ½ J ω², the velocities by central differences along q + s·q'."""
    T = 0.0
    for (m, J, x_up, a_up), (_, _, x_dn, a_dn) in zip(
        bodies(arm, q + h * qd), bodies(arm, q - h * qd), strict=True
    ):
        v = (x_up - x_dn) / (2 * h)
        omega = np.angle(np.exp(1j * (a_up - a_dn))) / (2 * h)
        T += 0.5 * m * float(v @ v) + 0.5 * J * omega**2
    return T


def inertia_from_energy(arm: AnthropomorphicArm, q: F) -> F:
    """A by polarisation of T(q') = ½ q'ᵀAq'."""
    E = np.eye(3)
    A = np.empty((3, 3))
    for j in range(3):
        A[j, j] = 2 * kinetic_energy(arm, q, E[j])
        for k in range(j):
            t_jk = kinetic_energy(arm, q, E[j] + E[k])
            A[j, k] = A[k, j] = t_jk - 0.5 * (A[j, j] + A[k, k])
    return A


# The default arm's working range: ψ1 = q1 + π/2 and ψ2 = q2 + 1.54 stay in (0.2, 2.9).
configurations = st.tuples(st.floats(-1.2, 1.2), st.floats(-1.3, 1.3), st.floats(-3.1, 3.1))


@settings(max_examples=25, deadline=None)
@given(q=configurations)
def test_inertia_matrix_is_the_kinetic_energy_of_the_links(q: tuple[float, float, float]) -> None:
    A = ARM.inertia_matrix(q)
    expected = inertia_from_energy(ARM, np.array(q))
    np.testing.assert_allclose(A, expected, atol=1e-7 * np.max(np.abs(expected)))


@settings(max_examples=25, deadline=None)
@given(q=configurations)
def test_inertia_matrix_is_symmetric_positive_definite(q: tuple[float, float, float]) -> None:
    A = ARM.inertia_matrix(q)
    np.testing.assert_array_equal(A, A.T)
    assert np.min(np.linalg.eigvalsh(A)) > 0


def test_inertia_matrix_is_positive_definite_along_a_programme() -> None:
    program = point_to_point(q_start=[-1.0, -1.2, -3.0], q_end=[1.1, 1.2, 3.0], duration=1.0)
    for t in np.linspace(0.0, 1.0, 41):
        A = ARM.inertia_matrix(program(t)[0])
        assert np.min(np.linalg.eigvalsh(A)) > 0


@settings(max_examples=20, deadline=None)
@given(q=configurations)
def test_closed_form_derivatives_agree_with_central_differences(
    q: tuple[float, float, float],
) -> None:
    closed = ARM.inertia_derivatives(q)
    numeric = numerical_inertia_derivatives(ARM.inertia_matrix, q=q)
    scale = np.max(np.abs(ARM.inertia_matrix(q)))
    np.testing.assert_allclose(closed.first, numeric.first, atol=1e-8 * scale)
    np.testing.assert_allclose(closed.second, numeric.second, atol=1e-5 * scale)


# --- restoring moments (14)-(18) and the final system ------------------------------------
@settings(max_examples=30, deadline=None)
@given(q=configurations, xi=st.tuples(*[st.floats(-1e-3, 1e-3)] * 3))
def test_restoring_moments_oppose_the_error_and_solve_18(
    q: tuple[float, float, float], xi: tuple[float, float, float]
) -> None:
    M = ARM.restoring_moments(q, xi)
    assert M[2] == 0.0
    s1, s2 = ARM.linkages(q)
    for k, (s, alpha, lam) in enumerate([(s1, ARM.alpha1, ARM.lam1), (s2, ARM.alpha2, ARM.lam2)]):
        assert M[k] * xi[k] >= 0
        h = ARM.a1 * float(s.phi) if k == 0 else ARM.a2 * float(s.phi)  # h = a φ
        Q = abs(M[k] / h)
        # (18): |h ξ| - α Q = λ Q^(2/3)
        assert abs(h * xi[k]) - alpha * Q == pytest.approx(lam * Q ** (2 / 3), rel=1e-9, abs=1e-18)


def test_the_arm_lags_its_accelerating_programme() -> None:
    """While every joint accelerates from rest the load -A q'' is negative in each row
    (A has positive entries here), so the links lag: ξ < 0 once the drives have taken it up.
    """
    q0, q1 = np.array([0.2, 0.1, 0.0]), np.array([0.8, 0.7, 0.6])
    program = point_to_point(q_start=q0, q_end=q1, duration=0.5, profile="quintic")
    assert np.all(ARM.inertia_matrix(q0) > 0)
    t = np.linspace(0.0, 0.08, 17)
    res = arm_dynamic_errors(arm=ARM, program=program, t_eval=t)
    assert res.success
    late = t >= 0.04
    assert np.all(res.xi[:, late] < 0)
    assert np.all(res.max_abs < 1e-3)  # a stiff drive: well under a milliradian


def test_closed_form_and_numerical_derivatives_give_the_same_errors() -> None:
    program = point_to_point(
        q_start=[0.2, 0.1, 0.0], q_end=[0.8, 0.7, 0.6], duration=0.5, profile="quintic"
    )
    t = np.linspace(0.0, 0.03, 7)
    closed = arm_dynamic_errors(arm=ARM, program=program, t_eval=t, rtol=1e-8)
    assert closed.success

    def restoring(xi: F, xi_dot: F, time: float) -> F:
        return ARM.restoring_moments(program(time)[0], xi)

    numeric = dynamic_errors(
        ARM.inertia_matrix,
        np.diag([0.0, 0.0, ARM.c33]),
        np.diag([ARM.b11, ARM.b22, ARM.b33]),
        program,
        t,
        restoring,
        rtol=1e-8,
    )
    np.testing.assert_allclose(closed.xi, numeric.xi, atol=1e-5 * np.max(np.abs(closed.xi)))


def test_bad_arm_parameters_are_refused() -> None:
    with pytest.raises(ModelInputError, match="m1 must be > 0"):
        AnthropomorphicArm(m1=-1.0)
    with pytest.raises(ModelInputError, match="alpha2 and lam2 must not both be 0"):
        AnthropomorphicArm(alpha2=0.0, lam2=0.0)
    with pytest.raises(ModelInputError, match="q must hold the 3 angles"):
        ARM.inertia_matrix([0.1, 0.2])
    # a1 = 0.1 < c1 = 0.2: at ψ1 = 0 (q1 = -π/2) the shoulder drive's pivot angle is obtuse
    with pytest.raises(ModelUndefinedError, match="needs a > c·cos ψ"):
        AnthropomorphicArm(a1=0.1, c1=0.2).inertia_matrix([-np.pi / 2, 0.0, 0.0])
