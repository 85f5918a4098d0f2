"""Lab work 2 (SMTs-2): friction coefficient, experimental and theoretical wear intensity.

Sources of the numbers: the lab manual, lab work 2 (equations (2.1)-(2.16), table 2.2,
item 18 of the procedure), table 1.1 of lab work 1, and ``docs/models.md`` section 2 with
corrections E1 and E2.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rigserver.core.errors import ModelInputError, ModelUndefinedError
from rigserver.core.wear import (
    STEEL_DENSITY,
    TheoreticalWear,
    adhesive_oxidative_difference,
    friction_coefficient,
    sliding_distance,
    steady_friction,
    wear_adequacy,
    wear_intensity_experimental,
    wear_intensity_theoretical,
    wear_track_area,
)

# Item 18 a) and table 2.2 (pin: steel VSt3ps / St3sp), "Equipment and specimens" (geometry).
E1 = 2.13e11  # Pa (2.13e5 MPa)
MU1 = 0.3
HB1 = 1240e6  # Pa
SIGMA_T = 225e6  # Pa
SIGMA_B = 420e6  # Pa
E_B = 0.23  # δ = 23 %
R1 = 5e-3  # m, d1 = 10 mm
R2 = 22.5e-3  # m
LOAD = 300.0  # N, item 7 of the procedure
T_ELASTIC = 3.0  # item 18 a)
T_PLASTIC = 1.3  # item 18 a)
# The manual gives no Ra for the R9 disc; table 1.1's closest run-in steel surface that
# slides dry is the 30KhGSA brake disc, Ra = 0.78 μm.
RA_DISC = 0.78e-6  # m
# A typical run: M_tr = 2.7 N·m on the chart at 300 N gives f = 2.7/(300·0.0225) = 0.4.
F_RUN = 0.4


def lab_theory(**changes: Any) -> TheoreticalWear:
    """The item-18 calculation, with some arguments changed."""
    args: dict[str, Any] = {
        "load": LOAD,
        "pin_radius": R1,
        "disc_radius": R2,
        "friction_coefficient": F_RUN,
        "ra_disc": RA_DISC,
        "youngs_modulus": E1,
        "poisson": MU1,
        "hardness": HB1,
        "yield_strength": SIGMA_T,
        "tensile_strength": SIGMA_B,
        "elongation": E_B,
        "fatigue_t": T_ELASTIC,
    }
    args.update(changes)
    return wear_intensity_theoretical(**args)


def kragelsky_by_hand(
    *, N: float, r1: float, r2: float, f: float, ra_um: float, t: float, plastic: bool
) -> float:
    """(2.1)-(2.6) written out again, ν = b_ν = 2, for the lab's pin data."""
    nu, b = 2.0, 2.0
    C = (
        math.sqrt(nu)
        * math.gamma(nu)
        * math.gamma(1 + t / 2)
        / (4 * (nu + 1) * math.gamma(nu + t / 2))
    )
    beta = 1 / (1 + 2 * nu)
    theta = (1 - MU1**2) / E1
    k_nu = math.gamma(nu + 1) / (2 * math.sqrt(math.pi) * math.gamma(nu + 1.5))
    Ac = math.pi * r1**2
    eta = Ac / (4 * math.pi * r2 * r1)
    pc = N / Ac
    delta = (ra_um / 4.3) ** 2  # (1.10) inverted: (2.6) as corrected by E2
    rr = delta * b ** (1 / nu)
    intensity: float
    if not plastic:
        kf = 2 / math.pi * math.sqrt(4 * f**2 * (1 - MU1 + MU1**2) + 1 - 2 * MU1)
        intensity = (
            C
            * (pc * theta / k_nu) ** (1 + beta * t)
            * (kf / (SIGMA_B * theta)) ** t
            * rr ** (t * (1 + beta) / 2)
            * (eta * b) ** (-beta * t)
        )
        return intensity
    kf = math.sqrt(2 * (SIGMA_T + 2 * f * HB1) / (SIGMA_T - 2 * f * HB1))
    intensity = (
        C
        * math.sqrt(2)
        * (pc / HB1) ** ((1 + beta * t) / (1 - beta))
        * (kf / E_B) ** t
        * rr ** ((1 + t) / 2)
        * (eta * b) ** (beta * (1 + t) / (1 - beta))
    )
    return intensity


