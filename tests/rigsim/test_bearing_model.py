"""rigsim.bearing_model: both models against closed forms and independent integrals."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from rigserver.core import bearing
from rigsim.bearing_model import Film, Geometry, film
from rigsim.errors import SettingsError

# The MTOS stand of the simulator: D = B = 50 mm, h0 = 30 μm
MTOS = Geometry(radius=0.025, width=0.050, clearance=30e-6)
# The slide-bearing stand of the manual: R2 = 25.175 mm, B = 29.7 mm, h0 = 175 μm (3.17-3.19)
SLIDE = Geometry(radius=25.175e-3, width=29.7e-3, clearance=175e-6)


def _film_force(state: Film, g: Geometry) -> float:
    """|∫∫ p (cos φ, sin φ) R dφ R dz| over the film, by the trapezoid rule (independent of
    the solvers' own integrals)."""
    a = g.width / (2.0 * g.radius)
    phi = np.linspace(0.0, 2.0 * np.pi, 1441)
    z = np.linspace(-a, a, 161)
    p = state.pressure(phi=phi[:, None], z=z[None, :])
    along_z = np.trapezoid(p, z, axis=1) * g.radius
    fx = np.trapezoid(along_z * np.cos(phi), phi) * g.radius
    fy = np.trapezoid(along_z * np.sin(phi), phi) * g.radius
    return float(np.hypot(fx, fy))


def test_short_model_balances_the_load_with_ocvirks_force() -> None:
    state = film(model="short", load=1500.0, omega=52.4, viscosity=0.02, geometry=MTOS)
    force = bearing.short_bearing_load(
        chi=state.chi, omega=52.4, viscosity=0.02, bearing_radius=0.025, width=0.05, clearance=30e-6
    )
    assert float(force.resultant) == pytest.approx(1500.0, rel=1e-9)
    assert state.attitude_angle == pytest.approx(float(force.attitude_angle), rel=1e-12)


def test_short_model_friction_is_the_ruptured_film_integral() -> None:
    mu, omega, g = 0.02, 52.4, MTOS
    state = film(model="short", load=1500.0, omega=omega, viscosity=mu, geometry=g)
    chi = state.chi
    r1 = g.journal_radius

    # Couette stress μωR1/h over the full film (π..2π) and over the striated film fraction
    # θ = h(0)/h(φ) in the ruptured zone (0..π), times the arm R1 and the width B
    def stress(phi: float) -> float:
        h = g.clearance * (1.0 - chi * np.cos(phi))
        share = 1.0 if phi >= np.pi else (1.0 - chi) / (1.0 - chi * np.cos(phi))
        return float(mu * omega * r1 / h * share)

    shear = quad(stress, 0.0, 2.0 * np.pi, points=[np.pi], epsabs=0, epsrel=1e-12)[0]
    shear *= r1 * r1 * g.width
    pressure_term = bearing.friction_moment_theoretical(
        chi=chi, omega=omega, viscosity=mu, bearing_radius=0.025, width=0.05, clearance=30e-6
    ).pressure_term
    assert state.friction_moment == pytest.approx(shear + float(pressure_term), rel=1e-9)


def test_short_model_friction_tends_to_petroff_at_light_load() -> None:
    # χ -> 0: no rupture, M = 2π μ ω R1³ B / h0 (Petroff)
    g = MTOS
    state = film(model="short", load=0.01, omega=52.4, viscosity=0.02, geometry=g)
    petroff = 2.0 * np.pi * 0.02 * 52.4 * g.journal_radius**3 * g.width / g.clearance
    assert state.chi < 1e-4
    assert state.friction_moment == pytest.approx(petroff, rel=1e-3)


def test_short_model_pressure_lies_below_both_asymptotes() -> None:
    state = film(model="short", load=324.0, omega=329.0, viscosity=0.027, geometry=SLIDE)
    a = SLIDE.width / (2.0 * SLIDE.radius)
    phi = np.radians(np.arange(190.0, 360.0, 10.0))
    p = state.pressure(phi=phi, z=0.0) / state.pressure_scale
    short = bearing.short_bearing_pressure(phi=phi, z=0.0, chi=state.chi, a=a, mu_bar=1, G=1)
    long = bearing.long_bearing_pressure(phi=phi, chi=state.chi, mu_bar=1, G=1)
    assert np.all(p > 0.0)
    assert np.all(p < short) and np.all(p < long)
    # no pressure at the edges z = ±a and in the diverging film 0 < φ < π
    assert np.all(state.pressure(phi=phi, z=a) == 0.0)
    assert np.all(state.pressure(phi=np.radians([10.0, 90.0, 170.0]), z=0.0) == 0.0)


@pytest.mark.parametrize(
    ("load", "omega", "viscosity", "g"), [(1500.0, 52.4, 0.02, MTOS), (324.0, 329.0, 0.027, SLIDE)]
)
def test_finite_model_pressure_carries_the_load(
    load: float, omega: float, viscosity: float, g: Geometry
) -> None:
    state = film(model="finite", load=load, omega=omega, viscosity=viscosity, geometry=g)
    # the pressure field in Pa, integrated here, carries the load to the grid's accuracy
    assert _film_force(state, g) == pytest.approx(load, rel=0.02)
    assert 0.0 < state.chi < 1.0
    assert 0.0 < state.attitude_angle < np.pi / 2.0


def test_finite_model_friction_tends_to_petroff_at_light_load() -> None:
    # χ -> 0: the film is full and M = 2π μ ω R³ B / h0 (the solver's radius is R)
    g = MTOS
    state = film(model="finite", load=1.0, omega=52.4, viscosity=0.02, geometry=g)
    petroff = 2.0 * np.pi * 0.02 * 52.4 * g.radius**3 * g.width / g.clearance
    assert state.chi < 0.01
    assert state.friction_moment == pytest.approx(petroff, rel=2e-3)


def test_finite_bearing_sinks_deeper_than_ocvirks() -> None:
    # Ocvirk's short-bearing force over-estimates a B/D = 1 bearing's capacity
    short = film(model="short", load=1500.0, omega=52.4, viscosity=0.02, geometry=MTOS)
    finite = film(model="finite", load=1500.0, omega=52.4, viscosity=0.02, geometry=MTOS)
    assert finite.chi > short.chi


def test_bad_model_and_overload_are_refused() -> None:
    with pytest.raises(SettingsError, match="bearing model must be one of"):
        film(model="long", load=1.0, omega=1.0, viscosity=1.0, geometry=MTOS)  # type: ignore[arg-type]
    with pytest.raises(SettingsError, match="finite-length film cannot carry 1e\\+08 N"):
        film(model="finite", load=1e8, omega=52.4, viscosity=0.02, geometry=MTOS)
    with pytest.raises(SettingsError, match="clearance must be < radius"):
        Geometry(radius=0.01, width=0.01, clearance=0.02)
