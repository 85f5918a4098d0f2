"""The analysis gives back the simulator's truth: exactly without noise, within the noise's
bounds with it. In process (simulated stand -> readings -> pipeline), over seeds and
configurations; the HTTP path is checked once in tests/rigsim/test_end_to_end.py.

Without noise (``rigsim run --noise off``: ideal instruments, no friction fluctuation) the
only differences left are round-off and the stated discretisations: the SMTs-2 counter's
last sample, and on the MTOS stand the finite-bearing grids (the simulator's equilibrium on
72 x 16, the analysis's 144 x 48: docs/reynolds.md puts the coarse grids' load error at
0.3-1 %, more at small χ). The slide-bearing simulator solves its pressure field again on the
analysis's grid at its χ (rigsim.bearing_model.refined), so there Π agrees to round-off.
With noise, every bound is 5 standard deviations of the error the instruments' noise and
quantisation (a step q adds q²/12 of variance) make, derived beside each assertion.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, example, given, settings
from hypothesis import strategies as st
from scipy.signal import find_peaks

from rigserver.core import roughness
from rigsim.cli import settings_for
from rigsim.simulators import SIMULATORS
from rigsim.simulators.mtos import simulated_configuration
from schemas.results import MtosResults, ProfilometerResults, SlideBearingResults, Smts2Results
from schemas.stands import StandKind
from tests.reports.simulated import analysed

FEW = settings(
    max_examples=5,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    phases=(Phase.explicit, Phase.reuse, Phase.generate),  # a failing run is slow to shrink
)


def _run(kind: StandKind, seed: int, noise: bool, **changes: Any) -> tuple[Any, Any]:
    s = settings_for(kind, noise=noise)
    sim = SIMULATORS[kind].simulate(replace(s, **changes), seed)
    return analysed(kind, sim).result.values, sim.truth


def _var(noise: float, resolution: float) -> float:
    """Variance of one reading's error: its noise and its quantisation step."""
    return noise**2 + resolution**2 / 12.0


# --- slide bearing --------------------------------------------------------------------------


@pytest.mark.parametrize("scale", [10.0, 20.0, 40.0])  # without noise the seed changes nothing
def test_slide_bearing_without_noise(scale: float) -> None:
    v, t = _run(StandKind.SLIDE_BEARING, 0, False, loader_scale=scale)
    assert isinstance(v, SlideBearingResults) and v.chi_mean is not None
    assert v.chi_mean == pytest.approx(t.chi, rel=1e-9)
    assert [r.chi for r in v.table] == pytest.approx([t.chi] * len(v.table), rel=1e-9)
    assert v.attitude_angle == pytest.approx(np.degrees(t.attitude_angle), abs=1e-9)
    assert v.mu_bar == pytest.approx(t.mu_bar, rel=1e-12)
    assert v.load == pytest.approx(t.load, rel=1e-12)
    assert [r.phi_model for r in v.table] == pytest.approx(list(t.phi_model), abs=1e-9)
    assert [r.pressure for r in v.table] == pytest.approx(list(t.pressure[:, 2]), rel=1e-9)
    top = int(np.argmax(t.pressure[:, 2]))
    assert [p.pressure for p in v.axial] == pytest.approx(list(t.pressure[top]), rel=1e-9)
    # the finite curve at φ_мод + φ_r is the measurement: the same solve at the same χ
    assert v.rupture_angle == pytest.approx(t.rupture_angle, abs=1e-9)
    measured = np.array([r.pi_measured for r in v.table])
    finite = np.array([r.pi_finite for r in v.table])
    assert np.abs(finite - measured).max() < 1e-9 * measured.max()


def test_slide_bearing_finite_curve_ends_with_the_measurement() -> None:
    # the symptom: at φ_мод = 360° the measurement is ~0 (φ_k is where the holes lose
    # pressure: below 0.1 % of the peak, bearing.RUPTURE_SHARE) and so must the finite curve
    # be (it was 1.43 when drawn at φ_мод, without the rupture angle)
    v, _ = _run(StandKind.SLIDE_BEARING, 0, False)
    last, peak = v.table[0], max(r.pi_measured for r in v.table)
    assert last.phi_model == pytest.approx(360.0) and last.pi_measured < 1e-3 * peak
    assert last.pi_finite == pytest.approx(last.pi_measured, abs=1e-9)
    peak_measured = max(v.table, key=lambda r: r.pi_measured).phi_model
    peak_finite = max(v.table, key=lambda r: r.pi_finite or 0.0).phi_model
    assert peak_finite == peak_measured


