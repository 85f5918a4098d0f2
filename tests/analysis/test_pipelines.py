"""Each stand's pipeline against numbers computed by hand from the manual's formulas."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rigserver.analysis import analyse, smts2
from schemas.stands import StandKind
from tests.analysis.conftest import FakeReadings, make_run, mtos_on_the_diagonal

AT = 98_066.5  # Pa per technical atmosphere


def test_smts2_streaming_equals_one_pass() -> None:
    """Chunked statistics give the same steady f as the whole series at once (2.8)."""
    rng = np.random.default_rng(1)
    n = 2_001
    moment = 2.7 + 0.1 * rng.standard_normal(n)
    cols = {
        "time": list(np.arange(n) * 0.1),
        "load": [300.0] * n,
        "speed": [1000.0] * n,
        "friction_moment": list(moment),
        "revolutions": list(np.arange(n) * 0.1),
    }
    readings = FakeReadings({"friction": cols}, {})
    one = smts2.analyse(make_run(StandKind.SMTS2), readings)
    f = moment / (300 * 0.0225)
    start = math.floor(n * 0.5)
    assert one.friction_steady == pytest.approx(f[start:].mean(), rel=1e-12)
    assert one.friction_steady_std == pytest.approx(f[start:].std(), rel=1e-9)
    chunked = readings.iter_chunks
    readings.iter_chunks = lambda g, c=None, rows=1 << 20: chunked(g, c, rows=97)  # type: ignore[method-assign]
    two = smts2.analyse(make_run(StandKind.SMTS2), readings)
    assert two.friction_steady == pytest.approx(one.friction_steady, rel=1e-12)
    assert len(two.friction.x) == 1000


def test_slide_bearing_tables_by_hand() -> None:
    h0, R, B, scale = 175e-6, 25.175e-3, 29.7e-3, 1e-6
    e_x = np.array([60e-6, 70e-6, 80e-6])
    e_y = np.array([50e-6, 45e-6, 40e-6])
    x0, y0 = 500.0, 400.0
    # (3.16): e_x = h0 - |X_уст - X|  ->  X = X_уст - (h0 - e_x)/scale
    x = x0 - (h0 - e_x) / scale
    y = y0 - (h0 - e_y) / scale
    p_centre = np.array([0.5, 1.2, 0.8])  # at
    rows = {
        "limb_angle": [100.0, 110.0, 120.0],
        "p1": [0.1, 0.3, 0.2],
        "p2": [0.3, 0.8, 0.5],
        "p3": list(p_centre),
        "p4": [0.3, 0.8, 0.5],
        "p5": [0.1, 0.3, 0.2],
        "x": list(x),
        "y": list(y),
        "t1": [30.0, 30.0, 30.0],
        "t2": [40.0, 40.0, 40.0],
    }
    m = {"x_zero": x0, "y_zero": y0, "load_zone_end": 150.0, "loader_scale": 10.0}
    res = analyse(make_run(StandKind.SLIDE_BEARING), FakeReadings({"rows": rows}, m)).values
    chi = np.hypot(e_x, e_y) / h0  # (3.17)
    assert [r.chi for r in res.table] == pytest.approx(list(chi), rel=1e-9)
    assert res.chi_mean == pytest.approx(chi.mean(), rel=1e-12)  # (3.23)
    assert res.load == pytest.approx(162.0)  # 10 mm x 16.2 N/mm
    mu0, w0 = 0.0282, 329.0
    pi_e = p_centre * AT * (h0 / R) ** 2 / (mu0 * w0)  # (3.18)-(3.19)
    assert [r.pi_measured for r in res.table] == pytest.approx(list(pi_e), rel=1e-12)
    phi_deg = 360.0 - (150.0 - np.array([100.0, 110.0, 120.0]))  # (3.20)
    assert [r.phi_model for r in res.table] == pytest.approx(list(phi_deg))
    mu_bar = 0.0773 * math.exp(-0.0485 * 35.0) / mu0  # (3.21)-(3.22), t = (t1+t2)/2
    a, c = B / (2 * R), chi.mean()
    phi = np.radians(phi_deg)
    pi0 = -3 * mu_bar * a**2 * c * np.sin(phi) / (1 - c * np.cos(phi)) ** 3  # (3.10), z = 0, G = 1
    assert [r.pi_short for r in res.table] == pytest.approx(list(pi0), rel=1e-9)
    err = (pi0 - pi_e) / pi0 * 100
    assert [r.error_short for r in res.table] == pytest.approx(list(err), rel=1e-9)
    assert res.phi_max == pytest.approx(phi_deg[1])
    assert [p.z for p in res.axial] == pytest.approx([-0.394, -0.197, 0.0, 0.197, 0.394])
    assert res.axial[2].pressure == pytest.approx(1.2 * AT)


def test_mtos_tables_by_hand() -> None:
    h0, k, l1, l2, D, B, w = 100e-6, 20e3, 0.20, 0.025, 0.050, 0.040, 157.0
    loads = np.array([500.0, 1000.0])
    dl = np.array([0.05, 0.08])  # mm
    x0 = 0.0
    e = np.array([30e-6, 40e-6])
    # (4.11): e_x = h0·cos45° - |X_уст - X|; put the journal on the diagonal (e_x = e_y)
    ex = e / math.sqrt(2)
    x = x0 - (h0 * math.cos(math.pi / 4) - ex) * 1e6  # μm
    temperatures = {
        "t1": [30.0, 30.0],
        "t2": [35.0, 38.0],
        "t3": [40.0, 45.0],
        "t4": [41.0, 46.0],
        "t5": [42.0, 47.0],
    }
    res = mtos_on_the_diagonal(list(loads), list(dl), list(x), temperatures, zero=x0)
    f_e = k * dl * 1e-3 * l1 / l2 / loads  # (4.13)-(4.16)
    assert [s.friction_measured for s in res.steps] == pytest.approx(list(f_e), rel=1e-12)
    assert [s.chi for s in res.steps] == pytest.approx(list(e / h0), rel=1e-9)
    assert [s.angle for s in res.steps] == pytest.approx([0.0, 0.0], abs=1e-9)  # e_x = e_y
    mu = [
        np.mean([0.0773 * math.exp(-0.0485 * t) for t in ts]) for ts in ((40, 41, 42), (45, 46, 47))
    ]
    assert [s.viscosity for s in res.steps] == pytest.approx(mu, rel=1e-12)  # (4.17)-(4.18)
    s1 = np.array(mu) * w * B * D / loads  # (4.21)
    assert [s.bearing_characteristic for s in res.steps] == pytest.approx(list(s1), rel=1e-12)
    assert res.steps[1].temperature_rise["t3"] == pytest.approx(15.0)  # (4.19, E4)
    assert all(s.friction_theory is not None and s.friction_theory > 0 for s in res.steps)
    assert res.h_crit == pytest.approx(1.6e-6 + 3.2e-6)
    assert [s.h_min for s in res.steps] == pytest.approx(list(h0 - e), rel=1e-9)
    assert res.friction_fluid == pytest.approx(f_e.mean(), rel=1e-12)  # both steps fluid
    assert res.h_min_smallest == pytest.approx(h0 - e.max(), rel=1e-9)


def test_mtos_table_4_4_last_part_by_hand() -> None:
    """μ1…μ5 (4.17), S1⁻¹, μ_t/μ0 with μ0 = μ at 50 °C, A1^00…A3^11 (4.5), V (4.4) and
    P_τ = P*·V (4.2)-(4.3) of table 4.4, from the closed forms: A3^20 = π/(2(1 - χ²)^1.5),
    A3^11 = -2χ/(1 - χ²)², and P_τ = -μωR·B³·πχ/(4h0²(1 - χ²)^1.5) (Ocvirk, E3)."""
    h0, D, B, w, load, e = 100e-6, 0.050, 0.040, 157.0, 1000.0, 40e-6
    ex = e / math.sqrt(2)
    x = -(h0 * math.cos(math.pi / 4) - ex) * 1e6  # (4.11), the journal on the diagonal
    temps = {"t1": 30.0, "t2": 38.0, "t3": 45.0, "t4": 46.0, "t5": 47.0}
    res = mtos_on_the_diagonal([load], [0.08], [x], {k: [v] for k, v in temps.items()})
    step = res.steps[0]
    mu = {k: 0.0773 * math.exp(-0.0485 * t) for k, t in temps.items()}  # (4.17)
    assert step.viscosity_at == pytest.approx(mu, rel=1e-12)
    mu_t = (mu["t3"] + mu["t4"] + mu["t5"]) / 3  # (4.18)
    assert step.bearing_characteristic_inverse == pytest.approx(load / (B * D * mu_t * w))
    mu0 = 0.0773 * math.exp(-0.0485 * 50.0)
    assert step.viscosity_ratio == pytest.approx(mu_t / mu0, rel=1e-12)
    chi, R = e / h0, D / 2
    one = 1 - chi**2
    a1 = math.pi / math.sqrt(one)
    a2 = a1 / one
    a3 = (3 * a2 - a1) / (2 * one)
    assert [step.a1_00, step.a2_00, step.a3_00] == pytest.approx([a1, a2, a3], rel=1e-9)
    assert step.a3_02 == pytest.approx((a1 - 2 * a2 + a3) / chi**2, rel=1e-9)  # as printed
    assert step.a3_20 == pytest.approx(math.pi / (2 * one**1.5), rel=1e-9)
    assert step.a3_11 == pytest.approx(-2 * chi / one**2, rel=1e-9)
    a = B / (2 * R)  # E3
    v = -chi * a**2 * (mu_t / mu0) * (math.pi / (2 * one**1.5)) * (w / 100.0)  # (4.4)
    assert step.v_factor == pytest.approx(v, rel=1e-9)
    ocvirk = -mu_t * w * R * B**3 * math.pi * chi / (4 * h0**2 * one**1.5)
    assert step.tangential_force == pytest.approx(ocvirk, rel=1e-9)
    p_star = 2 * B * R * mu0 * 100.0 / (h0 / R) ** 2  # (4.3)
    assert step.tangential_force == pytest.approx(p_star * v, rel=1e-9)  # (4.2)


def test_profilometer_sine_trace() -> None:
    A, lam, n_per = 1.0, 50.0, 200  # μm, μm, samples per period
    periods = 20
    x_um = np.arange(periods * n_per + 1) * lam / n_per
    y = A * np.cos(2 * np.pi * x_um / lam)  # symmetric about the middle: no mean-line tilt
    trace = {"x": list(x_um * 1e-3), "y": list(y)}  # mm, μm
    res = analyse(make_run(StandKind.PROFILOMETER), FakeReadings({"profile": trace}, {})).values
    assert res.ra == pytest.approx(2 * A / math.pi * 1e-6, rel=1e-3)  # Ra of a sine
    assert res.rmax == pytest.approx(2 * A * 1e-6, rel=1e-3)
    assert res.sm == pytest.approx(lam * 1e-6, rel=1e-6)
    # a sine's bearing ratio at depth p below the peak: t_p = arccos(1 - 2ε)/π
    eps = np.array(res.eps)
    assert res.tp == pytest.approx(list(np.arccos(1 - 2 * eps) / np.pi), abs=2e-3)
    assert res.fit_manual is not None and res.complex_parameter is not None


def test_slide_bearing_finite_solution_lies_below_both_asymptotes() -> None:
    """The finite bearing leaks at the ends (below Π∞) and carries circumferential flow
    (below Π0): both asymptotes bound it from above at the pressure peak (issue 5)."""
    h0, scale = 175e-6, 1e-6
    limbs = np.arange(0.0, 181.0, 10.0)
    e_x, e_y = 90e-6, 80e-6
    rows = {
        "limb_angle": list(limbs),
        **{f"p{k}": [0.5] * limbs.size for k in range(1, 6)},
        "x": [500.0 - (h0 - e_x) / scale] * limbs.size,
        "y": [400.0 - (h0 - e_y) / scale] * limbs.size,
        "t1": [30.0] * limbs.size,
        "t2": [40.0] * limbs.size,
    }
    m = {"x_zero": 500.0, "y_zero": 400.0, "load_zone_end": 180.0}
    res = analyse(make_run(StandKind.SLIDE_BEARING), FakeReadings({"rows": rows}, m)).values
    finite = max(r.pi_finite for r in res.table if r.pi_finite is not None)
    assert finite > 0
    assert finite < max(r.pi_short for r in res.table if r.pi_short is not None)
    assert finite < max(r.pi_long for r in res.table if r.pi_long is not None)
    assert all(p.pi_finite is not None and p.pi_finite >= 0 for p in res.axial)


def test_mtos_finite_friction_of_a_centred_journal_is_petroff() -> None:
    """χ = 0: M = 2π·μωR³B/h0 (Petroff), f = M/(N·R1) as in (4.10)."""
    h0, D, B, w, load = 100e-6, 0.050, 0.040, 157.0, 500.0
    x_centre = -(h0 * math.cos(math.pi / 4)) * 1e6  # (4.11): e_x = 0 when |X_уст - X| = h0·cos45°
    res = mtos_on_the_diagonal([load], [0.01], [x_centre], {f"t{k}": [40.0] for k in range(1, 6)})
    step = res.steps[0]
    assert step.chi == pytest.approx(0.0, abs=1e-9)
    mu = 0.0773 * math.exp(-0.0485 * 40.0)
    R = D / 2
    petroff = 2 * math.pi * mu * w * R**3 * B / h0
    assert step.friction_finite == pytest.approx(petroff / (load * (R - h0)), rel=1e-6)
    assert step.load_finite == pytest.approx(0.0, abs=1e-6)


def test_smts2_says_what_is_missing() -> None:
    """Without weighings and Ra the wear results stay empty and `pending` names why."""
    cols = {
        "time": [0.0, 1.0],
        "load": [300.0, 300.0],
        "speed": [1000.0, 1000.0],
        "friction_moment": [3.0, 3.0],
        "revolutions": [0.0, 1.0],
    }
    res = smts2.analyse(make_run(StandKind.SMTS2), FakeReadings({"friction": cols}, {}))
    assert res.experimental is None and res.theoretical is None
    assert any("pin_mass_before" in p for p in res.pending)
    assert any("disc_ra" in p for p in res.pending)
    empty = smts2.analyse(make_run(StandKind.SMTS2), FakeReadings({}, {}))
    assert empty.pending == ["no friction record yet"]
