"""rigsim.thermal: the steady heat balance against closed forms."""

from __future__ import annotations

import pytest

from rigsim.errors import SettingsError
from rigsim.thermal import OIL_DENSITY, OIL_HEAT_CAPACITY, HeatBalance, steady_film_temperature

# 1e-6 m³/s of oil carries ρ·c_p·Q = 870·1900·1e-6 = 1.653 W/K; with 2 W/K of conduction
BALANCE = HeatBalance(oil_flow=1e-6, conductance=2.0)
G = OIL_DENSITY * OIL_HEAT_CAPACITY * 1e-6 + 2.0


def test_total_conductance() -> None:
    assert pytest.approx(3.653) == G
    assert BALANCE.total == pytest.approx(G, rel=1e-12)


def test_constant_power_gives_t_in_plus_p_over_g() -> None:
    hot = steady_film_temperature(power=lambda t: 36.53, inlet=20.0, balance=BALANCE)
    assert hot.temperature == pytest.approx(20.0 + 36.53 / G, abs=1e-4)


def test_power_falling_with_temperature_settles_lower() -> None:
    # P = P0 - k (t - t_in): the balance G (t - t_in) = P0 - k (t - t_in) gives
    # t = t_in + P0/(G + k): the film's self-regulation in closed form
    p0, k = 50.0, 1.5
    hot = steady_film_temperature(power=lambda t: p0 - k * (t - 25.0), inlet=25.0, balance=BALANCE)
    assert hot.temperature == pytest.approx(25.0 + p0 / (G + k), abs=1e-4)
    assert hot.power == pytest.approx(p0 - k * (hot.temperature - 25.0), rel=1e-9)


def test_power_rising_slower_than_the_balance_is_found_from_below() -> None:
    # P = P0 + k (t - t_in) with k < G: t = t_in + P0/(G - k)
    p0, k = 10.0, 2.0
    hot = steady_film_temperature(power=lambda t: p0 + k * (t - 20.0), inlet=20.0, balance=BALANCE)
    assert hot.temperature == pytest.approx(20.0 + p0 / (G - k), abs=1e-3)


def test_no_power_no_rise() -> None:
    assert (
        steady_film_temperature(power=lambda t: 0.0, inlet=30.0, balance=BALANCE).temperature
        == 30.0
    )


def test_runaway_and_overheating_are_refused() -> None:
    # 1000 W need 274 K over the inlet: beyond the 150 K considered
    with pytest.raises(SettingsError, match="would overheat"):
        steady_film_temperature(power=lambda t: 1000.0, inlet=20.0, balance=BALANCE)
    # P = 1 + G (t - t_in) has no root: the warm-up climbs by 1/G = 0.27 K a step for ever
    with pytest.raises(SettingsError, match=r"thermal runaway: .* after 200 steps"):
        steady_film_temperature(power=lambda t: 1.0 + G * (t - 20.0), inlet=20.0, balance=BALANCE)


def test_a_balance_needs_a_way_out() -> None:
    with pytest.raises(SettingsError, match="needs some way out"):
        HeatBalance(oil_flow=0.0, conductance=0.0)
    with pytest.raises(SettingsError, match="oil_flow must be >= 0"):
        HeatBalance(oil_flow=-1.0, conductance=1.0)