# --- friction coefficient (2.8) and its steady mean ---------------------------------------


def test_friction_coefficient_of_a_typical_chart_reading() -> None:
    # 2.7 N·m at 300 N on r2 = 22.5 mm: f = 2.7/(300·0.0225) = 0.4.
    assert friction_coefficient(friction_moment=2.7, load=300.0, radius=R2) == pytest.approx(0.4)


def test_friction_coefficient_keeps_the_shape_of_a_series() -> None:
    moments = np.array([[0.0, 1.5], [6.75, 13.5]])  # N·m
    f = friction_coefficient(friction_moment=moments, load=300.0, radius=R2)
    assert f.shape == (2, 2)
    # 300 N · 0.0225 m = 6.75 N·m per unit f.
    np.testing.assert_allclose(f, [[0.0, 1.5 / 6.75], [1.0, 2.0]], rtol=1e-15)


positive_values = st.floats(min_value=1e-3, max_value=1e3)


@settings(max_examples=50)
@given(m=positive_values, n=positive_values, r=positive_values, k=st.floats(0.1, 10.0))
def test_friction_coefficient_is_linear_in_moment_inverse_in_load_and_radius(
    m: float, n: float, r: float, k: float
) -> None:
    f = friction_coefficient(friction_moment=m, load=n, radius=r)
    assert friction_coefficient(friction_moment=k * m, load=n, radius=r) == pytest.approx(k * f)
    assert friction_coefficient(friction_moment=m, load=k * n, radius=r) == pytest.approx(f / k)
    assert friction_coefficient(friction_moment=m, load=n, radius=k * r) == pytest.approx(f / k)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"friction_moment": -0.1, "load": 300.0, "radius": R2}, "friction_moment must be >= 0"),
        ({"friction_moment": 2.0, "load": 0.0, "radius": R2}, "load must be > 0"),
        ({"friction_moment": 2.0, "load": 300.0, "radius": -R2}, "radius must be > 0"),
        ({"friction_moment": [2.0, np.nan], "load": 300.0, "radius": R2}, "must be finite"),
    ],
)
def test_friction_coefficient_refuses_bad_input(kwargs: dict[str, Any], match: str) -> None:
    with pytest.raises(ModelInputError, match=match):
        friction_coefficient(**kwargs)


def test_steady_friction_is_the_mean_of_the_last_half() -> None:
    # Running-in from 0.6 down to 0.3, then 0.3 and 0.5 alternating: the last half
    # (samples 4..7) has mean 0.4 and population standard deviation 0.1.
    f = [0.6, 0.5, 0.4, 0.3, 0.3, 0.5, 0.3, 0.5]
    s = steady_friction(f=f)
    assert (s.start, s.count) == (4, 4)
    assert s.mean == pytest.approx(0.4)
    assert s.std == pytest.approx(0.1)


def test_steady_friction_window_of_an_odd_series_and_of_the_whole_series() -> None:
    # n = 5, fraction 0.5: floor(5·0.5) = 2 samples of running-in, 3 steady ones.
    s = steady_friction(f=[1.0, 1.0, 0.2, 0.3, 0.4])
    assert (s.start, s.count) == (2, 3)
    assert s.mean == pytest.approx(0.3)
    whole = steady_friction(f=[0.2, 0.4], fraction=1.0)
    assert (whole.start, whole.count) == (0, 2)
    assert whole.mean == pytest.approx(0.3)


def test_steady_friction_keeps_at_least_one_sample() -> None:
    s = steady_friction(f=[0.5, 0.25], fraction=1e-18)
    assert (s.start, s.count, s.mean) == (1, 1, 0.25)


