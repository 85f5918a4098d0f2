"""The finite journal bearing (Reynolds equation (3.1)) against closed forms and limits.

The closed forms are written out here, independently of ``rigserver.core.bearing``:
- short bearing, (3.12) integrated over the π film (Ocvirk [1]; Hamrock [2], ch. 10);
- infinitely long bearing, (3.15) over the π film (Sommerfeld/Gümbel; Hamrock [2], ch. 10);
- long bearing with the Reynolds (Swift-Stieber) condition, solved in 1-D here by quadrature
  and a root search for the rupture angle.
In the scales of (3.6) a force is ∫∫Π dφ dz, so with a = B/D (E3) these read, per unit
μωR⁴/c² and with components along (radial) and across (tangential) the line of centres:
  short: F_r = 8a³χ²/(1-χ²)², F_t = 2πa³χ/(1-χ²)^(3/2)
  long:  F_r = 2a·12χ²/((2+χ²)(1-χ²)), F_t = 2a·6πχ/((2+χ²)(1-χ²)^(1/2)).

[1] Ocvirk F.W., DuBois G.B. NACA TN 2808 (1952); the form in models.md (E3).
[2] Hamrock B.J. et al., Fundamentals of Fluid Film Lubrication, 2nd ed., 2004.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.sparse.linalg import spsolve

from rigserver.core._reynolds_grid import make_grid, sparse_operator, stencil
from rigserver.core.errors import ModelInputError
from rigserver.core.reynolds import (
    SupplyGroove,
    SupplyHole,
    dynamic_coefficients,
    equilibrium,
    finite_bearing,
    journal_equilibrium,
    solve_reynolds,
)


def short_bearing_force(chi: float, a: float) -> tuple[float, float]:
    """(F_r, F_t) of (3.12) over φ = π..2π, magnitudes (Ocvirk)."""
    return 8 * a**3 * chi**2 / (1 - chi**2) ** 2, 2 * np.pi * a**3 * chi / (1 - chi**2) ** 1.5


def long_bearing_force(chi: float, a: float) -> tuple[float, float]:
    """(F_r, F_t) of (3.15) over φ = π..2π over the width 2a (half-Sommerfeld)."""
    k = 2 * a * 6 * chi / (2 + chi**2)
    return k * 2 * chi / (1 - chi**2), k * np.pi / np.sqrt(1 - chi**2)


def long_bearing_reynolds_force(chi: float, a: float) -> tuple[float, float]:
    """1-D long bearing, Π(π) = 0 and Π = dΠ/dφ = 0 at rupture (Swift-Stieber).

    H³Π' = 6(H - H*) from (3.14); the rupture φ2 solves ∫_π^φ2 (H - H(φ2))/H³ dφ = 0.
    By parts, the film force F_x = -∫Π cos φ dφ = 6∫(H - H*)/H³ sin φ dφ and
    F_y = -∫Π sin φ dφ = -6∫(H - H*)/H³ cos φ dφ; F_r = -F_x (towards the centre), F_t = F_y.
    """

    def film(p: float) -> float:
        return float(1 - chi * np.cos(p))

    def gap(p2: float) -> float:
        hs = film(p2)
        return float(quad(lambda p: (film(p) - hs) / film(p) ** 3, np.pi, p2, epsabs=1e-13)[0])

    p2 = brentq(gap, 2 * np.pi + 1e-9, 3 * np.pi - 1e-9, xtol=1e-14)
    hs = film(p2)

    def weighted(trig: np.ufunc) -> float:
        integral = quad(
            lambda p: (film(p) - hs) / film(p) ** 3 * trig(p), np.pi, p2, epsabs=1e-13, limit=200
        )
        return float(integral[0])

    return -2 * a * 6 * weighted(np.sin), -2 * a * 6 * weighted(np.cos)


def attitude_deg(f_r: float, f_t: float) -> float:
    return float(np.degrees(np.arctan2(f_t, f_r)))


# --- the short-bearing limit -------------------------------------------------------------


def test_half_sommerfeld_tends_to_ocvirk_as_bearing_shortens() -> None:
    errors = []
    for bd in (0.1, 0.05):
        fb = finite_bearing(0.6, bd, cavitation="half_sommerfeld")
        f_r, f_t = short_bearing_force(0.6, bd)
        errors.append(abs(fb.load / np.hypot(f_r, f_t) - 1))
        assert fb.attitude_deg == pytest.approx(attitude_deg(f_r, f_t), abs=0.5)
    # The neglected ∂/∂φ term of (3.7) is O(a²) relative: the error falls ~4x per halving.
    assert errors[1] < 0.01
    assert 2.5 < errors[0] / errors[1] < 5


def test_printed_half_width_b_over_4r_would_miss_ocvirk_e3() -> None:
    # E3: a = B/(2R) = B/D. Dimensional Ocvirk tangential force μωR·B³·πχ/(4h0²(1-χ²)^1.5)
    # divided by the force scale μωR⁴/h0² is 2π(B/D)³χ/(1-χ²)^1.5 only with a = B/D.
    b_over_d, chi = 0.04, 0.5
    ocvirk_t = np.pi * chi / (4 * (1 - chi**2) ** 1.5) * (2 * b_over_d) ** 3
    for a, agrees in ((b_over_d, True), (b_over_d / 2, False)):  # B/(2R) vs printed B/(4R)
        s = solve_reynolds(chi=chi, half_width=a, cavitation="half_sommerfeld")
        assert (abs(s.force_y / ocvirk_t - 1) < 0.01) is agrees


def test_short_bearing_field_is_3_12() -> None:
    # Pointwise: (3.12) with G = μ̄ = 1 over the π film; the neglected term is O(a²).
    chi, a = 0.6, 0.05
    s = solve_reynolds(chi=chi, half_width=a, cavitation="half_sommerfeld", n_z=16)
    phi, z = s.phi[:, None], s.z[None, :]
    p0 = 3 * a**2 * chi * np.sin(phi) / (1 - chi * np.cos(phi)) ** 3 * ((z / a) ** 2 - 1)
    assert np.abs(s.pressure - np.maximum(p0, 0)).max() < 0.01 * p0.max()


# --- the long-bearing limits -------------------------------------------------------------


def test_mid_plane_of_a_long_bearing_is_3_15() -> None:
    # Full Sommerfeld film, B/D = 10: the end effects die out exponentially towards z = 0,
    # where Π must be (3.15) with G = μ̄ = 1; the error falls ~4x per halving of the grid.
    chi = 0.6
    errors = []
    for n in (1, 2):
        s = solve_reynolds(
            chi=chi, half_width=10, cavitation="sommerfeld", n_phi=72 * n, n_z=40 * n
        )
        c = np.cos(s.phi)
        p_long = 6 * chi * (2 - chi * c) / ((2 + chi**2) * (1 - chi * c) ** 2) * -np.sin(s.phi)
        errors.append(np.abs(s.pressure[:, 20 * n] - p_long).max() / p_long.max())
    assert errors[1] < 1e-3
    assert 3.5 < errors[0] / errors[1] < 4.5


def _extrapolated(
    chi: float, cavitation: str, reference: tuple[float, float]
) -> tuple[float, float]:
    """Relative load error and attitude error (degrees) from B/D = 5 and 10, extrapolated
    to B/D → ∞ in 1/a: the end effects are edge layers of fixed width, O(1/a) in total."""
    errors, attitudes = [], []
    for bd in (5, 10):
        fb = finite_bearing(chi, bd, n_z=8 * bd, cavitation=cavitation)
        errors.append(fb.load / (bd * np.hypot(*reference)) - 1)
        attitudes.append(fb.attitude_deg)
    return 2 * errors[1] - errors[0], 2 * attitudes[1] - attitudes[0] - attitude_deg(*reference)


def test_half_sommerfeld_tends_to_long_bearing_as_bearing_lengthens() -> None:
    chi = 0.6
    f_r, f_t = long_bearing_force(chi, 10)
    fb = finite_bearing(chi, 10, n_z=80, cavitation="half_sommerfeld")
    assert fb.load / np.hypot(f_r, f_t) == pytest.approx(1, abs=0.1)
    load_error, attitude_error = _extrapolated(chi, "half_sommerfeld", long_bearing_force(chi, 1))
    assert abs(load_error) < 0.005
    assert abs(attitude_error) < 0.1


@pytest.mark.parametrize("chi", [0.3, 0.8])
def test_reynolds_condition_tends_to_1d_swift_stieber_long_bearing(chi: float) -> None:
    load_error, attitude_error = _extrapolated(chi, "reynolds", long_bearing_reynolds_force(chi, 1))
    assert abs(load_error) < 0.005
    assert abs(attitude_error) < 0.1


# --- the numerics --------------------------------------------------------------------------


def test_grid_convergence_is_second_order() -> None:
    # Error of S against a grid 4x finer in both directions falls ~4x per halving.
    def s(n: int) -> float:
        return finite_bearing(0.6, 1.0, n_phi=36 * n, n_z=12 * n).sommerfeld

    fine = s(16)
    e = [abs(s(n) - fine) for n in (1, 2, 4)]
    assert 3.0 < e[0] / e[1] < 5.5
    assert 3.0 < e[1] / e[2] < 5.5


def test_banded_solve_matches_a_sparse_direct_solve() -> None:
    # Full Sommerfeld, no supply, full width: one periodic linear system of (3.1).
    chi, a = 0.7, 0.5
    s = solve_reynolds(
        chi=chi, half_width=a, n_phi=48, n_z=16, cavitation="sommerfeld", use_symmetry=False
    )
    grid = make_grid(48, 16, a, mirror=False)
    st = stencil(grid, chi_x=chi, chi_y=0.0, vel_x=0.0, vel_y=0.0, omega=1.0, mu_bar=1.0)
    direct = spsolve(sparse_operator(st).tocsc(), st.rhs.ravel()).reshape(st.rhs.shape)
    np.testing.assert_allclose(s.pressure[:, 1:-1], direct, atol=1e-10 * np.abs(direct).max())


def test_reynolds_solution_satisfies_the_complementarity_conditions() -> None:
    chi, a = 0.6, 0.5
    s = solve_reynolds(chi=chi, half_width=a, n_phi=72, n_z=24, use_symmetry=False)
    assert s.converged
    assert np.all(s.pressure >= 0)
    grid = make_grid(72, 24, a, mirror=False)
    st = stencil(grid, chi_x=chi, chi_y=0.0, vel_x=0.0, vel_y=0.0, omega=1.0, mu_bar=1.0)
    p = s.pressure[:, 1:-1]
    multiplier = st.apply(p) - st.rhs
    cav = s.ruptured[:, 1:-1]
    scale = np.abs(st.rhs).max()
    assert cav.any()
    assert np.all(p[cav] == 0)
    assert np.all(multiplier[cav] >= -1e-10 * scale)
    assert np.abs(multiplier[~cav]).max() < 1e-10 * scale
    # Without the condition the field goes below ambient.
    assert solve_reynolds(chi=chi, half_width=a, cavitation="sommerfeld").pressure.min() < 0


def test_concentric_journal_carries_no_load() -> None:
    s = solve_reynolds(chi=0.0, half_width=0.5, supply=(SupplyGroove(angle=np.pi),))
    assert s.load < 1e-14
    # and the load starts linearly in χ (the film force of a small eccentricity)
    small = [solve_reynolds(chi=c, half_width=0.5).load for c in (1e-4, 2e-4)]
    assert small[1] / small[0] == pytest.approx(2, rel=1e-3)


def test_field_is_symmetric_about_the_mid_plane() -> None:
    kw = {"chi": 0.7, "half_width": 0.6, "delta": 0.3, "chi_dot": 0.05, "n_phi": 72, "n_z": 24}
    full = solve_reynolds(**kw, use_symmetry=False)  # type: ignore[arg-type]
    half = solve_reynolds(**kw, use_symmetry=True)  # type: ignore[arg-type]
    scale = full.pressure.max()
    np.testing.assert_allclose(full.pressure, full.pressure[:, ::-1], atol=1e-12 * scale)
    np.testing.assert_allclose(half.pressure, full.pressure, atol=1e-12 * scale)
    # odd n_z: no node on the mid-plane, the mirror face carries no flux
    odd = {**kw, "n_z": 25}
    full = solve_reynolds(**odd, use_symmetry=False)  # type: ignore[arg-type]
    half = solve_reynolds(**odd, use_symmetry=True)  # type: ignore[arg-type]
    np.testing.assert_allclose(half.pressure, full.pressure, atol=1e-12 * scale)


def test_torque_difference_equals_moment_of_the_film_force() -> None:
    # T_journal - T_bush = ∫∫H ∂Π/∂φ = -∫∫Π ∂H/∂φ = χ_x F_y - χ_y F_x (e × F, the pressure
    # torque), whatever the film fraction; here off the axes and with a squeeze velocity.
    chi, delta = 0.55, 1.0
    s = solve_reynolds(chi=chi, half_width=0.7, delta=delta, chi_dot=0.1, delta_dot=0.05)
    moment = chi * (np.cos(delta) * s.force_y - np.sin(delta) * s.force_x)
    assert s.journal_torque - s.bush_torque == pytest.approx(moment, rel=1e-3)


def test_friction_variable_is_petroff_plus_the_pressure_torque() -> None:
    # Full-film convention: T = ∫∫1/H + (χ/2)|F| sin ψ, ∫_0^2π dφ/(1 - χ cos φ) = 2π/√(1-χ²),
    # so (R/c)f = 2π²S/√(1-ε²) + ε sin ψ/2 exactly (Raimondi-Boyd's tables obey it).
    for chi, bd in ((0.3, 0.5), (0.8, 1.0)):
        fb = finite_bearing(chi, bd)
        expected = (
            2 * np.pi**2 * fb.sommerfeld / np.sqrt(1 - chi**2)
            + chi * np.sin(np.radians(fb.attitude_deg)) / 2
        )
        assert fb.friction_variable == pytest.approx(expected, rel=1e-3)
        # the ruptured film drags less
        assert fb.friction_variable_film_fraction < fb.friction_variable


def test_lightly_loaded_bearing_tends_to_petroff() -> None:
    # ε → 0: (R/c)f → 2π²S (Petroff), Q/(RcNB) → π (Couette flow), Q_s/Q → 0.
    fb = finite_bearing(0.005, 1.0)
    assert fb.friction_variable / (2 * np.pi**2 * fb.sommerfeld) == pytest.approx(1, abs=1e-3)
    assert fb.flow_variable == pytest.approx(np.pi, rel=0.02)
    assert fb.side_flow_ratio < 0.02
    assert fb.attitude_deg == pytest.approx(90, abs=10)


def test_oil_from_a_hole_leaves_through_the_ends() -> None:
    # Concentric, journal at rest, a pressurised hole: Laplace's equation, so all the oil
    # from the hole leaves at z = ±a. The hole's edge is a staircase on the grid: the
    # balance closes at first order.
    gaps = []
    for n in (1, 2):
        s = solve_reynolds(
            chi=0.0,
            half_width=0.5,
            omega=0.0,
            supply=(SupplyHole(angle=1.0, diameter=0.3, pressure=2.0),),
            n_phi=144 * n,
            n_z=48 * n,
        )
        assert s.max_pressure == pytest.approx(2.0, rel=1e-12)
        gaps.append(abs(s.side_flow / s.inflow - 1))
    assert gaps[0] < 0.05
    assert gaps[1] < 0.7 * gaps[0]


def test_supply_hole_holds_its_pressure_and_pressure_at_reads_the_field() -> None:
    hole = SupplyHole(angle=np.pi / 2, diameter=0.1, z=0.2, pressure=1.5)
    s = solve_reynolds(chi=0.5, half_width=0.5, supply=(hole,), n_phi=72, n_z=24)
    assert s.pressure_at(phi=np.pi / 2, z=0.2) == pytest.approx(1.5)
    np.testing.assert_allclose(s.pressure_at(phi=s.phi, z=s.z[5]), s.pressure[:, 5], atol=1e-12)
    assert s.pressure_at(phi=np.pi / 2 + 2 * np.pi, z=0.2) == pytest.approx(1.5)
    with pytest.raises(ModelInputError, match=r"z must lie in \[-0.5, 0.5\]"):
        s.pressure_at(phi=0.0, z=0.6)


# --- inverse problem and dynamic coefficients ---------------------------------------------


def test_equilibrium_round_trip() -> None:
    for chi, bd in ((0.6, 0.5), (0.2, 1.5)):
        s = finite_bearing(chi, bd).sommerfeld
        eq = equilibrium(s, bd)
        assert eq.converged
        assert eq.eccentricity_ratio == pytest.approx(chi, abs=1e-8)
        assert eq.sommerfeld == pytest.approx(s, rel=1e-8)


def test_journal_equilibrium_in_si_units() -> None:
    # A bearing of the slide-bearing stand's size: R = 25 mm, c = 0.175 mm, B = 30 mm.
    r, c, b, mu, omega, w = 0.025, 175e-6, 0.030, 0.0282, 329.0, 300.0
    je = journal_equilibrium(
        load=w, speed=omega, viscosity=mu, radius=r, radial_clearance=c, length=b
    )
    s = (r / c) ** 2 * mu * omega / (2 * np.pi) / (w / (2 * r * b))
    assert je.bearing.sommerfeld == pytest.approx(s, rel=1e-8)
    assert je.min_film_thickness == pytest.approx(c - je.eccentricity)
    assert je.friction_torque == pytest.approx(je.friction_coefficient * w * r)
    assert je.power_loss == pytest.approx(je.friction_torque * omega)
    # film pressure integrates to the load: mean pressure W/(2RB) below the peak
    assert w / (2 * r * b) < je.max_pressure


def test_dynamic_coefficients_match_the_short_bearing() -> None:
    # Finite differences of the closed-form short-bearing force (3.10) in position and
    # velocity (G = 1 - 2δ', E = 2χ' (3.4)), π film, integrated here by quadrature.
    a, chi, h = 0.05, 0.5, 1e-5

    def force(cx: float, cy: float, vx: float, vy: float) -> np.ndarray:
        x, d = np.hypot(cx, cy), np.arctan2(cy, cx)
        G = 1 - 2 * (cx * vy - cy * vx) / x**2
        E = 2 * (cx * vx + cy * vy) / x
        p0 = np.arctan2(E, G * x)  # Gχ sin φ - E cos φ ∝ sin(φ - p0); Π > 0 beyond p0 + π

        def line(p: float) -> float:
            return float(-4 * a**3 * (G * x * np.sin(p) - E * np.cos(p)) / (1 - x * np.cos(p)) ** 3)

        lo, hi = p0 + np.pi, p0 + 2 * np.pi
        fr = -quad(lambda p: line(p) * np.cos(p), lo, hi, epsabs=1e-14)[0]
        ft = -quad(lambda p: line(p) * np.sin(p), lo, hi, epsabs=1e-14)[0]
        return np.array([fr * np.cos(d) - ft * np.sin(d), fr * np.sin(d) + ft * np.cos(d)])

    f0 = force(chi, 0, 0, 0)
    beta = np.arctan2(-f0[1], -f0[0])
    axes = np.array([[np.cos(beta), np.sin(beta)], [-np.sin(beta), np.cos(beta)]])
    k, c = np.empty((2, 2)), np.empty((2, 2))
    for j, (ex, ey) in enumerate(axes):
        dk = force(chi + h * ex, h * ey, 0, 0) - force(chi - h * ex, -h * ey, 0, 0)
        dc = force(chi, 0, h * ex, h * ey) - force(chi, 0, -h * ex, -h * ey)
        k[:, j] = -(axes @ dk) / (2 * h * np.hypot(*f0))
        c[:, j] = -(axes @ dc) / (2 * h * np.hypot(*f0))
    dyn = dynamic_coefficients(chi, a, cavitation="half_sommerfeld")
    assert dyn.converged
    np.testing.assert_allclose(dyn.stiffness, k, rtol=0.01)
    np.testing.assert_allclose(dyn.damping, c, rtol=0.01)


def test_dynamic_coefficients_do_not_depend_on_the_step() -> None:
    coarse = dynamic_coefficients(0.6, 1.0, step=1e-3)
    fine = dynamic_coefficients(0.6, 1.0, step=1e-4)
    scale = np.abs(fine.stiffness).max()
    np.testing.assert_allclose(coarse.stiffness, fine.stiffness, atol=2e-3 * scale)
    np.testing.assert_allclose(coarse.damping, fine.damping, atol=2e-3 * np.abs(fine.damping).max())
    # stiffness from the coefficients predicts the force at a third, larger displacement
    d = 3e-3
    base = solve_reynolds(chi=0.6, half_width=1.0, supply=(SupplyGroove(angle=np.pi),))
    moved = solve_reynolds(chi=0.6 + d, half_width=1.0, supply=(SupplyGroove(angle=np.pi),))
    beta = np.arctan2(-base.force_y, -base.force_x)
    ex = np.array([np.cos(beta), np.sin(beta)])
    ey = np.array([-np.sin(beta), np.cos(beta)])
    df = np.array([moved.force_x - base.force_x, moved.force_y - base.force_y])
    dx = d * np.array([np.cos(beta), -np.sin(beta)])  # the step along X, in load axes
    predicted = -fine.stiffness @ dx * base.load
    np.testing.assert_allclose([ex @ df, ey @ df], predicted, rtol=0.02)


# --- input checks --------------------------------------------------------------------------


def test_bad_input_is_refused_with_the_limit() -> None:
    with pytest.raises(ModelInputError, match=r"chi must lie in \[0.0, 1.0\), got 1.0"):
        solve_reynolds(chi=1.0, half_width=0.5)
    with pytest.raises(ModelInputError, match="half_width must be > 0, got -1"):
        solve_reynolds(chi=0.5, half_width=-1.0)
    with pytest.raises(ModelInputError, match="cavitation must be one of"):
        finite_bearing(0.5, 1.0, cavitation="elrod")
    with pytest.raises(ModelInputError, match="n_phi must be an integer >= 16, got 8"):
        finite_bearing(0.5, 1.0, n_phi=8)
    with pytest.raises(ModelInputError, match=r"eccentricity_ratio must lie in \(0.0, 1.0\)"):
        finite_bearing(0.0, 1.0)
    with pytest.raises(ModelInputError, match=r"supply\[0\].pressure must be >= 0"):
        solve_reynolds(chi=0.5, half_width=0.5, supply=(SupplyGroove(angle=0, pressure=-1),))
    with pytest.raises(ModelInputError, match=r"supply\[0\].z must lie in \(-0.5, 0.5\)"):
        solve_reynolds(chi=0.5, half_width=0.5, supply=(SupplyHole(angle=0, diameter=0.1, z=1),))
    with pytest.raises(ModelInputError, match=r"sommerfeld must lie in \["):
        equilibrium(1e-6, 1.0)
    other = solve_reynolds(chi=0.5, half_width=0.5, n_phi=72, n_z=24)
    with pytest.raises(ModelInputError, match=r"warm_start must come from the same grid"):
        solve_reynolds(chi=0.5, half_width=0.5, warm_start=other)


@settings(max_examples=8, deadline=None)
@given(
    chi=st.floats(min_value=0.05, max_value=0.95),
    bd=st.floats(min_value=0.2, max_value=2.0),
)
def test_any_bearing_keeps_pressure_non_negative_and_stiffens_with_eccentricity(
    chi: float, bd: float
) -> None:
    # Π >= 0 under the Reynolds condition; the load rises (S falls) with χ (the monotony
    # the inverse problem relies on); the pressure torque identity holds.
    lo = finite_bearing(chi, bd, n_phi=72, n_z=24)
    hi = finite_bearing(chi + 0.02, bd, n_phi=72, n_z=24)
    assert lo.solution.pressure.min() >= 0
    assert hi.sommerfeld < lo.sommerfeld
    s = lo.solution
    assert s.journal_torque - s.bush_torque == pytest.approx(chi * s.force_y, rel=2e-3)


def test_reversed_rotation_mirrors_the_field() -> None:
    # Ω → -Ω with δ = 0 is the reflection φ → -φ of (3.1)-(3.3): the field, the ruptured
    # zone with its film fraction, and the torques (in sign) follow.
    kw = {"chi": 0.6, "half_width": 0.5, "n_phi": 72, "n_z": 24}
    fwd = solve_reynolds(**kw, omega=1.0)  # type: ignore[arg-type]
    rev = solve_reynolds(**kw, omega=-1.0)  # type: ignore[arg-type]
    mirror = np.r_[0, np.arange(71, 0, -1)]  # index of -φ_i
    np.testing.assert_allclose(rev.pressure, fwd.pressure[mirror], atol=1e-12)
    np.testing.assert_allclose(rev.film_fraction, fwd.film_fraction[mirror], atol=1e-12)
    assert rev.force_x == pytest.approx(fwd.force_x)
    assert rev.force_y == pytest.approx(-fwd.force_y)
    assert rev.journal_torque == pytest.approx(-fwd.journal_torque)