@FEW
@given(seed=st.integers(0, 10_000))
def test_slide_bearing_with_noise(seed: int) -> None:
    v, t = _run(StandKind.SLIDE_BEARING, seed, True)
    s = settings_for(StandKind.SLIDE_BEARING)
    c, ins = s.configuration, s.instruments
    rows = len(v.table)
    # X and the zero X_уст each err by the gauge's noise and its division (d per division);
    # the zero's error is common to every row, so the mean χ keeps all of it and 1/rows of
    # the rest: σ_χ <= d·σ·√(1 + 1/rows)/h0 (a component of e along e moves χ one for one)
    sigma = np.sqrt(_var(ins.displacement.noise, ins.displacement.resolution))
    spread = c.displacement_per_division * sigma * np.sqrt(1.0 + 1.0 / rows)
    assert v.chi_mean == pytest.approx(t.chi, abs=5 * spread / c.clearance)
    # the component across e turns ψ by (its error)/e
    turn = np.degrees(5 * spread / (t.chi * c.clearance))
    assert v.attitude_angle == pytest.approx(np.degrees(t.attitude_angle), abs=turn)
    # t = mean over the rows of (t1 + t2)/2: σ_t = √(2 σ_th²)/2/√rows; μ̄ moves by |α|·Δt
    sigma_t = np.sqrt(2 * _var(ins.thermometer.noise, ins.thermometer.resolution)) / 2
    d_t = 5 * sigma_t / np.sqrt(rows)
    assert v.mu_bar == pytest.approx(t.mu_bar, rel=abs(c.viscosity.alpha) * d_t * 1.01)


# --- MTOS -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def mtos_finite_exact() -> tuple[MtosResults, Any]:
    v, t = _run(StandKind.MTOS, 5, False)
    return v, t


def test_mtos_without_noise(mtos_finite_exact: tuple[MtosResults, Any]) -> None:
    v, t = mtos_finite_exact
    for got, true in zip(v.steps, t.steps, strict=True):
        assert got.chi == pytest.approx(true.chi, abs=1e-12)
        # (4.12): δ = ψ on the film, γ = -angle on the asperities (the truth's angle is the
        # line of centres from the X axis minus 45°)
        sign = 1.0 if true.regime == 1 else -1.0
        assert got.angle == pytest.approx(sign * np.degrees(true.angle), abs=1e-9)
        assert got.friction_measured == pytest.approx(true.friction, rel=1e-12)
        assert got.friction_moment == pytest.approx(true.friction_moment, rel=1e-12)
        assert got.viscosity == pytest.approx(true.viscosity, rel=1e-12)
        assert got.h_min == pytest.approx(true.h_min, rel=1e-9)
        assert got.film_parameter == pytest.approx(true.film_parameter, rel=1e-9)
        assert got.film == ("fluid" if true.film == "fluid" else "mixed")
        assert got.film_lambda == {"fluid": "full film"}.get(true.film, true.film)
        if true.regime == 1:
            # the finite film at the measured χ carries N to the grids' discretisation
            # (72 x 16 against 144 x 48; 2 % at the lightest load, χ = 0.2)
            assert got.load_finite == pytest.approx(true.load, rel=0.02)


def test_mtos_boundary_experiment_is_labelled_boundary(
    mtos_finite_exact: tuple[MtosResults, Any],
) -> None:
    v, _ = mtos_finite_exact
    boundary = [s for s in v.steps if s.regime == "boundary"]
    assert boundary and all(s.film_parameter < 1.0 for s in boundary)
    assert all(s.film_lambda == "boundary" for s in boundary)
    assert not any(s.film_lambda == "boundary" for s in v.steps if s.regime != "boundary")
    # (2.104) cannot see it: its two states are fluid and mixed
    assert all(s.film == "mixed" for s in boundary)
    assert v.regime_disagreements == []


