"""Processing of the slide-bearing and MTOS stand readings (labs 3-4)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rigserver.core.bearing import short_bearing_pressure
from rigserver.core.bearing_readings import (
    bearing_characteristic,
    mean_eccentricity_ratio,
    mean_oil_viscosity,
    measured_dimensionless_pressure,
    model_angle_deg,
    mtos_attitude_angles,
    mtos_eccentricity,
    mtos_film_viscosity,
    mtos_friction,
    relative_error_percent,
    slide_bearing_eccentricity,
    temperature_rise,
    viscosity,
)
from rigserver.core.errors import ModelInputError, ModelUndefinedError

# Slide-bearing stand constants (manual, lab 3): h0, R2, μ0 = μ20, ω0, A, α of (3.21).
H0 = 175e-6
R2 = 25.175e-3
MU0 = 0.0282
OMEGA0 = 329.0
A = 0.0773
ALPHA = -0.0485


# --- viscosity (3.21), (4.17) -----------------------------------------------------------


@settings(max_examples=50, deadline=None)
@given(t=st.floats(min_value=-20.0, max_value=150.0))
def test_viscosity_law_log_round_trip(t: float) -> None:
    mu = viscosity(t=t, A=A, alpha=ALPHA)
    assert float(np.log(mu / A) / ALPHA) == pytest.approx(t, abs=1e-9)


def test_viscosity_values_and_checks() -> None:
    # At 0 °C the law returns A; the oil thins as it heats (α < 0).
    assert float(viscosity(t=0.0, A=A, alpha=ALPHA)) == A
    mus = viscosity(t=np.array([20.0, 40.0]), A=A, alpha=ALPHA)
    assert mus[1] < mus[0]
    with pytest.raises(ModelInputError, match=r"A must be > 0, got -1.0"):
        viscosity(t=20.0, A=-1.0, alpha=ALPHA)


# --- slide-bearing stand (3.16)-(3.27) --------------------------------------------------


def test_slide_bearing_eccentricity_by_hand() -> None:
    # |X_уст - X| = 75 μm, |Y_уст - Y| = 100 μm: e_x = 100, e_y = 75, e = 125 μm (3-4-5).
    got = slide_bearing_eccentricity(
        x=np.array([25e-6, 0.0]),
        y=np.array([200e-6, 0.0]),
        x_set=100e-6,
        y_set=100e-6,
        clearance=H0,
    )
    np.testing.assert_allclose(got.e_x, [100e-6, 75e-6], rtol=1e-12)
    np.testing.assert_allclose(got.e_y, [75e-6, 75e-6], rtol=1e-12)
    assert got.e[0] == pytest.approx(125e-6, rel=1e-12)
    assert got.chi[0] == pytest.approx(125 / 175, rel=1e-12)
    assert got.e[1] == pytest.approx(75e-6 * np.sqrt(2), rel=1e-12)


def test_measured_pressure_inverts_the_scaling_of_3_6() -> None:
    # Π of the short-bearing theory made dimensional by (3.6), p - p_a = Π·μ0ω0/Ψ², and
    # read back by (3.18)-(3.19), is Π again.
    phi = np.deg2rad(np.arange(190.0, 360.0, 10.0))
    pi0 = short_bearing_pressure(phi=phi, z=0.0, chi=0.6, a=0.59, mu_bar=0.9, G=1.0)
    gauge = pi0 * MU0 * OMEGA0 / (H0 / R2) ** 2
    back = measured_dimensionless_pressure(
        gauge_pressure=gauge, clearance=H0, bearing_radius=R2, mu0=MU0, omega0=OMEGA0
    )
    np.testing.assert_allclose(back, pi0, rtol=1e-12)


def test_measured_pressure_of_one_technical_atmosphere() -> None:
    # 1 at = 98 066.5 Pa on the stand: Π = pΨ²/(μ0ω0), Ψ = 175/25 175.
    got = measured_dimensionless_pressure(
        gauge_pressure=98_066.5, clearance=H0, bearing_radius=R2, mu0=MU0, omega0=OMEGA0
    )
    assert float(got) == pytest.approx(98_066.5 * (175 / 25_175) ** 2 / (0.0282 * 329), rel=1e-12)


def test_model_angle_spans_the_load_zone_of_table_3_3() -> None:
    # Procedure items 7-12: start at the end of the load zone φ_k and turn back 180°.
    limb = 250.0 - np.arange(0.0, 190.0, 10.0)
    got = model_angle_deg(limb_deg=limb, load_zone_end_deg=250.0)
    np.testing.assert_allclose(got, np.arange(360.0, 170.0, -10.0))
    assert got[0] == 360.0  # φ_k = 2π of (3.11), not 0


def test_model_angle_wraps_when_the_limb_passes_zero() -> None:
    # φ_k = 30°, turned back 40° through 0 to the limb reading 350°: φ_мод = 320°
    # ((3.20) unwrapped gives 360 - (30 - 350) = 680°).
    assert float(model_angle_deg(limb_deg=350.0, load_zone_end_deg=30.0)) == pytest.approx(320.0)


def test_mean_viscosity_and_mean_chi() -> None:
    got = mean_oil_viscosity(t_in=[30.0, 32.0], t_out=[40.0, 46.0], A=A, alpha=ALPHA, mu0=MU0)
    # t = (t1ср + t2ср)/2 = (31 + 43)/2 = 37 °C.
    assert got.temperature == pytest.approx(37.0)
    assert got.viscosity == pytest.approx(A * np.exp(ALPHA * 37.0))
    assert got.mu_bar == pytest.approx(A * np.exp(ALPHA * 37.0) / MU0)
    assert mean_eccentricity_ratio(chi=[0.5, 0.6, 0.7]) == pytest.approx(0.6)
    with pytest.raises(ModelInputError, match=r"chi must hold at least one row"):
        mean_eccentricity_ratio(chi=[])


def test_relative_errors_of_table_3_3_leave_zeros_of_the_theory_undefined() -> None:
    phi = np.deg2rad(np.arange(180.0, 361.0, 10.0))
    theory = short_bearing_pressure(phi=phi, z=0.0, chi=0.6, a=0.59, mu_bar=1.0, G=1.0)
    measured = 0.8 * theory
    got = relative_error_percent(reference=theory, other=measured)
    # Π0 = 0 at φ = 180° and 360° (sin φ = 0): no relative error there.
    assert not got.defined[0] and not got.defined[-1]
    assert np.all(got.defined[1:-1])
    # (3.26): (Π0 - Π_э)/Π0·100 = 20 % for Π_э = 0.8·Π0.
    np.testing.assert_allclose(got.percent[1:-1], 20.0, rtol=1e-12)
    assert np.all(np.isnan(got.percent[~got.defined]))


def test_friction_error_divides_by_the_experiment() -> None:
    # Table 4.4 note: Δf = (f_э - f_T)/f_э·100 %; f_э = 0.004, f_T = 0.003 -> 25 %.
    got = relative_error_percent(reference=0.004, other=0.003)
    assert float(got.percent) == pytest.approx(25.0)


# --- MTOS stand (4.11)-(4.21) -----------------------------------------------------------

MH0 = 60e-6


def test_mtos_eccentricity_is_the_clearance_at_the_setting() -> None:
    # At X = X_уст, Y = Y_уст: e_x = e_y = h0·cos45°, e = h0, χ = 1 (journal on the bush).
    got = mtos_eccentricity(x=5e-6, y=-3e-6, x_set=5e-6, y_set=-3e-6, clearance=MH0)
    assert float(got.e_x) == pytest.approx(MH0 / np.sqrt(2))
    assert float(got.chi) == pytest.approx(1.0)
    lifted = mtos_eccentricity(x=15e-6, y=-3e-6, x_set=5e-6, y_set=-3e-6, clearance=MH0)
    assert float(lifted.e_x) == pytest.approx(MH0 / np.sqrt(2) - 10e-6)
    assert float(lifted.chi) < 1.0


@settings(max_examples=40, deadline=None)
@given(
    e_x=st.floats(min_value=1e-7, max_value=1e-4),
    e_y=st.floats(min_value=1e-7, max_value=1e-4),
)
def test_attitude_angles(e_x: float, e_y: float) -> None:
    got = mtos_attitude_angles(e_x=e_x, e_y=e_y)
    # (4.12) as printed, for positive components.
    assert float(got.delta) == pytest.approx(np.pi / 4 - np.arctan(e_x / e_y), abs=1e-12)
    assert float(got.gamma) == pytest.approx(np.pi / 4 - np.arctan(e_y / e_x), abs=1e-12)
    assert float(got.gamma) == pytest.approx(-float(got.delta), abs=1e-12)


def test_attitude_angles_edges() -> None:
    equal = mtos_attitude_angles(e_x=3e-5, e_y=3e-5)
    assert float(equal.delta) == pytest.approx(0.0, abs=1e-15)
    assert float(equal.gamma) == pytest.approx(0.0, abs=1e-15)
    # e_y = 0: arctg(e_x/e_y) = 90°, δ = -45°.
    assert float(mtos_attitude_angles(e_x=3e-5, e_y=0.0).delta) == pytest.approx(-np.pi / 4)
    with pytest.raises(ModelUndefinedError, match=r"journal centred"):
        mtos_attitude_angles(e_x=0.0, e_y=0.0)


def test_mtos_friction_chain() -> None:
    # k = 5000 N/m, Δl = 0.4 mm -> F = 2 N; l1 = 0.2 m -> M = 0.4 N·m;
    # l2 = 0.025 m -> F_tr = 16 N; N = 2000 N -> f_э = 0.008.
    got = mtos_friction(
        indicator_travel=0.4e-3, spring_rate=5000.0, spring_arm=0.2, friction_arm=0.025, load=2000.0
    )
    assert float(got.spring_force) == pytest.approx(2.0)
    assert float(got.moment) == pytest.approx(0.4)
    assert float(got.friction_force) == pytest.approx(16.0)
    assert float(got.coefficient) == pytest.approx(0.008)
    with pytest.raises(ModelInputError, match=r"load must be > 0, got 0.0"):
        mtos_friction(
            indicator_travel=0.4e-3, spring_rate=5e3, spring_arm=0.2, friction_arm=0.025, load=0.0
        )


def test_film_viscosity_is_the_mean_of_viscosities() -> None:
    got = mtos_film_viscosity(t3=50.0, t4=60.0, t5=70.0, A=A, alpha=ALPHA)
    expected = (A * np.exp(ALPHA * 50) + A * np.exp(ALPHA * 60) + A * np.exp(ALPHA * 70)) / 3
    assert float(got.mean) == pytest.approx(expected, rel=1e-12)
    assert float(got.mu4) == pytest.approx(A * np.exp(ALPHA * 60), rel=1e-12)
    # Not the viscosity at the mean temperature (exp is convex, so the mean is larger).
    assert float(got.mean) > float(viscosity(t=60.0, A=A, alpha=ALPHA)) * (1 + 1e-3)


def test_e4_temperature_rise_is_positive_when_the_oil_heats() -> None:
    # Inlet 40 °C, near the film 55 °C: a rise of +15 °C (the print t1 - t_i gives -15).
    rise = temperature_rise(t=np.array([48.0, 55.0]), t_in=40.0)
    np.testing.assert_allclose(rise, [8.0, 15.0])
    assert np.all(rise > 0)


def test_e9_bearing_characteristic_is_mu_omega_over_mean_pressure() -> None:
    mu, omega, load, width, diameter = 0.05, 100.0, 1000.0, 0.03, 0.05
    p_mean = load / (width * diameter)  # 666 666.7 Pa
    s1 = float(
        bearing_characteristic(viscosity=mu, omega=omega, load=load, width=width, diameter=diameter)
    )
    assert s1 == pytest.approx(mu * omega / p_mean, rel=1e-12)  # 7.5e-6
    assert s1 != pytest.approx(p_mean / (mu * omega), rel=0.5)  # 1.33e5, the other "S1"
    # Hersey: S1 grows with viscosity and speed, falls with load.
    more_viscous = bearing_characteristic(
        viscosity=2 * mu, omega=omega, load=load, width=width, diameter=diameter
    )
    assert float(more_viscous) == pytest.approx(2 * s1)