@pytest.mark.parametrize(
    ("f", "fraction", "match"),
    [
        ([], 0.5, "non-empty one-dimensional"),
        ([[0.3, 0.3]], 0.5, "non-empty one-dimensional"),
        ([0.3, -0.1], 0.5, "f must be >= 0"),
        ([0.3], 0.0, r"fraction must lie in \(0.0, 1.0\]"),
        ([0.3], 1.5, r"fraction must lie in \(0.0, 1.0\]"),
    ],
)
def test_steady_friction_refuses_bad_input(f: Any, fraction: float, match: str) -> None:
    with pytest.raises(ModelInputError, match=match):
        steady_friction(f=f, fraction=fraction)


# --- experimental wear intensity (2.9)-(2.13) --------------------------------------------


def test_experimental_intensity_of_a_typical_run() -> None:
    # 30 mg off a 10 mm steel pin over 15 000 revolutions of the 22.5 mm disc.
    m1 = 12.0e-3  # kg
    m2 = m1 - 30e-6
    dm = m1 - m2  # (2.9)
    V = dm / 7800.0  # (2.10)
    h = V / (math.pi * 0.005**2)  # (2.11)
    L = 2 * math.pi * 0.0225 * 15_000  # (2.12) = 2120.6 m
    w = wear_intensity_experimental(
        mass_before=m1,
        mass_after=m2,
        density=STEEL_DENSITY,
        pin_radius=R1,
        disc_radius=R2,
        revolutions=15_000,
    )
    assert w.mass_loss == pytest.approx(dm, rel=1e-12)
    assert w.volume == pytest.approx(V, rel=1e-12)
    assert w.wear_depth == pytest.approx(h, rel=1e-12)
    assert w.sliding_distance == pytest.approx(L, rel=1e-12)
    assert w.intensity == pytest.approx(h / L, rel=1e-12)  # (2.13)
    assert 1e-8 <= w.intensity <= 1e-7  # the magnitude models.md reports for such runs


def test_equal_masses_mean_zero_wear() -> None:
    w = wear_intensity_experimental(
        mass_before=0.012, mass_after=0.012, density=7800.0,
        pin_radius=R1, disc_radius=R2, revolutions=15_000,
    )  # fmt: skip
    assert (w.mass_loss, w.volume, w.wear_depth, w.intensity) == (0.0, 0.0, 0.0, 0.0)


@settings(max_examples=50)
@given(dm=st.floats(1e-7, 1e-3), k=st.floats(0.01, 10.0))
def test_experimental_intensity_is_linear_in_mass_loss(dm: float, k: float) -> None:
    def intensity(loss: float) -> float:
        m1 = 0.05
        return wear_intensity_experimental(
            mass_before=m1, mass_after=m1 - loss, density=7800.0,
            pin_radius=R1, disc_radius=R2, revolutions=15_000,
        ).intensity  # fmt: skip

    # I_h = Δm/(ρ·π r1²·2π r2 M); the subtraction m1 - Δm rounds at 1e-17 kg.
    assert intensity(k * dm) == pytest.approx(k * intensity(dm), rel=1e-9)


def test_mass_gain_is_refused() -> None:
    with pytest.raises(ModelInputError, match=r"mass_after = 0.0121 kg exceeds mass_before"):
        wear_intensity_experimental(
            mass_before=0.012, mass_after=0.0121, density=7800.0,
            pin_radius=R1, disc_radius=R2, revolutions=15_000,
        )  # fmt: skip


@pytest.mark.parametrize(
    "name", ["mass_before", "mass_after", "density", "pin_radius", "disc_radius", "revolutions"]
)
@pytest.mark.parametrize("bad", [0.0, -1.0])
def test_experimental_refuses_non_positive_input(name: str, bad: float) -> None:
    args = {
        "mass_before": 0.012, "mass_after": 0.0119, "density": 7800.0,
        "pin_radius": R1, "disc_radius": R2, "revolutions": 15_000.0,
    }  # fmt: skip
    args[name] = bad
    with pytest.raises(ModelInputError, match=f"{name} must be > 0, got {bad}"):
        wear_intensity_experimental(**args)


