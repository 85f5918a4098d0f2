"""rigsim.simulators.smts2: the friction record and the weighings give back the truth."""

from __future__ import annotations

import numpy as np
import pytest

from rigserver.core import wear
from rigsim.batches import SimulatedRun
from rigsim.errors import SettingsError
from rigsim.simulators import smts2
from schemas.channels import check_columns
from schemas.stands import SMTS2_GROUPS, Smts2Config

R2 = 0.0225  # disc radius r2 (manual, lab 2)
R1 = 0.005  # pin radius r1 = d1/2


@pytest.fixture(scope="module")
def run() -> SimulatedRun[smts2.Smts2Truth]:
    return smts2.simulate(seed=5)


def _friction(run: SimulatedRun[smts2.Smts2Truth]) -> np.ndarray:
    rows = run.columns("friction")
    return wear.friction_coefficient(
        friction_moment=rows["friction_moment"], load=rows["load"], radius=R2
    )


def test_every_batch_passes_the_servers_check_in_order(
    run: SimulatedRun[smts2.Smts2Truth],
) -> None:
    groups = {g.name: g for g in SMTS2_GROUPS}
    last: dict[str, float] = {}
    for batch in run.batches:
        group = groups[batch.group]
        assert check_columns(group, batch.columns, last) == []
        if group.aligned:
            last = {k: float(v[-1]) for k, v in batch.columns.items()}
    # the weighing first, the record in 300-row batches, the second weighing last
    assert [b.group for b in (run.batches[0], run.batches[-1])] == ["measurements"] * 2
    assert run.batches[-1].at > run.batches[-2].at


def test_archard_truth_in_closed_form(run: SimulatedRun[smts2.Smts2Truth]) -> None:
    t = run.truth
    # 15 000 rev at 1000 rpm less 2 % slip: the counter stops at 150 (hundreds)
    assert t.speed == pytest.approx(980.0)
    assert 15_000.0 <= t.revolutions < 15_000.0 + 980.0 / 60.0 / 10.0 + 1e-9
    assert t.sliding_distance == pytest.approx(2 * np.pi * R2 * t.revolutions, rel=1e-12)
    # I_h = V/(π r1² L) = k·N/(π r1²) = 1e-14·300/(π·0.005²) = 3.8197e-8
    assert t.intensity == pytest.approx(1e-14 * 300.0 / (np.pi * R1**2), rel=1e-12)
    assert t.intensity == pytest.approx(3.8197e-8, rel=1e-4)
    # tens of milligrams off the pin (models.md, section 2): ρ·k·N·L = 49.6 mg
    assert t.mass_loss == pytest.approx(7800.0 * 1e-14 * 300.0 * t.sliding_distance, rel=1e-12)


def test_weighings_and_counter_give_back_the_wear_intensity(
    run: SimulatedRun[smts2.Smts2Truth],
) -> None:
    m = run.columns("measurements")
    counter = run.columns("friction")["revolutions"]
    assert counter[0] == 0.0 and counter[-1] == 150.0
    measured = wear.wear_intensity_experimental(
        mass_before=m["pin_mass_before"][0] * 1e-3,
        mass_after=m["pin_mass_after"][0] * 1e-3,
        density=7800.0,
        pin_radius=R1,
        disc_radius=R2,
        revolutions=(counter[-1] - counter[0]) * 100.0,
    )
    # balance 0.1 mg on 50 mg, the counter's last hundred: well inside 2 %
    assert measured.intensity == pytest.approx(run.truth.intensity, rel=0.02)
    assert m["disc_ra"][0] == pytest.approx(0.5)  # μm


def test_friction_runs_in_to_its_steady_value(run: SimulatedRun[smts2.Smts2Truth]) -> None:
    f = _friction(run)
    steady = wear.steady_friction(f=f, fraction=0.5)
    assert steady.mean == pytest.approx(run.truth.friction_steady, rel=0.02)
    # the first second starts near f0 = 0.6 (the transient decays over 300 rev = 18 s)
    assert f[:10].mean() == pytest.approx(run.truth.friction_start, rel=0.08)
    assert np.all(run.columns("friction")["friction_moment"] <= 15.0)


def test_adhesive_rubs_harder_than_oxidative() -> None:
    f = {
        mode: wear.steady_friction(
            f=_friction(smts2.simulate(smts2.Smts2Settings.for_mode(mode), seed=1)), fraction=0.5
        ).mean
        for mode in ("adhesive", "oxidative")
    }
    # (2.16) with the modes' steady values 0.55 and 0.30: (0.55 - 0.30)/0.55 = 45.5 %
    delta = wear.adhesive_oxidative_difference(f_adhesive=f["adhesive"], f_oxidative=f["oxidative"])
    assert delta == pytest.approx(100 * (0.55 - 0.30) / 0.55, abs=3.0)


def test_mode_defaults_are_the_manuals() -> None:
    # lab 2, procedure: adhesive 200 N and oxidative 300 N, 2000 rev each; changes apply on top
    adhesive = smts2.Smts2Settings.for_mode("adhesive")
    assert (adhesive.load, adhesive.revolutions) == (200.0, 2000.0)
    oxidative = smts2.Smts2Settings.for_mode("oxidative", speed=500.0)
    assert (oxidative.load, oxidative.revolutions, oxidative.speed) == (300.0, 2000.0, 500.0)


def test_settings_outside_the_machine_are_refused() -> None:
    with pytest.raises(SettingsError, match=r"load must lie in \[200, 5000\] N, got 100"):
        smts2.Smts2Settings(load=100.0)
    with pytest.raises(SettingsError, match=r"speed must be one of \(300.0, 500.0, 1000.0\)"):
        smts2.Smts2Settings(speed=750.0)
    # 0.6·(1 + 4·0.04)·1500 N·0.0225 m = 23.5 N·m: the machine stops above 15 N·m
    with pytest.raises(SettingsError, match=r"would reach 23.5 N\*m: the machine stops above 15"):
        smts2.Smts2Settings(load=1500.0)
    with pytest.raises(SettingsError, match="mode must be one of"):
        smts2.Smts2Settings.for_mode("abrasive")  # type: ignore[arg-type]


def test_configuration_is_posted_with_the_run(run: SimulatedRun[smts2.Smts2Truth]) -> None:
    assert run.run_create.stand.value == "smts2"
    assert Smts2Config.model_validate(run.run_create.configuration) == Smts2Config()
    assert run.run_create.test_plan["mode"] == "wear"
