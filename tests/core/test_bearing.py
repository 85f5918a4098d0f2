"""Asymptotic journal-bearing theory (labs 3-4) against quadrature and closed forms."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import dblquad, quad

from rigserver.core.bearing import (
    friction_coefficient_theoretical,
    friction_moment_theoretical,
    long_bearing_pressure,
    short_bearing_eccentricity,
    short_bearing_integrals,
    short_bearing_load,
    short_bearing_pressure,
)
from rigserver.core.errors import ModelInputError

# Slide-bearing stand (manual lab 3): h0, R2, μ0 = μ20, ω0. B from correction E3: the
# edges of table 3.2 at z = ±0.59 with a = B/(2R) give B = 1.18·R.
H0 = 175e-6
R = 25.175e-3
B = 2 * 0.59 * R
MU0 = 0.0282
OMEGA0 = 329.0
PSI = H0 / R
# A run: oil at 35 °C (viscosity law (3.21)), journal at 300 rad/s.
MU = 0.0773 * np.exp(-0.0485 * 35.0)
OMEGA = 300.0

chis = st.floats(min_value=1e-6, max_value=0.99)


def _pressure_pa(phi: float, Z: float, chi: float, a: float) -> float:
    """Dimensional short-bearing pressure p - p_a = Π0·μ0ω0/Ψ² (3.6), (3.12)."""
    pi0 = short_bearing_pressure(phi=phi, z=Z / R, chi=chi, a=a, mu_bar=MU / MU0, G=OMEGA / OMEGA0)
    return float(pi0) * MU0 * OMEGA0 / PSI**2


def _film_force(chi: float, a: float, weight: str) -> float:
    """∫∫ p·(sin φ | cos φ) R dφ dZ over φ ∈ (π, 2π), Z ∈ (-aR, aR), by scipy dblquad."""
    trig = np.sin if weight == "sin" else np.cos
    value, _ = dblquad(
        lambda phi, Z: _pressure_pa(phi, Z, chi, a) * trig(phi) * R,
        -a * R,
        a * R,
        np.pi,
        2 * np.pi,
        epsabs=0.0,
        epsrel=1e-10,
    )
    return float(value)


def _ocvirk_tangential(chi: float) -> float:
    # DuBois & Ocvirk, NACA Report 1157 (1953): W_t = μUL³πε/(4c²(1-ε²)^1.5), U = ωR.
    return float(MU * OMEGA * R * B**3 * np.pi * chi / (4 * H0**2 * (1 - chi**2) ** 1.5))


def _ocvirk_radial(chi: float) -> float:
    # Same source: W_r = μUL³ε²/(c²(1-ε²)²).
    return float(MU * OMEGA * R * B**3 * chi**2 / (H0**2 * (1 - chi**2) ** 2))


def _p_star_v(chi: float, a: float) -> float:
    """P*·V of (4.2)-(4.4) written out in the test, with A3^20 by quadrature."""
    a3_20, _ = quad(lambda p: np.sin(p) ** 2 / (1 - chi * np.cos(p)) ** 3, np.pi, 2 * np.pi)
    p_star = 2 * B * R * MU0 * OMEGA0 / PSI**2
    v = -chi * a**2 * (MU / MU0) * a3_20 * (OMEGA / OMEGA0)
    return float(p_star * v)


# --- short-bearing pressure -------------------------------------------------------------


@pytest.mark.parametrize("chi", [0.2, 0.5, 0.8])
def test_short_pressure_integrates_to_p_star_v_and_ocvirk(chi: float) -> None:
    a = B / (2 * R)  # correction E3
    tangential = _film_force(chi, a, "sin")
    radial = _film_force(chi, a, "cos")
    assert tangential == pytest.approx(_p_star_v(chi, a), rel=1e-8)
    # The perpendicular projection P_τ is Ocvirk's tangential force (negative sign of V).
    assert -tangential == pytest.approx(_ocvirk_tangential(chi), rel=1e-8)
    assert radial == pytest.approx(_ocvirk_radial(chi), rel=1e-8)
    load = short_bearing_load(
        chi=chi, omega=OMEGA, viscosity=MU, bearing_radius=R, width=B, clearance=H0
    )
    assert float(load.tangential) == pytest.approx(tangential, rel=1e-8)
    assert float(load.radial) == pytest.approx(radial, rel=1e-8)
    assert float(load.resultant) == pytest.approx(np.hypot(tangential, radial), rel=1e-8)
    # Ocvirk's attitude angle: tan ψ = π√(1-ε²)/(4ε).
    assert float(np.tan(load.attitude_angle)) == pytest.approx(
        np.pi * np.sqrt(1 - chi**2) / (4 * chi), rel=1e-10
    )


def test_e3_printed_half_width_breaks_the_force_balance() -> None:
    # The print of (3.5), (3.24), (4.8), (4.20) has a = B/(4R) = B/(2D).
    chi = 0.5
    printed = B / (4 * R)
    integral = _film_force(chi, printed, "sin")
    # P*·V with the printed a is twice the integral of its own pressure field ...
    assert _p_star_v(chi, printed) == pytest.approx(2 * integral, rel=1e-8)
    # ... and a quarter of Ocvirk's force.
    assert -_p_star_v(chi, printed) == pytest.approx(_ocvirk_tangential(chi) / 4, rel=1e-8)


@settings(max_examples=40, deadline=None)
@given(
    phi=st.floats(min_value=np.pi, max_value=2 * np.pi),
    zeta=st.floats(min_value=-1.0, max_value=1.0),
    chi=st.floats(min_value=0.0, max_value=0.99),
    a=st.floats(min_value=0.01, max_value=2.0),
    G=st.floats(min_value=1e-3, max_value=10.0),
)
def test_short_pressure_non_negative_in_load_zone(
    phi: float, zeta: float, chi: float, a: float, G: float
) -> None:
    p = short_bearing_pressure(phi=phi, z=zeta * a, chi=chi, a=a, mu_bar=1.0, G=G)
    assert p >= -1e-12


@settings(max_examples=40, deadline=None)
@given(
    phi=st.floats(min_value=0.0, max_value=2 * np.pi),
    zeta=st.floats(min_value=-1.0, max_value=1.0),
    chi=st.floats(min_value=0.0, max_value=0.95),
    a=st.floats(min_value=0.01, max_value=1.0),
    k=st.floats(min_value=0.1, max_value=10.0),
)
def test_short_pressure_scales_as_a_squared_and_vanishes_at_edges(
    phi: float, zeta: float, chi: float, a: float, k: float
) -> None:
    kw: dict[str, Any] = {"phi": phi, "chi": chi, "mu_bar": 1.3, "G": 0.9, "E": 0.2}
    base = short_bearing_pressure(z=zeta * a, a=a, **kw)
    scaled = short_bearing_pressure(z=zeta * k * a, a=k * a, **kw)
    # Rounding of (z/a)² - 1 near the edges: absolute slack against 3μ̄a²k²·|wedge|/H³.
    slack = 1e-12 * 3 * 1.3 * (k * a) ** 2 * 1.1 / (1 - chi) ** 3
    assert scaled == pytest.approx(k**2 * base, rel=1e-9, abs=slack)
    edges = short_bearing_pressure(z=np.array([-a, a]), a=a, **kw)
    np.testing.assert_allclose(edges, 0.0, atol=1e-15)


def test_short_pressure_broadcasts_and_cavitation_clips() -> None:
    phi = np.linspace(0, 2 * np.pi, 37)[:, None]
    z = np.linspace(-0.3, 0.3, 5)[None, :]
    raw = short_bearing_pressure(phi=phi, z=z, chi=0.6, a=0.3, mu_bar=1.0, G=1.0)
    clipped = short_bearing_pressure(
        phi=phi, z=z, chi=0.6, a=0.3, mu_bar=1.0, G=1.0, cavitated=True
    )
    assert raw.shape == (37, 5)
    assert np.any(raw < 0)  # the raw formula is antisymmetric: negative in (0, π)
    np.testing.assert_array_equal(clipped, np.maximum(raw, 0.0))
    # E = 0: Π0(2π - φ) = -Π0(φ).
    np.testing.assert_allclose(raw[::-1], -raw, atol=1e-12)


def test_short_pressure_rejects_z_outside_the_bearing_and_chi_one() -> None:
    with pytest.raises(ModelInputError, match=r"z must lie in \[-a, a\].*z = 0.4 with a = 0.3"):
        short_bearing_pressure(phi=4.0, z=0.4, chi=0.5, a=0.3, mu_bar=1.0, G=1.0)
    with pytest.raises(ModelInputError, match=r"chi must lie in \[0.0, 1.0\), got 1.0"):
        short_bearing_pressure(phi=4.0, z=0.0, chi=1.0, a=0.3, mu_bar=1.0, G=1.0)


# --- long-bearing pressure --------------------------------------------------------------


@pytest.mark.parametrize("chi", [0.1, 0.5, 0.9])
def test_long_pressure_integrates_to_sommerfeld_load(chi: float) -> None:
    # Full Sommerfeld film, per unit length (Sommerfeld 1904; Hamrock, Schmid & Jacobson,
    # Fundamentals of Fluid Film Lubrication, 2004, ch. 10): the force is perpendicular to
    # the line of centres, W/L = 12πμωR³ε/(c²(2+ε²)(1-ε²)^0.5).
    sommerfeld = 12 * np.pi * MU * OMEGA * R**3 * chi / (H0**2 * (2 + chi**2) * np.sqrt(1 - chi**2))

    def p(phi: float) -> float:
        pi_inf = long_bearing_pressure(phi=phi, chi=chi, mu_bar=MU / MU0, G=OMEGA / OMEGA0)
        return float(pi_inf) * MU0 * OMEGA0 / PSI**2

    kw: dict[str, Any] = {"epsabs": 0.0, "epsrel": 1e-11, "limit": 200}
    perpendicular = quad(lambda f: p(f) * np.sin(f) * R, 0, 2 * np.pi, **kw)[0]
    along = quad(lambda f: p(f) * np.cos(f) * R, 0, 2 * np.pi, epsabs=1e-12 * sommerfeld)[0]
    assert -perpendicular == pytest.approx(sommerfeld, rel=1e-9)
    assert along == pytest.approx(0.0, abs=1e-9 * sommerfeld)
    # Half-Sommerfeld (load zone only): the integrand p·sin φ is even about π, so half.
    half = quad(lambda f: p(f) * np.sin(f) * R, np.pi, 2 * np.pi, **kw)[0]
    assert -half == pytest.approx(sommerfeld / 2, rel=1e-9)


@settings(max_examples=40, deadline=None)
@given(phi=st.floats(min_value=0.0, max_value=2 * np.pi), chi=chis)
def test_long_pressure_zero_at_0_and_pi_antisymmetric_positive_in_load_zone(
    phi: float, chi: float
) -> None:
    kw: dict[str, Any] = {"chi": chi, "mu_bar": 1.0, "G": 1.0}
    ends = long_bearing_pressure(phi=np.array([0.0, np.pi, 2 * np.pi]), **kw)
    # round-off of sin φ near 0, π, 2π is amplified by 1/(1 - χ)² (3.15)
    scale = 1e-12 * chi / (1 - chi) ** 2
    np.testing.assert_allclose(ends, 0.0, atol=scale)
    p = long_bearing_pressure(phi=phi, **kw)
    mirror = long_bearing_pressure(phi=2 * np.pi - phi, **kw)
    assert mirror == pytest.approx(-p, rel=1e-9, abs=scale)
    if phi > np.pi:
        assert p >= -1e-12


# --- integrals of (4.5) -----------------------------------------------------------------


@pytest.mark.parametrize("chi", [1e-8, 0.05, 0.3, 0.6, 0.9, 0.99])
def test_integrals_match_quadrature(chi: float) -> None:
    got = short_bearing_integrals(chi=chi)

    def integral(i: int, j: int, n: int) -> float:
        f = lambda p: np.sin(p) ** i * np.cos(p) ** j / (1 - chi * np.cos(p)) ** n  # noqa: E731
        return float(quad(f, np.pi, 2 * np.pi, epsabs=1e-13, epsrel=1e-12, limit=200)[0])

    assert float(got.a1_00) == pytest.approx(integral(0, 0, 1), rel=1e-10)
    assert float(got.a2_00) == pytest.approx(integral(0, 0, 2), rel=1e-10)
    assert float(got.a3_00) == pytest.approx(integral(0, 0, 3), rel=1e-10)
    assert float(got.a3_02) == pytest.approx(integral(0, 2, 3), rel=1e-10)
    assert float(got.a3_20) == pytest.approx(integral(2, 0, 3), rel=1e-10)
    assert float(got.a3_11) == pytest.approx(integral(1, 1, 3), rel=1e-9, abs=1e-12)


def test_a3_02_accurate_at_small_chi_where_the_printed_form_cancels() -> None:
    got = short_bearing_integrals(chi=1e-8)
    # Limit χ → 0: ∫_π^2π cos²φ dφ = π/2.
    assert float(got.a3_02) == pytest.approx(np.pi / 2, rel=1e-12)
    # (4.5) as printed loses every digit there (0/0 in floating point).
    printed = (got.a1_00 - 2 * got.a2_00 + got.a3_00) / 1e-16
    assert float(printed) != pytest.approx(np.pi / 2, rel=0.1)
    assert float(short_bearing_integrals(chi=0.0).a3_02) == pytest.approx(np.pi / 2)


@settings(max_examples=60, deadline=None)
@given(chi=st.floats(min_value=0.0, max_value=0.99, exclude_min=True))
def test_a3_20_closed_form_and_printed_chain(chi: float) -> None:
    got = short_bearing_integrals(chi=chi)
    assert float(got.a3_20) == pytest.approx(np.pi / (2 * (1 - chi**2) ** 1.5), rel=1e-12)
    if chi > 0.05:  # (4.5) as printed, where it does not cancel catastrophically
        printed_02 = (got.a1_00 - 2 * got.a2_00 + got.a3_00) / chi**2
        assert float(got.a3_02) == pytest.approx(float(printed_02), rel=1e-9)


# --- friction moment and coefficient (4.1)-(4.10) ---------------------------------------

# An MTOS-like bearing: D = 50 mm, B = 20 mm (a = 0.4), h0 = 50 μm, ω = 150 rad/s.
MR, MB, MH0, MW, MMU = 25e-3, 20e-3, 50e-6, 150.0, 0.03
MTOS_LIKE: dict[str, Any] = {
    "omega": MW,
    "viscosity": MMU,
    "bearing_radius": MR,
    "width": MB,
    "clearance": MH0,
}


def test_moment_is_petroff_at_zero_eccentricity() -> None:
    got = friction_moment_theoretical(chi=0.0, **MTOS_LIKE)
    # Petroff: M = 2πμωR1³B/h0, R1 = R - h0.
    petroff = 2 * np.pi * MMU * MW * (MR - MH0) ** 3 * MB / MH0
    assert float(got.moment) == pytest.approx(petroff, rel=1e-12)
    assert float(got.pressure_term) == 0.0


@settings(max_examples=30, deadline=None)
@given(
    chi=chis,
    mu0=st.floats(min_value=1e-3, max_value=1.0),
    omega0=st.floats(min_value=1.0, max_value=1e3),
)
def test_moment_terms_and_v_and_independence_of_scales(
    chi: float, mu0: float, omega0: float
) -> None:
    kw = {**MTOS_LIKE, "chi": chi}
    got = friction_moment_theoretical(reference_viscosity=mu0, reference_omega=omega0, **kw)
    default = friction_moment_theoretical(**kw)
    a = MB / (2 * MR)
    a3_20 = np.pi / (2 * (1 - chi**2) ** 1.5)
    # (4.3), (4.4) written out: P* = 2BRμ0ω0/ψ², V = -χa²μ̄A3^20·G.
    assert float(got.force_scale) == pytest.approx(2 * MB * MR * mu0 * omega0 / (MH0 / MR) ** 2)
    assert float(got.v) == pytest.approx(-chi * a**2 * (MMU / mu0) * a3_20 * (MW / omega0))
    assert float(got.half_width) == pytest.approx(a)
    # (4.1): M = -½P_τ e + ωμR1³·2πB/√(h0² - e²).
    e = chi * MH0
    shear = MW * MMU * (MR - MH0) ** 3 * 2 * np.pi * MB / np.sqrt(MH0**2 - e**2)
    assert float(got.shear_term) == pytest.approx(shear, rel=1e-12)
    assert float(got.pressure_term) == pytest.approx(-0.5 * float(got.tangential_force) * e)
    assert float(got.moment) == pytest.approx(float(got.pressure_term) + shear, rel=1e-12)
    # μ0, ω0 cancel in the moment and in P_τ.
    assert float(got.moment) == pytest.approx(float(default.moment), rel=1e-12)
    assert float(got.tangential_force) == pytest.approx(float(default.tangential_force))


def _f_at_load(load: float) -> float:
    sol = short_bearing_eccentricity(load=load, **MTOS_LIKE)
    assert sol.converged
    return float(friction_coefficient_theoretical(chi=sol.chi, load=load, **MTOS_LIKE))


@settings(max_examples=25, deadline=None)
@given(
    load=st.floats(min_value=50.0, max_value=2e4),
    factor=st.floats(min_value=1.05, max_value=10.0),
)
def test_friction_coefficient_positive_and_falls_with_load_in_fluid_film(
    load: float, factor: float
) -> None:
    f1 = _f_at_load(load)
    f2 = _f_at_load(load * factor)
    assert 0.0 < f2 < f1


def test_friction_coefficient_is_moment_over_load_times_journal_radius() -> None:
    moment = friction_moment_theoretical(chi=0.7, **MTOS_LIKE).moment
    f = friction_coefficient_theoretical(chi=0.7, load=1500.0, **MTOS_LIKE)
    assert float(f) == pytest.approx(float(moment) / (1500.0 * (MR - MH0)), rel=1e-12)


@settings(max_examples=30, deadline=None)
@given(chi=st.floats(min_value=1e-4, max_value=0.999))
def test_eccentricity_inverts_the_resultant(chi: float) -> None:
    load = float(short_bearing_load(chi=chi, **MTOS_LIKE).resultant)
    sol = short_bearing_eccentricity(load=load, **MTOS_LIKE)
    assert sol.converged
    assert sol.chi == pytest.approx(chi, rel=1e-9)


def test_eccentricity_reports_an_impossible_load_and_zero_load() -> None:
    kw = {**MTOS_LIKE, "omega": 1e-3, "viscosity": 1e-3}
    # Film force at χ = 1 - 1e-12 is ~ μωRB³/h0² · 1/(1-χ²)² ≈ 5e18 N here.
    sol = short_bearing_eccentricity(load=1e25, **kw)
    assert not sol.converged
    assert "exceeds the film force" in sol.message
    assert short_bearing_eccentricity(load=0.0, **kw).chi == 0.0


def test_friction_inputs_are_checked() -> None:
    kw: dict[str, Any] = {"chi": 0.5, "omega": MW, "viscosity": MMU, "width": MB}
    with pytest.raises(ModelInputError, match=r"clearance must be < bearing_radius"):
        friction_moment_theoretical(bearing_radius=1e-3, clearance=2e-3, **kw)
    with pytest.raises(ModelInputError, match=r"load must be > 0, got 0.0"):
        friction_coefficient_theoretical(bearing_radius=MR, clearance=MH0, load=0.0, **kw)