@FEW
@given(
    seed=st.integers(0, 10_000),
    loads=st.lists(st.sampled_from([500.0, 1000.0, 2000.0, 3000.0]), min_size=1, max_size=3),
)
def test_mtos_with_noise(seed: int, loads: list[float]) -> None:
    fluid = tuple(sorted(set(loads)))
    v, t = _run(StandKind.MTOS, seed, True, model="short", loads_fluid=fluid)
    s = settings_for(StandKind.MTOS)
    c, ins = simulated_configuration(), s.instruments
    for i, (got, true) in enumerate(zip(v.steps, t.steps, strict=True)):
        # each component of e: the reading's and the zero's noise and 0.1 μm steps, and the
        # drift since the zero (rate·time, a bias): |Δe_x| <= 5σ√2 + drift·t; χ moves by at
        # most √2 times that over h0
        at = s.step_duration * (i + 1)
        sigma = np.sqrt(2 * _var(ins.displacement.noise, ins.displacement.resolution))
        d_e = (5 * sigma + ins.displacement.drift * at) * 1e-6
        assert got.chi == pytest.approx(true.chi, abs=np.sqrt(2) * d_e / c.clearance)
        # f_э = k·Δl·l1/(l2·N): the indicator's and the dynamometer's relative errors add in
        # quadrature
        travel = true.friction_moment / c.lever_moment_arm / c.spring_rate
        rel = np.hypot(
            np.sqrt(_var(ins.indicator.noise, ins.indicator.resolution)) / travel,
            np.sqrt(_var(ins.dynamometer.noise, ins.dynamometer.resolution)) / true.load,
        )
        assert got.friction_measured == pytest.approx(true.friction, rel=5 * rel)


# --- SMTs-2 -----------------------------------------------------------------------------


@FEW
@given(
    seed=st.integers(0, 10_000),
    load=st.sampled_from([200.0, 300.0, 500.0]),
    speed=st.sampled_from([300.0, 500.0, 1000.0]),
)
def test_smts2_without_noise(seed: int, load: float, speed: float) -> None:
    v, t = _run(StandKind.SMTS2, seed, False, load=load, speed=speed)
    assert isinstance(v, Smts2Results) and v.experimental is not None
    s = settings_for(StandKind.SMTS2)
    # the running-in term (f0 - fs)·exp(-n/n_r) is below 0.2·exp(-7500/300) ≈ 3e-12 over
    # the steady half of 15 000 revolutions
    assert v.friction_steady == pytest.approx(t.friction_steady, rel=1e-9)
    assert v.mean_load == pytest.approx(t.load, rel=1e-12)
    # the counter shows whole hundreds; the run stops within one sample past the plan
    per_sample = t.speed / 60.0 / s.sample_rate
    assert 0.0 <= t.revolutions - v.revolutions <= per_sample
    assert v.experimental.mass_loss == pytest.approx(t.mass_loss, rel=1e-9)
    assert v.experimental.volume == pytest.approx(t.volume, rel=1e-9)
    distance = t.sliding_distance * v.revolutions / t.revolutions
    assert v.experimental.intensity == pytest.approx(t.intensity * t.revolutions / v.revolutions)
    # Archard's k of the simulator, V = k·N·L, back from k = V/(F·L) (ASTM G99)
    k = t.volume / (t.load * distance)
    assert v.experimental.specific_wear_rate == pytest.approx(k, rel=1e-9)
    assert k == pytest.approx(s.wear_coefficient * t.revolutions / v.revolutions, rel=1e-9)


