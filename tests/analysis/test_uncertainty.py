"""GUM uncertainties of the headline results: against partial derivatives derived by hand,
and against a Monte Carlo propagation where the model is nonlinear (χ = |e|/h0)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rigserver.analysis.uncertainty import batch_mean, slide_bearing_chi_mean
from rigserver.core import bearing_readings
from schemas.results import MtosResults, ProfilometerResults, SlideBearingResults, Smts2Results
from schemas.stands import MtosConfig, SlideBearingConfig, Smts2Config, StandKind
from tests.reports.simulated import simulated

R3 = math.sqrt(3.0)


def test_friction_coefficient_by_hand() -> None:
    sim = simulated(StandKind.SMTS2)
    v, c = sim.result.values, Smts2Config.model_validate(sim.run.configuration)
    assert isinstance(v, Smts2Results) and v.friction_steady_uncertainty is not None
    a = c.accuracy
    # f = M/(N r2): relative u² = u_A² + (a_M/√3)² + (a_N/√3)² + (a_r/(√3 r2))²; u_A from 20
    # batch means of the steady block means
    steady = np.array(
        [y for x, y in zip(v.friction.x, v.friction.y, strict=True) if x >= v.steady_from_time]
    )
    means = [part.mean() for part in np.array_split(steady, 20)]
    u_a = np.std(means, ddof=1) / math.sqrt(20)
    f = steady.mean()
    rel = math.sqrt(
        (u_a / f) ** 2
        + (a.moment / R3) ** 2
        + (a.load / R3) ** 2
        + (a.length / R3 / c.disc_radius) ** 2
    )
    assert v.friction_steady_uncertainty == pytest.approx(f * rel, rel=1e-9)
    assert v.friction_steady_expanded == pytest.approx(2 * f * rel, rel=1e-9)


def test_wear_intensity_and_k_by_hand() -> None:
    sim = simulated(StandKind.SMTS2)
    v, c = sim.result.values, Smts2Config.model_validate(sim.run.configuration)
    assert isinstance(v, Smts2Results) and v.experimental is not None
    a, e = c.accuracy, v.experimental
    # I = Δm/(ρ π r1² 2π r2 M): ∂ln I/∂m1 = 1/Δm = -∂ln I/∂m2, ∂ln I/∂ρ = -1/ρ,
    # ∂ln I/∂r1 = -2/r1, ∂ln I/∂r2 = -1/r2, ∂ln I/∂M = -1/M; a resolution q gives q/(2√3)
    u_m = a.balance_resolution / (2 * R3)
    r1, r2 = c.pin_diameter / 2, c.disc_radius
    common = [
        math.sqrt(2) * u_m / e.mass_loss,
        a.density / R3 / c.pin.density,
        a.length / R3 / r2,
        a.counter / (2 * R3) / v.revolutions,
    ]
    rel_i = math.hypot(*common, 2 * a.length / R3 / r1)
    assert e.intensity_uncertainty == pytest.approx(e.intensity * rel_i, rel=1e-6)
    # k = Δm/(ρ N 2π r2 M): no r1, the load's tolerance instead
    rel_k = math.hypot(*common, a.load / R3)
    assert e.specific_wear_rate_uncertainty == pytest.approx(e.specific_wear_rate * rel_k, rel=1e-6)
    assert e.specific_wear_rate_expanded == pytest.approx(
        2 * e.specific_wear_rate * rel_k, rel=1e-6
    )


def test_mtos_friction_by_hand() -> None:
    sim = simulated(StandKind.MTOS)
    v, c = sim.result.values, MtosConfig.model_validate(sim.run.configuration)
    assert isinstance(v, MtosResults)
    a = c.accuracy
    rows = sim.readings.read("steps")
    for i, step in enumerate(v.steps):
        # f_э = k Δl l1/(l2 N): relative u² = (u_Δl/Δl)² + (a_k/√3)² + (u_l/l1)² + (u_l/l2)²
        # + (a_N/√3)²
        rel = math.sqrt(
            (a.indicator / R3 / rows["indicator"][i]) ** 2
            + (a.spring_rate / R3) ** 2
            + (a.arms / R3 / c.lever_moment_arm) ** 2
            + (a.arms / R3 / c.friction_arm) ** 2
            + (a.dynamometer / R3) ** 2
        )
        assert step.friction_measured_uncertainty == pytest.approx(
            step.friction_measured * rel, rel=1e-9
        )


def test_profilometer_type_b_from_the_error_limits() -> None:
    v = simulated(StandKind.PROFILOMETER).result.values
    assert isinstance(v, ProfilometerResults) and v.ra_error is not None and v.rz_error is not None
    # (1.14) gives limits ΔRa, ΔRz; a rectangular distribution: u = Δ/√3, U = 2u
    assert v.ra_uncertainty == pytest.approx(v.ra_error / R3, rel=1e-12)
    assert v.rz_expanded == pytest.approx(2 * v.rz_error / R3, rel=1e-12)


def test_slide_bearing_chi_against_monte_carlo() -> None:
    sim = simulated(StandKind.SLIDE_BEARING)
    v, c = sim.result.values, SlideBearingConfig.model_validate(sim.run.configuration)
    assert isinstance(v, SlideBearingResults) and v.chi_mean_uncertainty is not None
    rows, m = sim.readings.read("rows"), sim.readings.measurements()
    a, d = c.accuracy, c.displacement_per_division
    rng = np.random.default_rng(1)
    draws = 4000
    limit = a.displacement

    def uniform(shape: tuple[int, ...]) -> np.ndarray:
        return rng.uniform(-limit, limit, shape)

    n = rows["x"].size
    x = rows["x"][None, :] + uniform((draws, n))
    y = rows["y"][None, :] + uniform((draws, n))
    x0 = m["x_zero"] + uniform((draws, 1))
    y0 = m["y_zero"] + uniform((draws, 1))
    h0 = c.clearance + rng.uniform(-a.clearance, a.clearance, (draws, 1))
    chi = bearing_readings.slide_bearing_eccentricity(
        x=x * d, y=y * d, x_set=x0 * d, y_set=y0 * d, clearance=h0
    ).chi.mean(axis=1)
    # first order within 5 % of the Monte Carlo spread (χ_ср is near-linear at χ ≈ 0.75)
    assert v.chi_mean_uncertainty == pytest.approx(float(np.std(chi)), rel=0.05)
    direct = slide_bearing_chi_mean(
        x=list(rows["x"]),
        y=list(rows["y"]),
        x_zero=m["x_zero"],
        y_zero=m["y_zero"],
        per_division=d,
        limit_divisions=limit,
        clearance=c.clearance,
        clearance_limit=a.clearance,
    )
    assert direct.std_dev == pytest.approx(v.chi_mean_uncertainty, rel=1e-12)


def test_batch_means_see_the_correlation() -> None:
    # AR(1) with ρ = 0.9: the mean's true standard deviation is σ√((1+ρ)/(1-ρ)/n) ≈ 4.4σ/√n;
    # s/√n would give σ/√n. Batch means recover the factor within their own scatter.
    rng = np.random.default_rng(3)
    rho, n, runs = 0.9, 20_000, 40
    estimates = []
    for _ in range(runs):
        white = rng.normal(0, math.sqrt(1 - rho**2), n)
        series = np.empty(n)
        series[0] = rng.normal()
        for i in range(1, n):
            series[i] = rho * series[i - 1] + white[i]
        estimates.append(batch_mean(series).std_dev)
    expected = math.sqrt((1 + rho) / (1 - rho) / n)
    assert float(np.mean(estimates)) == pytest.approx(expected, rel=0.15)