# --- theoretical wear intensity (2.1)-(2.7) ----------------------------------------------


@pytest.mark.parametrize("t", [1.3, 2.0, 3.0, 5.0, 11.0, 20.0])
def test_E1_C_at_nu_2_is_0118_over_1_plus_half_t(t: float) -> None:
    # E1: with ν = 2, C = √2/12 · Γ(1+t/2)/Γ(2+t/2) = 0.118/(1 + t/2); the printed (2.2)
    # 0.118·(1 + t/2) is larger by (1 + t/2)², a factor 2.7 already at t = 1.3.
    c = lab_theory(fatigue_t=t).C
    assert c == pytest.approx(0.118 / (1 + t / 2), rel=2e-3)


def test_E1_other_coefficients_at_nu_2_b_2() -> None:
    r = lab_theory()
    # (2.2): k_ν = 0.17 (lab 1's Γ(3)/Γ(3.5) = 0.60 lacks the 1/(2√π)), β = 1/5.
    assert r.k_nu == pytest.approx(0.17, abs=5e-4)
    assert r.beta == pytest.approx(0.2, rel=1e-15)
    # Rmax/R = Δ·b^(1/ν) = √2·Δ.
    assert r.rmax_over_r == pytest.approx(math.sqrt(2) * r.complex_parameter, rel=1e-15)


@pytest.mark.parametrize("ra_um", [0.1, 0.3, 0.78, 2.0])
def test_E2_complex_parameter_is_quadratic_in_ra(ra_um: float) -> None:
    # E2: Δ = 5.4e-2·Ra² (Ra in μm); 1/4.3² = 0.05408, hence rel 2e-3. The printed
    # 5.4e-2·Ra is off by a factor 1/Ra (10 at Ra = 0.1 μm, 2 at Ra = 2 μm).
    r = lab_theory(ra_disc=ra_um * 1e-6)
    assert r.complex_parameter == pytest.approx(5.4e-2 * ra_um**2, rel=2e-3)


def test_item_18_st3sp_pin_on_r9_disc_at_300_N() -> None:
    r = lab_theory()
    # (2.3)-(2.5): A_c = π·25e-6 m², p_c = 300/A_c = 3.82 MPa, η_c = r1/(4 r2) = 1/18.
    assert r.contour_area == pytest.approx(math.pi * 25e-6, rel=1e-15)
    assert r.nominal_area == pytest.approx(4 * math.pi * 0.0225 * 0.005, rel=1e-15)
    assert r.contour_pressure == pytest.approx(300 / (math.pi * 25e-6), rel=1e-15)
    assert r.eta_c == pytest.approx(1 / 18, rel=1e-15)
    assert r.theta == pytest.approx(0.91 / 2.13e11, rel=1e-15)
    # (2.7): 3.82 MPa <= HB1 = 1240 MPa, elastic; k_f^y of f = 0.4, μ = 0.3.
    assert r.contact == "elastic"
    assert r.k_f == pytest.approx(2 / math.pi * math.sqrt(0.64 * 0.79 + 0.4), rel=1e-14)
    expected = kragelsky_by_hand(
        N=LOAD, r1=R1, r2=R2, f=F_RUN, ra_um=0.78, t=T_ELASTIC, plastic=False
    )
    assert r.intensity == pytest.approx(expected, rel=1e-12)