@FEW
@given(seed=st.integers(0, 10_000))
def test_smts2_with_noise(seed: int) -> None:
    v, t = _run(StandKind.SMTS2, seed, True)
    s = settings_for(StandKind.SMTS2)
    ins = s.instruments
    assert isinstance(v, Smts2Results) and v.experimental is not None
    # f fluctuates as AR(1) (ρ = 0.9) of relative size σ: the mean of n rows has variance
    # σ²f²(1 + ρ)/((1 - ρ)n); the moment and load readings add white relative errors
    n = v.rows - int(v.rows * (1.0 - s.configuration.steady_fraction))
    moment = t.friction_steady * t.load * s.configuration.disc_radius
    white = np.hypot(
        np.sqrt(_var(ins.moment.noise, ins.moment.resolution)) / moment,
        np.sqrt(_var(ins.load.noise, ins.load.resolution)) / t.load,
    )
    sigma = t.friction_steady * np.sqrt(s.friction_fluctuation**2 * 19.0 + white**2) / np.sqrt(n)
    assert v.friction_steady == pytest.approx(t.friction_steady, abs=5 * sigma)
    # Δm = m1 - m2, two weighings of 0.1 mg noise and resolution
    weighing = np.sqrt(2 * _var(ins.balance.noise, ins.balance.resolution)) * 1e-3
    assert v.experimental.mass_loss == pytest.approx(t.mass_loss, abs=5 * weighing)


# --- profilometer ----------------------------------------------------------------------


@FEW
@given(seed=st.integers(0, 10_000), ra=st.sampled_from([0.2e-6, 0.8e-6, 2.5e-6]))
def test_profilometer_without_noise(seed: int, ra: float) -> None:
    v, t = _run(StandKind.PROFILOMETER, seed, False, ra=ra)
    assert isinstance(v, ProfilometerResults)
    # the trace's tilt is linear, so the least-squares mean line removes it exactly
    for name in ("ra", "rq", "rz", "rmax"):
        assert getattr(v, name) == pytest.approx(getattr(t, name), rel=1e-9)
    assert v.ra == pytest.approx(ra, rel=1e-9)


@FEW
@given(seed=st.integers(0, 10_000))
@example(seed=198)  # noise splits an element: Rz of the truth's elements is 109σ off
def test_profilometer_with_noise(seed: int) -> None:
    v, t = _run(StandKind.PROFILOMETER, seed, True)
    ins = settings_for(StandKind.PROFILOMETER).instruments
    sigma = np.sqrt(_var(ins.gauge.noise, ins.gauge.resolution)) * 1e-6
    assert isinstance(v, ProfilometerResults) and v.ra is not None and v.rz is not None
    # Ra is the mean |y|: an error n_i moves it by at most mean|n_i| ≈ σ√(2/π) < σ (+ the
    # refitted mean line's share); 5σ is ample.
    assert v.ra == pytest.approx(t.ra, abs=5 * sigma)
    # Rz (1.4) takes the highest point of each element between crossings of the mean line.
    # Noise where the profile dips to the line can split one element in two (or join two),
    # which changes which points count by far more than the noise (seed 198: +109σ). Over
    # the elements the measured profile shows, the highest point of each moves by at most
    # max|n| (the error of each ordinate, mean line included): Rz by at most twice that.
    rz_true, error = _rz_over_measured_elements(seed)
    assert v.rz == pytest.approx(rz_true, abs=2 * error * (1 + 1e-9))


def _rz_over_measured_elements(seed: int) -> tuple[float, float]:
    """Rz (1.4) of the noise-free profile at the peaks and valleys of the measured one, the
    highest (deepest) of each element between its crossings of the mean line (the same
    seed's trace with and without noise); and the largest error of an ordinate, m."""
    kind, um = StandKind.PROFILOMETER, 1e-6
    traces = [
        SIMULATORS[kind].simulate(settings_for(kind, noise=noise), seed).columns("profile")
        for noise in (False, True)
    ]
    true, measured = (_from_mean_line(c["x"] * um, c["y"] * um) for c in traces)
    element = np.concatenate(([0], np.cumsum(np.diff(measured >= 0) != 0)))

    def highest(r: np.ndarray, sign: float) -> list[float]:
        at = find_peaks(sign * measured)[0]
        at = at[sign * measured[at] > 0]  # a peak above the line, a valley below it
        return sorted(max(sign * r[at[element[at] == e]]) for e in np.unique(element[at]))

    peaks, valleys = highest(true, 1.0), highest(true, -1.0)
    assert len(peaks) >= 5 and len(valleys) >= 5
    rz = float(np.mean(peaks[-5:]) + np.mean(valleys[-5:]))
    return rz, float(np.max(np.abs(measured - true)))


def _from_mean_line(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    line = roughness.mean_line(x=x, y=y)
    return np.asarray(y - (line.intercept + line.slope * x))
