"""rigsim.simulators.mtos: the readings, processed by the stand's formulas, give back the truth."""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
import pytest

from rigserver.core import bearing, bearing_readings
from rigsim.batches import SimulatedRun
from rigsim.errors import SettingsError
from rigsim.simulators import mtos
from rigsim.thermal import DROP_VOLUME, OIL_DENSITY, OIL_HEAT_CAPACITY
from schemas.channels import check_columns
from schemas.stands import MTOS_GROUPS

SHORT = mtos.MtosSettings(model="short")
COS45 = np.cos(np.pi / 4.0)


@pytest.fixture(scope="module")
def short_run() -> SimulatedRun[mtos.MtosTruth]:
    return mtos.simulate(SHORT, seed=3)


@pytest.fixture(scope="module")
def finite_run() -> SimulatedRun[mtos.MtosTruth]:
    return mtos.simulate(mtos.MtosSettings(model="finite"), seed=4)


def _processed(
    run: SimulatedRun[mtos.MtosTruth],
) -> tuple[bearing_readings.Eccentricity, np.ndarray]:
    c = mtos.MtosSettings().configuration
    rows = run.columns("steps")
    zero = run.columns("measurements")
    ecc = bearing_readings.mtos_eccentricity(
        x=rows["x"] * 1e-6,
        y=rows["y"] * 1e-6,
        x_set=zero["x_zero"][0] * 1e-6,
        y_set=zero["y_zero"][0] * 1e-6,
        clearance=c.clearance,
    )
    f = bearing_readings.mtos_friction(
        indicator_travel=rows["indicator"] * 1e-3,
        spring_rate=c.spring_rate * 1e3,
        spring_arm=c.lever_moment_arm,
        friction_arm=c.friction_arm,
        load=rows["load"],
    ).coefficient
    return ecc, f


def test_every_batch_passes_the_servers_check(short_run: SimulatedRun[mtos.MtosTruth]) -> None:
    groups = {g.name: g for g in MTOS_GROUPS}
    for batch in short_run.batches:
        assert check_columns(groups[batch.group], batch.columns) == []
    # the manual's plan: 6 loads of experiment 1, 3 of each starved experiment
    assert short_run.rows("steps") == 12
    assert short_run.columns("steps")["regime"].tolist() == [1.0] * 6 + [2.0] * 3 + [3.0] * 3


def test_deterministic_from_the_seed() -> None:
    a, b, c = (mtos.simulate(SHORT, seed=s) for s in (5, 5, 6))
    assert all(
        np.array_equal(x.columns[k], y.columns[k])
        for x, y in zip(a.batches, b.batches, strict=True)
        for k in x.columns
    )
    assert not np.array_equal(a.columns("steps")["x"], c.columns("steps")["x"])
    assert a.truth == b.truth


@pytest.mark.parametrize("fixture", ["short_run", "finite_run"])
def test_stand_formulas_give_back_chi_and_f(fixture: str, request: pytest.FixtureRequest) -> None:
    run: SimulatedRun[mtos.MtosTruth] = request.getfixturevalue(fixture)
    ecc, f = _processed(run)
    truth = run.truth.steps
    fits = [s.representable for s in truth]
    assert sum(fits) >= 9  # experiments 1 and 2 stay where (4.11) holds
    assert np.abs(ecc.chi[fits] - [s.chi for s in truth if s.representable]).max() < 0.02
    assert f == pytest.approx([s.friction for s in truth], rel=0.05)


def test_film_viscosity_from_the_thermocouples(short_run: SimulatedRun[mtos.MtosTruth]) -> None:
    rows = short_run.columns("steps")
    law = SHORT.configuration.viscosity
    mu = bearing_readings.mtos_film_viscosity(
        t3=rows["t3"], t4=rows["t4"], t5=rows["t5"], A=law.A, alpha=law.alpha
    ).mean
    # thermocouples read to 0.1 °C: α·0.1 = 0.5 % of μ
    assert mu == pytest.approx([s.viscosity for s in short_run.truth.steps], rel=0.01)