def test_plastic_branch_against_the_hand_computation() -> None:
    # A 0.2 mm pin at 300 N: p_c = 300/(π·4e-8) = 2.39 GPa > HB1, plastic; f = 0.05 keeps
    # σ_T = 225 MPa above 2f·HB1 = 124 MPa.
    r = lab_theory(pin_radius=0.2e-3, friction_coefficient=0.05, fatigue_t=T_PLASTIC)
    assert r.contact == "plastic"
    assert r.k_f == pytest.approx(math.sqrt(2 * (225 + 124) / (225 - 124)), rel=1e-14)
    expected = kragelsky_by_hand(
        N=LOAD, r1=0.2e-3, r2=R2, f=0.05, ra_um=0.78, t=T_PLASTIC, plastic=True
    )
    assert r.intensity == pytest.approx(expected, rel=1e-12)


def test_contact_is_elastic_up_to_and_including_p_c_equal_to_HB() -> None:
    pc = LOAD / (math.pi * R1**2)  # (2.3)-(2.4), same operations as the model
    assert lab_theory(hardness=pc).contact == "elastic"
    below = float(np.nextafter(pc, 0.0))
    plastic = lab_theory(hardness=below, friction_coefficient=1e-3, yield_strength=SIGMA_B)
    assert plastic.contact == "plastic"


def test_plastic_contact_with_sigma_t_below_2f_hb_is_undefined() -> None:
    # St3sp with f = 0.4: 2f·HB1 = 992 MPa > σ_T = 225 MPa, so k_f^n has no real value.
    with pytest.raises(
        ModelUndefinedError, match=r"σ_T = yield_strength = 225000000.0 Pa <= 2f·HB"
    ):
        lab_theory(pin_radius=0.2e-3, fatigue_t=T_PLASTIC)


def test_sigma_t_below_2f_hb_does_not_matter_in_elastic_contact() -> None:
    # k_f^n is not used in elastic contact: the item-18 case has 2f·HB1 > σ_T too.
    assert lab_theory().contact == "elastic"


@pytest.mark.parametrize(
    ("pin_radius", "f", "t", "loads", "mode"),
    [
        (R1, F_RUN, T_ELASTIC, (1.0, 9.0e4), "elastic"),  # p_c <= HB1 below 97 kN
        (0.2e-3, 0.05, T_PLASTIC, (200.0, 5000.0), "plastic"),  # above 156 N
    ],
)
@settings(max_examples=30)
@given(u=st.floats(0.0, 1.0), v=st.floats(0.0, 1.0))
def test_theoretical_intensity_grows_with_load_within_one_contact_mode(
    pin_radius: float, f: float, t: float, loads: tuple[float, float], mode: str, u: float, v: float
) -> None:
    lo, hi = loads
    n1, n2 = sorted((lo + u * (hi - lo), lo + v * (hi - lo)))
    a = lab_theory(load=n1, pin_radius=pin_radius, friction_coefficient=f, fatigue_t=t)
    b = lab_theory(load=n2, pin_radius=pin_radius, friction_coefficient=f, fatigue_t=t)
    assert a.contact == b.contact == mode
    assert a.intensity <= b.intensity


@pytest.mark.parametrize(
    "name",
    [
        "load", "pin_radius", "disc_radius", "friction_coefficient", "ra_disc",
        "youngs_modulus", "hardness", "yield_strength", "tensile_strength", "fatigue_t",
        "nu", "b",
    ],
)  # fmt: skip
@pytest.mark.parametrize("bad", [0.0, -2.0])
def test_theoretical_refuses_non_positive_input(name: str, bad: float) -> None:
    with pytest.raises(ModelInputError, match=f"{name} must be > 0, got {bad}"):
        lab_theory(**{name: bad})


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"poisson": 0.6}, r"poisson must lie in \[0.0, 0.5\], got 0.6"),
        ({"elongation": 23.0}, r"elongation must lie in \(0.0, 1.0\], got 23.0"),
        ({"elongation": 0.0}, r"elongation must lie in \(0.0, 1.0\]"),
        ({"yield_strength": 500e6}, "yield_strength = 500000000.0 Pa exceeds tensile_strength"),
        ({"pin_radius": 0.1}, r"pin_radius = 0.1 m exceeds 4·disc_radius = 0.09 m"),
        ({"load": math.inf}, "load must be finite"),
    ],
)
def test_theoretical_refuses_inputs_outside_the_model(changes: dict[str, Any], match: str) -> None:
    with pytest.raises(ModelInputError, match=match):
        lab_theory(**changes)


