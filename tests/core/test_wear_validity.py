"""rigserver.core.wear_validity: (2.1)'s own applicability figures, against an independent
sum of Hertz contacts over the bearing curve's height distribution and by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq

from rigserver.core import wear
from rigserver.core.wear_validity import MIN_CYCLES, wear_theory_validity

# The lab's data (models.md section 2): St3sp pin on an R9 disc, 300 N, f ≈ 0.4
LAB = {
    "load": 300.0,
    "pin_radius": 0.005,
    "disc_radius": 0.0225,
    "friction_coefficient": 0.4,
    "ra_disc": 0.5e-6,
    "youngs_modulus": 2.13e11,
    "poisson": 0.3,
    "hardness": 1.24e9,
    "yield_strength": 2.25e8,
    "tensile_strength": 4.2e8,
    "elongation": 0.23,
    "fatigue_t": 3.0,
}


def _validity(data: dict[str, float], nu: float = 2.0, b: float = 2.0) -> object:
    theory = wear.wear_intensity_theoretical(**data, nu=nu, b=b)
    return theory, wear_theory_validity(
        theory=theory,
        friction_coefficient=data["friction_coefficient"],
        poisson=data["poisson"],
        hardness=data["hardness"],
        yield_strength=data["yield_strength"],
        fatigue_strength=data["tensile_strength"],
        fatigue_t=data["fatigue_t"],
        b=b,
        nu=nu,
    )


def _hertz_sum(p_c: float, e_star: float, radius: float, rmax: float, nu: float, b: float):
    """Independent: summits of radius R with heights u (depth below the peak line, as a share
    of Rmax) of density n(u) = b ν(ν-1) u^(ν-2)/(2π R Rmax) per unit area (so that the cut
    area is b ε^ν); each pressed by Rmax(ε - u) carries (4/3)E*√R δ^(3/2) on πRδ."""

    def density(u: float) -> float:
        return b * nu * (nu - 1.0) * u ** (nu - 2.0) / (2.0 * math.pi * radius * rmax)

    def load(eps: float) -> float:
        def one(u: float) -> float:
            return 4.0 / 3.0 * e_star * math.sqrt(radius) * (rmax * (eps - u)) ** 1.5 * density(u)

        return quad(one, 0.0, eps)[0]

    def area(eps: float) -> float:
        return quad(lambda u: math.pi * radius * rmax * (eps - u) * density(u), 0.0, eps)[0]

    eps = brentq(lambda e: load(e) - p_c, 1e-12, 1.0, xtol=1e-15)
    return eps, p_c / area(eps)


@settings(max_examples=20, deadline=None)
@given(
    load=st.floats(50.0, 5000.0),
    ra_um=st.floats(0.1, 3.0),
    nu=st.floats(1.5, 3.0),
    b=st.floats(1.0, 3.0),
)
def test_real_contact_pressure_is_the_sum_of_hertz_contacts(
    load: float, ra_um: float, nu: float, b: float
) -> None:
    data = {**LAB, "load": load, "ra_disc": ra_um * 1e-6}
    theory, v = _validity(data, nu=nu, b=b)
    # any R with Rmax/R fixed gives the same ε and p_r (only the ratio enters)
    radius = 1e-4
    eps, p_r = _hertz_sum(
        theory.contour_pressure, 1.0 / theory.theta, radius, theory.rmax_over_r * radius, nu, b
    )
    assert v.approach == pytest.approx(eps, rel=1e-6)
    assert v.real_contact_pressure == pytest.approx(p_r, rel=1e-6)


def test_the_lab_steel_is_outside_the_range() -> None:
    theory, v = _validity(LAB)
    # by hand (ν = b = 2): Δ = (0.5/4.3)², Rmax/R = √2 Δ, k_ν = Γ(3)/(2√π Γ(3.5)),
    # ε = (p_c θ/(b k_ν √(Rmax/R)))^(2/5), p_r = 2 p_c/(b ε²)
    delta = (0.5 / 4.3) ** 2
    k_nu = 2.0 / (2.0 * math.sqrt(math.pi) * math.gamma(3.5))
    p_c = 300.0 / (math.pi * 0.005**2)
    theta = (1 - 0.3**2) / 2.13e11
    eps = (p_c * theta / (2.0 * k_nu * math.sqrt(math.sqrt(2.0) * delta))) ** 0.4
    p_r = 2.0 * p_c / (2.0 * eps**2)
    k_f = 2.0 / math.pi * math.sqrt(4 * 0.16 * (1 - 0.3 + 0.09) + 1 - 0.6)
    n = (4.2e8 / (k_f * p_r)) ** 3
    assert theory.contact == "elastic"  # p_c = 3.8 MPa <= HB: (2.7) sees elastic contact
    assert v.real_contact_pressure == pytest.approx(p_r, rel=1e-12)
    assert v.real_contact_pressure > 1.24e9  # but the asperities are plastic
    assert v.cycles_to_failure == pytest.approx(n, rel=1e-12)
    assert v.cycles_to_failure < 1.0
    assert v.plastic_k_f is None  # σ_T = 225 MPa <= 2f·HB = 992 MPa
    assert not v.within_range and len(v.reasons) == 3
    assert v.reasons == ("plastic_asperities", "few_cycles", "no_plastic_k_f")
    # σ_T = 225 MPa <= 2f·HB = 2·0.4·1240 MPa = 992 MPa: k_f^n undefined
    assert v.plastic_k_f is None


def test_a_smooth_light_soft_contact_is_inside_the_range() -> None:
    # a polymer-like pin (E = 3 GPa, HB = 150 MPa, σ_B = 60 MPa, t = 5) on a polished disc
    # (Ra 0.05 μm) at 20 N: p_r ≈ 7 MPa < HB and n = (σ_B/(k_f p_r))^t ≈ 4e6 >= 10
    data = {
        **LAB,
        "load": 20.0,
        "ra_disc": 0.05e-6,
        "youngs_modulus": 3e9,
        "poisson": 0.35,
        "hardness": 1.5e8,
        "yield_strength": 4e7,
        "tensile_strength": 6e7,
        "friction_coefficient": 0.2,
        "fatigue_t": 5.0,
    }
    theory, v = _validity(data)
    k_f = wear.elastic_fatigue_factor(friction_coefficient=0.2, poisson=0.35)
    assert v.cycles_to_failure == pytest.approx((6e7 / (k_f * v.real_contact_pressure)) ** 5)
    assert v.real_contact_pressure < 1.5e8 and v.cycles_to_failure >= MIN_CYCLES
    assert v.within_range and v.reasons == ()
    # σ_T = 40 MPa <= 2f·HB = 60 MPa leaves k_f^n undefined; the elastic branch applies and
    # does not need it
    assert v.plastic_k_f is None and theory.contact == "elastic"


def test_plastic_branch_needs_k_f_n() -> None:
    # p_c above HB: (2.7) picks the plastic branch, which is outside its range without k_f^n
    data = {**LAB, "load": 5000.0, "pin_radius": 0.001, "hardness": 1.0e9}
    with pytest.raises(wear.ModelUndefinedError):
        wear.wear_intensity_theoretical(**data)
    low_f = {**data, "friction_coefficient": 0.05}  # 2f·HB = 100 MPa < σ_T = 225 MPa
    theory, v = _validity(low_f)
    assert theory.contact == "plastic"
    expected = math.sqrt(2 * (2.25e8 + 1e8) / (2.25e8 - 1e8))
    assert v.plastic_k_f == pytest.approx(expected, rel=1e-12)
    assert v.within_range


def test_k_f_n_is_none_exactly_where_sigma_t_is_at_most_2f_hb() -> None:
    for f in np.linspace(0.01, 1.0, 50):
        k = wear.plastic_fatigue_factor(
            friction_coefficient=f, yield_strength=2.25e8, hardness=1.24e9
        )
        assert (k is None) == (2 * f * 1.24e9 >= 2.25e8)
