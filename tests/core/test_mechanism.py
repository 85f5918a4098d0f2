"""Dynamic errors of programmed motion, seed 000 (1)-(6), with corrections E7, E8."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray
from scipy.integrate import solve_ivp

from rigserver.core.errors import ModelInputError, ModelUndefinedError
from rigserver.core.mechanism import (
    InertiaDerivatives,
    dynamic_errors,
    error_equation_coefficients,
    numerical_inertia_derivatives,
    point_to_point,
    program_from_samples,
)

F = NDArray[np.float64]

# --- an independent reference: the classical two-link planar arm -------------------------
# Links of length l1, centres of mass at lc1, lc2, masses m1, m2, central inertias J1, J2;
# q2 relative to link 1 (Spong, Hutchinson, Vidyasagar, Robot Modeling and Control, 7.4).
M1, M2, L1, LC1, LC2, J1, J2 = 2.0, 1.5, 0.6, 0.3, 0.25, 0.06, 0.03
I1 = J1 + M1 * LC1**2
I2 = J2 + M2 * LC2**2
H = M2 * L1 * LC2


def two_link_A(q: F) -> F:
    c2 = np.cos(q[1])
    return np.array(
        [[I1 + I2 + M2 * L1**2 + 2 * H * c2, I2 + H * c2], [I2 + H * c2, I2]], dtype=float
    )


def two_link_derivatives(q: F) -> InertiaDerivatives:
    """Closed-form ∂A/∂q2 and ∂²A/∂q2² of two_link_A (A depends on q2 only)."""
    s2, c2 = np.sin(q[1]), np.cos(q[1])
    first = np.zeros((2, 2, 2))
    second = np.zeros((2, 2, 2, 2))
    first[:, :, 1] = [[-2 * H * s2, -H * s2], [-H * s2, 0.0]]
    second[:, :, 1, 1] = [[-2 * H * c2, -H * c2], [-H * c2, 0.0]]
    return InertiaDerivatives(first=first, second=second)


def two_link_torque(p: F, pd: F, pdd: F) -> F:
    """Rigid-body joint torques M(p)p̈ + C(p, ṗ)ṗ of the classical two-link arm."""
    h = H * np.sin(p[1])
    coriolis = np.array([-h * (2 * pd[0] * pd[1] + pd[1] ** 2), h * pd[0] ** 2])
    return np.asarray(two_link_A(p) @ pdd + coriolis, dtype=float)


def jacobian(f: Callable[[F], F], x: F, step: float = 1e-6) -> F:
    """Central-difference Jacobian, columns = derivatives along each coordinate."""
    cols = [(f(x + step * e) - f(x - step * e)) / (2 * step) for e in np.eye(x.size)]
    return np.column_stack(cols)


angles = st.floats(-3.0, 3.0)
rates = st.floats(-3.0, 3.0)


# --- coefficients (5) against the classical dynamics ---------------------------------------
@settings(max_examples=25, deadline=None)
@given(q=st.tuples(angles, angles), qd=st.tuples(rates, rates), qdd=st.tuples(rates, rates))
def test_coefficients_are_the_linearisation_of_the_classical_two_link_dynamics(
    q: tuple[float, float], qd: tuple[float, float], qdd: tuple[float, float]
) -> None:
    q_, qd_, qdd_ = np.array(q), np.array(qd), np.array(qdd)
    co = error_equation_coefficients(two_link_A, q=q_, q_dot=qd_, q_ddot=qdd_)
    # order zero: the right side of (6) is minus the rigid-body torque of the programme
    np.testing.assert_allclose(co.load, -two_link_torque(q_, qd_, qdd_), atol=1e-7)
    # order one: ∂τ/∂ṗ is the ξ' coefficient, ∂τ/∂p the ξ coefficient (module docstring)
    d_vel = jacobian(lambda v: two_link_torque(q_, v, qdd_), qd_)
    d_pos = jacobian(lambda p: two_link_torque(p, qd_, qdd_), q_)
    np.testing.assert_allclose(co.velocity, d_vel, atol=1e-6)
    np.testing.assert_allclose(co.position, d_pos, atol=1e-6)


# A generic state (any with q2 not 0 or π and both rates non-zero would do).
Q, QD, QDD = np.array([0.3, 0.7]), np.array([1.1, -0.8]), np.array([0.5, 2.0])


def test_e7_velocity_term_uses_gamma_not_the_printed_lambda_mlk() -> None:
    co = error_equation_coefficients(two_link_A, q=Q, q_dot=QD, q_ddot=QDD)
    d_vel = jacobian(lambda v: two_link_torque(Q, v, QDD), QD)
    # the print of (5) puts λ_mlk = ∂A_mk/∂q_l on the left of the γ definition
    printed = np.einsum("mlk,m->kl", co.lam, QD)
    assert np.max(np.abs(printed - d_vel)) > 0.1 * np.max(np.abs(d_vel))
    np.testing.assert_allclose(co.velocity, d_vel, atol=1e-6)


def test_e8_gamma_term_multiplies_the_velocity_error() -> None:
    co = error_equation_coefficients(two_link_A, q=Q, q_dot=QD, q_ddot=QDD)
    d_pos = jacobian(lambda p: two_link_torque(p, QD, QDD), Q)
    # the print of the final system has γ_mlk q̇_m ξ_l: γ q̇ in the ξ coefficient
    printed = co.position + co.velocity
    assert np.max(np.abs(printed - d_pos)) > 0.1 * np.max(np.abs(d_pos))


def test_mu_index_order_of_the_printed_6_fails() -> None:
    """(6) prints μ_klms q̇_m q̇_s ξ_l; (5) defines μ_kmls = ∂θ_kml/∂q_s, so it is μ_kmsl."""
    co = error_equation_coefficients(two_link_A, q=Q, q_dot=QD, q_ddot=QDD)
    d_pos = jacobian(lambda p: two_link_torque(p, QD, QDD), Q)
    printed = np.einsum("klm,m->kl", co.lam, QDD) + np.einsum("klms,m,s->kl", co.mu, QD, QD)
    assert np.max(np.abs(printed - d_pos)) > 0.1 * np.max(np.abs(d_pos))


@settings(max_examples=20, deadline=None)
@given(q=st.tuples(angles, angles))
def test_numerical_derivatives_agree_with_the_closed_form(q: tuple[float, float]) -> None:
    closed = two_link_derivatives(np.array(q))
    numeric = numerical_inertia_derivatives(two_link_A, q=q)
    scale = np.max(np.abs(two_link_A(np.array(q))))
    # truncation and rounding of central differences with steps ε^(1/3), ε^(1/4)
    np.testing.assert_allclose(numeric.first, closed.first, atol=1e-9 * scale)
    np.testing.assert_allclose(numeric.second, closed.second, atol=1e-6 * scale)


def test_closed_form_and_numerical_derivatives_give_the_same_coefficients() -> None:
    numeric = error_equation_coefficients(two_link_A, q=Q, q_dot=QD, q_ddot=QDD)
    closed = error_equation_coefficients(
        two_link_A, q=Q, q_dot=QD, q_ddot=QDD, derivative=two_link_derivatives
    )
    np.testing.assert_allclose(closed.mu, numeric.mu, atol=1e-6)
    np.testing.assert_allclose(closed.gamma, numeric.gamma, atol=1e-9)
    np.testing.assert_allclose(closed.theta, numeric.theta, atol=1e-9)


# --- one degree of freedom: the damped oscillator -----------------------------------------
MASS, STIFF, DAMP, ACC = 2.0, 800.0, 4.0, 3.0
OMEGA = np.sqrt(STIFF / MASS)
ZETA = DAMP / (2 * np.sqrt(STIFF * MASS))
OMEGA_D = OMEGA * np.sqrt(1 - ZETA**2)


def step_response(t: F) -> F:
    """ξ of m ξ'' + b ξ' + c ξ = -m a H(t), from rest: the damped oscillator's step."""
    tt = np.maximum(t, 0.0)
    decay = np.exp(-ZETA * OMEGA * tt)
    shape = 1 - decay * (np.cos(OMEGA_D * tt) + ZETA * OMEGA / OMEGA_D * np.sin(OMEGA_D * tt))
    return np.asarray(-ACC / OMEGA**2 * shape * (t >= 0), dtype=float)


def constant_mass(q: F) -> F:
    return np.array([[MASS]])


@pytest.mark.parametrize(("method", "rtol"), [("Radau", 1e-8), ("DOP853", 1e-9), ("LSODA", 1e-9)])
def test_one_dof_constant_acceleration_is_a_damped_step_response(method: str, rtol: float) -> None:
    def program(t: float) -> tuple[F, F, F]:
        return np.array([0.5 * ACC * t**2]), np.array([ACC * t]), np.array([ACC])

    t = np.linspace(0.0, 1.0, 101)
    res = dynamic_errors(
        constant_mass, [[STIFF]], [[DAMP]], program, t, method=method, rtol=rtol, atol=1e-13
    )
    assert res.success
    exact = step_response(t)
    # the global error stays within a hundred local tolerances
    np.testing.assert_allclose(res.xi[0], exact, atol=100 * rtol * np.max(np.abs(exact)))
    np.testing.assert_allclose(res.max_abs, [np.max(np.abs(exact))], rtol=100 * rtol)


def test_trapezoidal_profile_is_four_superposed_steps() -> None:
    """q'' of a trapezoid is ACC·[H(t) - H(t-ta) - H(t-T+ta) + H(t-T)]; ξ superposes steps.

    The breakpoints restart the integrator, so the corners of q'' cost no accuracy.
    """
    T, ramp = 0.4, 0.25
    ta = ramp * T
    delta = ACC * ta * (T - ta)  # the distance covered at acceleration ACC
    program = point_to_point(
        q_start=[0.0], q_end=[delta], duration=T, profile="trapezoidal", accel_fraction=ramp
    )
    t = np.linspace(0.0, 1.0, 201)
    res = dynamic_errors(
        constant_mass, [[STIFF]], [[DAMP]], program, t, method="DOP853", rtol=1e-9, atol=1e-13
    )
    exact = step_response(t) - step_response(t - ta) - step_response(t - T + ta)
    exact += step_response(t - T)
    np.testing.assert_allclose(res.xi[0], exact, atol=1e-6 * np.max(np.abs(exact)))


# --- the elastic two-link arm: linear theory against the full nonlinear model -------------
STIFFNESS = np.diag([40.0, 20.0])
DAMPING = np.diag([0.8, 0.3])


def nonlinear_deviation(
    program: Callable[[float], tuple[F, F, F]],
    t: F,
    p0: F,
    pd0: F,
    external: Callable[[float], F] = lambda time: np.zeros(2),
) -> F:
    """p - q of the elastic arm: motors follow q(t), links p driven through springs c, b.

    M(p)p̈ + C(p, ṗ)ṗ = -c(p - q) - b(ṗ - q̇) + τ_ext(t), the full nonlinear Lagrangian
    dynamics of the links.
    """

    def rhs(time: float, y: F) -> F:
        p, pd = y[:2], y[2:]
        q, qd, _ = program(time)
        spring = -STIFFNESS @ (p - q) - DAMPING @ (pd - qd) + external(time)
        pdd = np.linalg.solve(two_link_A(p), spring - two_link_torque(p, pd, np.zeros(2)))
        return np.concatenate([pd, pdd])

    sol = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([p0, pd0]), t_eval=t,
                    method="DOP853", rtol=1e-11, atol=1e-13)  # fmt: skip
    assert sol.success
    q_prog = np.column_stack([program(time)[0] for time in t])
    return np.asarray(sol.y[:2] - q_prog, dtype=float)


def linearisation_error(scale: float) -> tuple[float, float]:
    """Max |ξ| and max |ξ_nonlinear - ξ_linear| for a move of amplitude `scale`."""
    q0 = np.array([0.2, 0.5])
    program = point_to_point(
        q_start=q0, q_end=q0 + scale * np.array([1.0, -0.8]), duration=0.6, profile="quintic"
    )
    t = np.linspace(0.0, 1.5, 151)
    lin = dynamic_errors(
        two_link_A, STIFFNESS, DAMPING, program, t, method="DOP853", rtol=1e-11, atol=1e-13
    )
    assert lin.success
    q_start, qd_start, _ = program(0.0)
    nonlin = nonlinear_deviation(program, t, q_start, qd_start)
    return float(np.max(np.abs(nonlin))), float(np.max(np.abs(nonlin - lin.xi)))


def test_linear_errors_agree_with_the_nonlinear_arm_to_second_order() -> None:
    xi_big, err_big = linearisation_error(0.05)
    xi_small, err_small = linearisation_error(0.025)
    # ξ scales linearly with the move (the load -A q'' is linear in it) ...
    assert xi_big / xi_small == pytest.approx(2.0, rel=0.1)
    # ... and the neglected terms are quadratic in ξ: halving the move quarters them.
    assert 3.0 < err_big / err_small < 5.0
    assert err_big < 0.02 * xi_big


def fast_programme(t: float) -> tuple[F, F, F]:
    """A smooth programme with O(1) speeds and accelerations (rad, rad/s, rad/s²)."""
    q = np.array([0.3 + 2.0 * t + 0.4 * np.sin(3.0 * t), 1.0 - 1.5 * t + 0.5 * np.sin(2.5 * t)])
    qd = np.array([2.0 + 1.2 * np.cos(3.0 * t), -1.5 + 1.25 * np.cos(2.5 * t)])
    qdd = np.array([-3.6 * np.sin(3.0 * t), -3.125 * np.sin(2.5 * t)])
    return q, qd, qdd


def feedforward(xi: F, xi_dot: F, t: float) -> F:
    """Link torques τ_rigid(q, q', q'') applied from outside, as a force on the left of (6).

    With them the programme needs no spring force, so ξ = 0 is exact and the error comes
    from the initial deviation alone.
    """
    return -two_link_torque(*fast_programme(t))


def perturbation(scale: float) -> tuple[F, F, F]:
    """ξ of the nonlinear arm, of (6), and of (6) without the γ, λ, μ terms, on a grid.

    The initial deviation ξ(0) = scale·(0.5, -0.5) is the only excitation.
    """
    t = np.linspace(0.0, 1.0, 51)
    xi0 = scale * np.array([0.5, -0.5])
    lin = dynamic_errors(
        two_link_A, STIFFNESS, DAMPING, fast_programme, t, feedforward, method="DOP853",
        rtol=1e-10, atol=1e-13, xi0=xi0,
    )  # fmt: skip
    q_start, qd_start, _ = fast_programme(0.0)
    nonlin = nonlinear_deviation(
        fast_programme,
        t,
        q_start + xi0,
        qd_start,
        external=lambda time: -feedforward(xi0, xi0, time),
    )

    def bare(time: float, y: F) -> F:  # A(q(t)) ξ'' + b ξ' + c ξ = 0
        acc = np.linalg.solve(
            two_link_A(fast_programme(time)[0]), -DAMPING @ y[2:] - STIFFNESS @ y[:2]
        )
        return np.concatenate([y[2:], acc])

    naive = solve_ivp(bare, (0.0, 1.0), np.concatenate([xi0, [0.0, 0.0]]), t_eval=t,
                      method="DOP853", rtol=1e-10, atol=1e-13).y[:2]  # fmt: skip
    return nonlin, lin.xi, naive


def test_coriolis_and_centrifugal_terms_hold_to_second_order_on_a_fast_programme() -> None:
    """With O(1) programme speeds, γ, λ, μ all act at first order in ξ."""
    nonlin_big, lin_big, naive_big = perturbation(0.02)
    nonlin_small, lin_small, naive_small = perturbation(0.01)
    size_big, size_small = np.max(np.abs(nonlin_big)), np.max(np.abs(nonlin_small))
    err_big, err_small = (
        np.max(np.abs(nonlin_big - lin_big)),
        np.max(np.abs(nonlin_small - lin_small)),
    )
    assert size_big / size_small == pytest.approx(2.0, rel=0.1)
    assert 3.0 < err_big / err_small < 5.0
    assert err_big < 0.02 * size_big
    # control: without γ, λ, μ the error is first order in ξ, and much larger
    naive_err_big = np.max(np.abs(nonlin_big - naive_big))
    naive_err_small = np.max(np.abs(nonlin_small - naive_small))
    assert naive_err_big / naive_err_small < 2.5
    assert naive_err_big > 10 * err_big


# --- the limit of rigid drives ---------------------------------------------------------------
def test_errors_vanish_like_one_over_stiffness_and_tend_to_the_static_deflection() -> None:
    """As c → ∞ (damping ratio fixed) c·ξ(t) → f(t) = -τ_rigid(t): ξ = O(1/c)."""
    q0 = np.array([0.2, 0.5])
    program = point_to_point(
        q_start=q0, q_end=q0 + np.array([1.0, -0.8]), duration=0.6, profile="quintic"
    )
    t = np.linspace(0.0, 0.6, 61)
    load = np.column_stack([-two_link_torque(*program(time)) for time in t])
    gaps, peaks = [], []
    for c in (1e4, 1e6):
        damping = 2 * 0.7 * np.sqrt(c * 0.5) * np.eye(2)  # ζ ≈ 0.7 for an inertia ≈ 0.5
        res = dynamic_errors(
            two_link_A, c * np.eye(2), damping, program, t, method="LSODA", rtol=1e-8, atol=1e-14
        )
        assert res.success
        gaps.append(np.max(np.abs(c * res.xi - load)) / np.max(np.abs(load)))
        peaks.append(c * res.max_abs)
    # the lag of the damped drive, ~2ζ√(m/c)·f', makes the gap O(c^-1/2): 100x stiffer,
    # about 10x closer; the peaks c·max|ξ| tend to max|f| of each joint
    assert gaps[1] < gaps[0] / 5
    np.testing.assert_allclose(peaks[1], np.max(np.abs(load), axis=1), rtol=2e-3)
    assert np.all(np.abs(peaks[0] / np.max(np.abs(load), axis=1) - 1) > 2e-3)


# --- programmed motion -----------------------------------------------------------------------
def test_trapezoidal_move_values() -> None:
    # Δ = 1, T = 1, ramp 1/4: v = 1/(1 - 1/4) = 4/3, a = v/(1/4) = 16/3
    program = point_to_point(q_start=[0.0], q_end=[1.0], duration=1.0)
    q, qd, qdd = program(0.125)
    assert (q[0], qd[0], qdd[0]) == pytest.approx((0.5 * 16 / 3 * 0.125**2, 16 / 3 * 0.125, 16 / 3))
    q, qd, qdd = program(0.5)
    assert (q[0], qd[0], qdd[0]) == pytest.approx((0.5, 4 / 3, 0.0))
    q, qd, qdd = program(2.0)
    assert (q[0], qd[0], qdd[0]) == pytest.approx((1.0, 0.0, 0.0))
    assert program.breakpoints == pytest.approx((0.0, 0.25, 0.75, 1.0))


def test_quintic_move_values() -> None:
    # s = 10τ³ - 15τ⁴ + 6τ⁵: s(1/2) = 1/2, s'(1/2) = 15/8, s''(1/2) = 0, s''(1/4) = 45/8·...
    program = point_to_point(q_start=[1.0, 0.0], q_end=[3.0, -1.0], duration=2.0, profile="quintic")
    q, qd, qdd = program(1.0)
    np.testing.assert_allclose(q, [2.0, -0.5])
    np.testing.assert_allclose(qd, np.array([2.0, -1.0]) * 15 / 8 / 2.0)
    np.testing.assert_allclose(qdd, [0.0, 0.0], atol=1e-15)
    # s''(τ) = 60τ(1 - τ)(1 - 2τ); at τ = 1/4: 60·(1/4)(3/4)(1/2) = 45/8
    np.testing.assert_allclose(program(0.5)[2], np.array([2.0, -1.0]) * 45 / 8 / 4.0)


@settings(max_examples=30, deadline=None)
@given(
    time=st.floats(0.0, 1.0).filter(lambda x: min(abs(x - b) for b in (0, 0.3, 0.7, 1)) > 1e-3),
    profile=st.sampled_from(["trapezoidal", "quintic"]),
)
def test_programme_derivatives_are_consistent(time: float, profile: str) -> None:
    program = point_to_point(
        q_start=[0.2, -1.0], q_end=[1.5, 0.5], duration=1.0, profile=profile, accel_fraction=0.3
    )
    h = 1e-6
    q_up, qd_up, _ = program(time + h)
    q_dn, qd_dn, _ = program(time - h)
    _, qd, qdd = program(time)
    np.testing.assert_allclose((q_up - q_dn) / (2 * h), qd, atol=1e-6)
    np.testing.assert_allclose((qd_up - qd_dn) / (2 * h), qdd, atol=1e-5)


def test_samples_of_a_cubic_are_reproduced_exactly() -> None:
    # a not-a-knot cubic spline reproduces any cubic polynomial
    t = np.linspace(0.0, 2.0, 9)
    program = program_from_samples(t=t, q=np.vstack([t**3 - 2 * t, 0.5 * t**2]))
    q, qd, qdd = program(1.3)
    np.testing.assert_allclose(q, [1.3**3 - 2.6, 0.5 * 1.69])
    np.testing.assert_allclose(qd, [3 * 1.69 - 2, 1.3])
    np.testing.assert_allclose(qdd, [6 * 1.3, 1.0])
    with pytest.raises(ModelInputError, match=r"t must lie in \[0.0, 2.0\]"):
        program(2.5)


def test_sampled_programme_gives_the_same_errors_as_the_closed_form_one() -> None:
    exact = point_to_point(q_start=[0.0], q_end=[0.5], duration=1.0, profile="quintic")
    ts = np.linspace(0.0, 1.0, 201)
    sampled = program_from_samples(
        t=ts, q=np.array([[exact(x)[0][0] for x in ts]]), bc_type="clamped"
    )
    t = np.linspace(0.0, 1.0, 51)
    opts = {"method": "DOP853", "rtol": 1e-9, "atol": 1e-13}
    a = dynamic_errors(constant_mass, [[STIFF]], [[DAMP]], exact, t, **opts)  # type: ignore[arg-type]
    b = dynamic_errors(constant_mass, [[STIFF]], [[DAMP]], sampled, t, **opts)  # type: ignore[arg-type]
    # the spline's q'' differs from the quintic's by O(h²) = O(2.5e-5) relative
    np.testing.assert_allclose(b.xi, a.xi, atol=1e-3 * np.max(np.abs(a.xi)))
    with pytest.raises(ModelInputError, match=r"t_eval must lie in \[0.0, 1.0\]"):
        dynamic_errors(constant_mass, [[STIFF]], [[DAMP]], sampled, np.linspace(0, 2, 5))


# --- interface, validation and reporting -----------------------------------------------------
def hold(t: float) -> tuple[F, F, F]:
    return np.array([0.3, 0.7]), np.zeros(2), np.zeros(2)


def test_keyword_call_and_restoring_force_add_to_stiffness() -> None:
    """A linear restoring force k ξ is the same as adding k to the stiffness."""
    t = np.linspace(0.0, 1.0, 21)
    kw = {"inertia_matrix": two_link_A, "damping": DAMPING, "program": hold, "t_eval": t}
    extra = np.diag([10.0, 5.0])
    kw |= {"xi0": [0.01, 0.02], "method": "DOP853", "rtol": 1e-10}
    a = dynamic_errors(stiffness=STIFFNESS + extra, **kw)  # type: ignore[arg-type]
    b = dynamic_errors(
        stiffness=STIFFNESS,
        restoring=lambda xi, xd, time: extra @ xi,
        **kw,  # type: ignore[arg-type]
    )
    np.testing.assert_allclose(b.xi, a.xi, atol=1e-9)
    assert a.xi.shape == (2, 21)
    assert a.xi_dot.shape == (2, 21)


def test_non_convergence_is_reported_not_raised() -> None:
    # ξ'' = ξ² from ξ(0) = 4 blows up at t* = 2.9745/√4 = 1.487 s (t* = ∫ dξ/ξ' by energy)
    res = dynamic_errors(
        lambda q: np.eye(1), [[0.0]], [[0.0]], lambda t: (np.zeros(1),) * 3,
        np.arange(0.0, 3.01, 0.25), lambda xi, xd, t: -(xi**2), xi0=[4.0], method="DOP853",
    )  # fmt: skip
    assert not res.success
    assert "stopped" in res.message
    assert res.t[-1] == 1.25
    assert res.xi.shape == (1, res.t.size)


def test_a_wrong_closed_form_derivative_is_refused() -> None:
    def wrong(q: F) -> InertiaDerivatives:
        good = two_link_derivatives(q)
        return InertiaDerivatives(first=-good.first, second=good.second)

    with pytest.raises(ModelInputError, match="disagrees with central differences"):
        dynamic_errors(two_link_A, STIFFNESS, DAMPING, hold, [0.0, 1.0], derivative=wrong)


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"method": "Euler"}, ModelInputError, "method must be one of"),
        ({"t_eval": [0.0, 1.0, 0.5]}, ModelInputError, "t_eval must be strictly increasing"),
        ({"t_eval": [0.0]}, ModelInputError, "t_eval must hold at least 2 times"),
        ({"stiffness": [[40.0, 1.0], [0.0, 20.0]]}, ModelInputError, "stiffness must be symm"),
        ({"damping": -DAMPING}, ModelInputError, "damping must be positive semi-definite"),
        ({"stiffness": np.eye(3)}, ModelInputError, r"stiffness must be an 2 x 2 array"),
        ({"xi0": [0.0]}, ModelInputError, "xi0 must have length 2"),
        ({"rtol": 0.0}, ModelInputError, "rtol must be > 0"),
        ({"derivative": "complex"}, ModelInputError, "derivative must be one of"),
        (
            {"inertia_matrix": lambda q: np.array([[1.0, 2.0], [2.0, 1.0]])},
            ModelUndefinedError,
            "inertia_matrix must be positive definite",
        ),
        (
            {"inertia_matrix": lambda q: np.array([[1.0, 0.5], [0.0, 1.0]])},
            ModelInputError,
            "inertia_matrix must be symmetric",
        ),
        (
            {"program": lambda t: (np.zeros(2), np.zeros(3), np.zeros(2))},
            ModelInputError,
            "program\\(t\\) must return q' of length 2",
        ),
    ],
)
def test_bad_input_is_refused(kwargs: dict[str, object], error: type, match: str) -> None:
    args: dict[str, object] = {
        "inertia_matrix": two_link_A,
        "stiffness": STIFFNESS,
        "damping": DAMPING,
        "program": hold,
        "t_eval": [0.0, 1.0],
    }
    args.update(kwargs)
    with pytest.raises(error, match=match):
        dynamic_errors(**args)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"profile": "cubic"}, "profile must be one of"),
        ({"duration": 0.0}, "duration must be > 0"),
        ({"accel_fraction": 0.6}, r"accel_fraction must lie in \(0.0, 0.5\]"),
        ({"q_end": [1.0]}, "q_end must have the length of q_start"),
    ],
)
def test_bad_moves_are_refused(kwargs: dict[str, object], match: str) -> None:
    args: dict[str, object] = {"q_start": [0.0, 0.0], "q_end": [1.0, 1.0], "duration": 1.0}
    args.update(kwargs)
    with pytest.raises(ModelInputError, match=match):
        point_to_point(**args)  # type: ignore[arg-type]