# --- adequacy (2.14)-(2.15) and adhesive vs oxidative friction (2.16) --------------------


def test_adequacy_band_edges_are_inclusive() -> None:
    # (2.15): 0.4·I_theor <= I_exp <= 2.6·I_theor; I_theor = 1e-8.
    i_t = 1e-8
    for inside in (0.4 * i_t, 2.6 * i_t):
        assert wear_adequacy(i_exp=inside, i_theor=i_t).adequate
    assert not wear_adequacy(i_exp=float(np.nextafter(0.4 * i_t, 0.0)), i_theor=i_t).adequate
    assert not wear_adequacy(i_exp=float(np.nextafter(2.6 * i_t, 1.0)), i_theor=i_t).adequate
    a = wear_adequacy(i_exp=2e-8, i_theor=i_t)
    assert a.lower == pytest.approx(0.4e-8)
    assert a.upper == pytest.approx(2.6e-8)


def test_adequacy_relative_error() -> None:
    # (2.14): (2e-8 - 1e-8)/2e-8 = +50 %; a theory 4 times too high gives -300 %.
    assert wear_adequacy(i_exp=2e-8, i_theor=1e-8).relative_error_percent == pytest.approx(50.0)
    far = wear_adequacy(i_exp=1e-8, i_theor=4e-8)
    assert far.relative_error_percent == pytest.approx(-300.0)
    assert not far.adequate


def test_adequacy_without_measured_wear_is_undefined() -> None:
    with pytest.raises(ModelUndefinedError, match="i_exp = 0"):
        wear_adequacy(i_exp=0.0, i_theor=1e-8)
    with pytest.raises(ModelInputError, match="i_theor must be > 0"):
        wear_adequacy(i_exp=1e-8, i_theor=0.0)


def test_adhesive_oxidative_difference_sign() -> None:
    # (2.16): (0.5 - 0.3)/0.5 = +40 % when adhesive friction is higher, negative otherwise.
    assert adhesive_oxidative_difference(f_adhesive=0.5, f_oxidative=0.3) == pytest.approx(40.0)
    assert adhesive_oxidative_difference(f_adhesive=0.3, f_oxidative=0.6) == pytest.approx(-100.0)
    with pytest.raises(ModelInputError, match="f_adhesive must be > 0"):
        adhesive_oxidative_difference(f_adhesive=0.0, f_oxidative=0.3)


def test_sliding_distance_is_2_12() -> None:
    # (2.12): L = 2π r2 M_rev; the lab's 15 000 rev on r2 = 22.5 mm
    assert float(sliding_distance(disc_radius=0.0225, revolutions=15_000)) == pytest.approx(
        2 * math.pi * 0.0225 * 15_000, rel=1e-15
    )
    with pytest.raises(ModelInputError, match="revolutions"):
        sliding_distance(disc_radius=0.0225, revolutions=-1.0)


def test_wear_track_area_of_a_parabolic_groove_on_a_tilted_surface() -> None:
    # y = tilt·x - d0(1 - ((x - c)/w)²) inside |x - c| < w: the groove's area is 4/3·d0·w
    # exactly (Simpson); the trapezoid rule on 4001 samples errs by O(h²)
    x = np.linspace(0.0, 4e-3, 4001)
    c, w, d0 = 2e-3, 1e-3, 5e-6
    groove = np.where(np.abs(x - c) < w, d0 * (1.0 - ((x - c) / w) ** 2), 0.0)
    y = 2e-3 * x + 1e-6 - groove
    assert wear_track_area(x=x, y=y) == pytest.approx(4.0 / 3.0 * d0 * w, rel=1e-5)
    with pytest.raises(ModelInputError, match="x increasing"):
        wear_track_area(x=x[::-1], y=y)
