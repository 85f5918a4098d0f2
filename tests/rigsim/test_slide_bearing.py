"""rigsim.simulators.slide_bearing: readings that the lab-3 formulas turn back into the truth."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from rigserver.core import bearing, bearing_readings
from rigsim.batches import SimulatedRun
from rigsim.bearing_model import Geometry, film
from rigsim.errors import SettingsError
from rigsim.simulators import slide_bearing as sb
from rigsim.thermal import OIL_DENSITY, OIL_HEAT_CAPACITY
from schemas.channels import check_columns
from schemas.stands import SLIDE_BEARING_GROUPS, SlideBearingConfig

SHORT = sb.SlideBearingSettings(model="short")
AT = 98_066.5  # Pa per technical atmosphere, the gauges' unit


@pytest.fixture(scope="module", params=["short", "finite"])
def run(request: pytest.FixtureRequest) -> SimulatedRun[sb.SlideBearingTruth]:
    return sb.simulate(replace(SHORT, model=request.param), seed=11)


def _eccentricity(run: SimulatedRun[sb.SlideBearingTruth]) -> bearing_readings.Eccentricity:
    c = SHORT.configuration
    rows, m = run.columns("rows"), run.columns("measurements")
    d = c.displacement_per_division
    return bearing_readings.slide_bearing_eccentricity(
        x=rows["x"] * d,
        y=rows["y"] * d,
        x_set=m["x_zero"][0] * d,
        y_set=m["y_zero"][0] * d,
        clearance=c.clearance,
    )


def test_every_batch_passes_the_servers_check(run: SimulatedRun[sb.SlideBearingTruth]) -> None:
    groups = {g.name: g for g in SLIDE_BEARING_GROUPS}
    for batch in run.batches:
        assert check_columns(groups[batch.group], batch.columns) == []
    # 180° in 10° steps: 19 limb positions, the first at φ_k
    limb = run.columns("rows")["limb_angle"]
    assert limb.size == 19
    assert limb[0] == run.columns("measurements")["load_zone_end"][0]
    assert np.diff(limb).tolist() == [-10.0] * 18


def test_3_16_gives_back_chi_at_every_limb_position(
    run: SimulatedRun[sb.SlideBearingTruth],
) -> None:
    ecc = _eccentricity(run)
    assert np.abs(ecc.chi - run.truth.chi).max() < 0.02
    assert bearing_readings.mean_eccentricity_ratio(chi=ecc.chi) == pytest.approx(
        run.truth.chi, abs=0.01
    )


def test_3_20_and_the_gauges(run: SimulatedRun[sb.SlideBearingTruth]) -> None:
    rows, m = run.columns("rows"), run.columns("measurements")
    phi = bearing_readings.model_angle_deg(
        limb_deg=rows["limb_angle"], load_zone_end_deg=m["load_zone_end"][0]
    )
    # φ_k is read to a degree (noise 0.5°)
    assert phi == pytest.approx(run.truth.phi_model, abs=2.0)
    gauges = np.column_stack([rows[f"p{k}"] for k in range(1, 6)]) * AT
    # gauges read to 0.05 at with 0.02 at of noise
    assert np.abs(gauges - run.truth.pressure).max() < 0.1 * AT


def test_mean_temperature_gives_the_films_viscosity(
    run: SimulatedRun[sb.SlideBearingTruth],
) -> None:
    rows = run.columns("rows")
    c = SHORT.configuration
    oil = bearing_readings.mean_oil_viscosity(
        t_in=rows["t1"], t_out=rows["t2"], A=c.viscosity.A, alpha=c.viscosity.alpha, mu0=c.mu0
    )
    assert oil.temperature == pytest.approx(run.truth.temperature, abs=0.05)
    assert oil.mu_bar == pytest.approx(run.truth.mu_bar, rel=0.005)


def test_short_truth_carries_the_load_and_is_not_the_theory_under_test() -> None:
    run = sb.simulate(SHORT, seed=2)
    t, c = run.truth, SHORT.configuration
    force = bearing.short_bearing_load(
        chi=t.chi,
        omega=c.omega0,
        viscosity=t.viscosity,
        bearing_radius=c.bearing_radius,
        width=c.width,
        clearance=c.clearance,
    )
    assert float(force.resultant) == pytest.approx(16.2 * 20.0, rel=1e-9)  # 20 mm of loader
    assert t.rupture_angle == 0.0  # both asymptotes vanish at the thinnest film
    # Π_э at z = 0 stays below Π0 (3.10) and Π∞ (3.15) at the true χ and μ̄ where it is read
    phi = np.radians(t.phi_model)
    centre = t.pressure[:, 2] * (c.clearance / c.bearing_radius) ** 2 / (c.mu0 * c.omega0)
    a = c.width / (2 * c.bearing_radius)
    p0 = bearing.short_bearing_pressure(phi=phi, z=0.0, chi=t.chi, a=a, mu_bar=t.mu_bar, G=1.0)
    p_long = bearing.long_bearing_pressure(phi=phi, chi=t.chi, mu_bar=t.mu_bar, G=1.0)
    loaded = centre > 1e-3
    assert loaded.sum() >= 15
    assert np.all(centre[loaded] < p0[loaded]) and np.all(centre[loaded] < p_long[loaded])


def test_finite_film_ruptures_past_the_thinnest_film() -> None:
    run = sb.simulate(replace(SHORT, model="finite"), seed=2)
    assert 0.0 < run.truth.rupture_angle < 45.0
    # at the limb position φ_k the hole is at the rupture, the thinnest film just before it
    assert run.truth.pressure[0, 2] < 0.05 * run.truth.pressure[:, 2].max()


def test_heat_balance_closes() -> None:
    run = sb.simulate(SHORT, seed=2)
    t = run.truth
    c = SHORT.configuration
    state = film(
        model="short",
        load=t.load,
        omega=c.omega0,
        viscosity=t.viscosity,
        geometry=Geometry(radius=c.bearing_radius, width=c.width, clearance=c.clearance),
    )
    # M·ω0 = (2ρc_pQ + G)(t - t_in): the oil leaves at t2 = 2t - t1
    g = 2 * OIL_DENSITY * OIL_HEAT_CAPACITY * SHORT.oil_flow + SHORT.conductance
    rise = t.temperature - SHORT.inlet_temperature
    assert state.friction_moment * c.omega0 == pytest.approx(g * rise, rel=1e-4)


def test_gauge_unit_follows_the_configuration() -> None:
    at = sb.simulate(SHORT, seed=2)
    atm = sb.simulate(replace(SHORT, configuration=SlideBearingConfig(gauge_unit="atm")), seed=2)
    # the same pressures, read in technical (98 066.5 Pa) or standard (101 325 Pa) atmospheres
    for run, unit in ((at, AT), (atm, 101_325.0)):
        read = run.columns("rows")["p3"]
        assert np.abs(read - run.truth.pressure[:, 2] / unit).max() < 0.1


def test_settings_are_checked() -> None:
    with pytest.raises(SettingsError, match=r"loader_scale must lie in \(0, 1000\] mm"):
        sb.SlideBearingSettings(loader_scale=-1.0)
    with pytest.raises(SettingsError, match="limb_step <= limb_span"):
        sb.SlideBearingSettings(limb_step=20.0, limb_span=10.0)