def test_fluid_steps_sit_where_ocvirks_film_carries_the_load(
    short_run: SimulatedRun[mtos.MtosTruth],
) -> None:
    c = SHORT.configuration
    for step in short_run.truth.steps[:6]:
        force = bearing.short_bearing_load(
            chi=step.chi,
            omega=c.omega,
            viscosity=step.viscosity,
            bearing_radius=c.diameter / 2,
            width=c.width,
            clearance=c.clearance,
        )
        assert float(force.resultant) == pytest.approx(step.load, rel=1e-6)
        assert step.film == "fluid"


def test_attitude_angle_is_delta_of_4_12(short_run: SimulatedRun[mtos.MtosTruth]) -> None:
    ecc, _ = _processed(short_run)
    delta = bearing_readings.mtos_attitude_angles(e_x=ecc.e_x[:6], e_y=ecc.e_y[:6]).delta
    truth = [s.angle for s in short_run.truth.steps[:6]]
    assert np.degrees(delta) == pytest.approx(np.degrees(truth), abs=2.0)


def test_heat_balance_closes(short_run: SimulatedRun[mtos.MtosTruth]) -> None:
    # M·ω = (ρ c_p Q + G)(t_film - t_in) at every step (4.19: the film is hotter than t1)
    for step in short_run.truth.steps:
        drops = {2: SHORT.drops_mixed, 3: SHORT.drops_boundary}.get(step.regime)
        flow = SHORT.oil_flow if drops is None else drops * DROP_VOLUME / 60.0
        g = OIL_DENSITY * OIL_HEAT_CAPACITY * flow + SHORT.conductance
        rise = step.film_temperature - SHORT.inlet_temperature
        assert step.friction_moment * SHORT.configuration.omega == pytest.approx(g * rise, rel=1e-4)


def test_stribeck_fluid_branch_and_starved_friction(
    short_run: SimulatedRun[mtos.MtosTruth],
) -> None:
    steps = short_run.truth.steps
    fluid = [s.friction for s in steps[:6]]
    assert all(a > b for a, b in itertools.pairwise(fluid))  # f falls as N rises
    assert all(5e-4 < f < 0.02 for f in fluid)  # fluid friction, manual: 0.0005..0.005 and up
    h_crit = short_run.truth.h_crit
    assert h_crit == pytest.approx(1.6e-6 + 3.2e-6)  # journal + bush asperities (seed 001)
    fb = SHORT.boundary_friction
    c = SHORT.configuration
    roughness = np.hypot(c.journal_rq, c.bush_rq)
    for step in steps[9:]:
        # h_min = Λ·√(Rq_j² + Rq_b²) with Λ = 0.5, and f = f_b + (f_film - f_b)·h_min/h_crit
        # with 0 < f_film < f_b
        ratio = SHORT.film_parameter_boundary * roughness / h_crit
        assert step.film == "boundary"
        assert step.film_parameter == pytest.approx(SHORT.film_parameter_boundary)
        assert step.h_min == pytest.approx(ratio * h_crit)
        assert (1.0 - ratio) * fb < step.friction < fb
    assert all(s.film == "mixed" for s in steps[6:9])
    assert all(s.film_parameter == pytest.approx(2.5) for s in steps[6:9])


def test_4_11_folds_a_component_beyond_h0_cos45(short_run: SimulatedRun[mtos.MtosTruth]) -> None:
    ecc, _ = _processed(short_run)
    c = SHORT.configuration
    for i, step in enumerate(short_run.truth.steps):
        if step.representable:
            continue
        # the |X_уст - X| of (4.11) reflects e_x about h0·cos45°: e_x' = 2·h0·cos45° - e_x
        limit = c.clearance * COS45
        folded = [2 * limit - e if e > limit else e for e in (step.e_x, step.e_y)]
        assert ecc.chi[i] == pytest.approx(np.hypot(folded[0], folded[1]) / c.clearance, abs=0.01)
        assert ecc.chi[i] < step.chi


def test_settings_are_checked() -> None:
    with pytest.raises(SettingsError, match=r"load must lie in \(0, 10000\] N"):
        mtos.MtosSettings(loads_fluid=(0.0,))
    with pytest.raises(SettingsError, match="boundary_friction must lie in"):
        replace(SHORT, boundary_friction=1.5)
