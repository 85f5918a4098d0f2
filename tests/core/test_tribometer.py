"""The tribometers' formulas against closed forms and limits (docs/models.md, section 6)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from rigserver.core import tribometer
from rigserver.core.errors import ModelInputError


def test_effective_modulus_of_two_equal_steels() -> None:
    # 1/E* = 2(1 - ν²)/E: two 210 GPa steels, ν = 0.3 -> E* = 115.4 GPa
    e = tribometer.effective_modulus(youngs_1=210e9, poisson_1=0.3, youngs_2=210e9, poisson_2=0.3)
    assert e == pytest.approx(210e9 / (2 * (1 - 0.09)), rel=1e-15)


@given(
    load=st.floats(0.1, 1000.0),
    radius=st.floats(1e-4, 0.05),
    modulus=st.floats(1e9, 5e11),
)
def test_hertz_p0_is_the_closed_form(load: float, radius: float, modulus: float) -> None:
    # p0 = (6FE*²/(π³R²))^(1/3) (Johnson 1985, (4.23)) and p0 = 3F/(2πa²), a = (3FR/4E*)^(1/3)
    h = tribometer.hertz_ball_on_flat(load=load, ball_radius=radius, modulus=modulus)
    assert h.max_pressure == pytest.approx(
        (6 * load * modulus**2 / (math.pi**3 * radius**2)) ** (1 / 3), rel=1e-12
    )
    assert h.mean_pressure == pytest.approx(2 * h.max_pressure / 3, rel=1e-12)
    assert math.pi * h.radius**2 * h.mean_pressure == pytest.approx(load, rel=1e-12)


def test_hertz_of_a_steel_ball_on_steel() -> None:
    # a 6 mm steel ball on steel at 10 N: a = (3·10·0.003/(4·115.38 GPa))^(1/3) = 58.0 µm,
    # p0 = 3·10/(2π a²) = 1.42 GPa (worked by hand from Johnson's (4.22)-(4.23))
    e = tribometer.effective_modulus(youngs_1=210e9, poisson_1=0.3, youngs_2=210e9, poisson_2=0.3)
    h = tribometer.hertz_ball_on_flat(load=10.0, ball_radius=3e-3, modulus=e)
    assert h.radius == pytest.approx(58.0e-6, rel=2e-3)
    assert h.max_pressure == pytest.approx(1.42e9, rel=3e-3)


def test_spherical_cap_limits() -> None:
    r = 3e-3
    # d = 2R: the scar is the ball's equator, the cap a hemisphere 2πR³/3
    assert tribometer.spherical_cap_volume(scar_diameter=2 * r, ball_radius=r) == pytest.approx(
        2 * math.pi * r**3 / 3, rel=1e-12
    )
    assert tribometer.spherical_cap_volume(scar_diameter=0.0, ball_radius=r) == 0.0
    with pytest.raises(ModelInputError, match="scar_diameter"):
        tribometer.spherical_cap_volume(scar_diameter=2.1 * r, ball_radius=r)


@given(ratio=st.floats(1e-6, 0.05))
def test_small_scars_tend_to_g99s_approximation(ratio: float) -> None:
    # V = πd⁴/(64R)·(1 + O((d/R)²)) for d ≪ R (ASTM G99): the exact cap's next term is
    # (1/8)(d/2R)²... so the two agree to (d/R)² at most
    r = 3e-3
    d = ratio * r
    exact = tribometer.spherical_cap_volume(scar_diameter=d, ball_radius=r)
    approx = math.pi * d**4 / (64 * r)
    assert exact == pytest.approx(approx, rel=ratio**2)


def test_volumes_of_the_track_and_the_pin() -> None:
    assert tribometer.disc_track_volume(area=2e-10, track_radius=0.01) == pytest.approx(
        2 * math.pi * 0.01 * 2e-10
    )
    assert tribometer.stroke_track_volume(area=2e-10, stroke_length=0.01) == pytest.approx(2e-12)
    assert tribometer.flat_pin_volume(diameter=4e-3, height_loss=1e-5) == pytest.approx(
        math.pi * 4e-6 * 1e-5
    )
    assert tribometer.specific_wear_rate(volume=1e-12, load=10.0, distance=100.0) == 1e-15
    with pytest.raises(ModelInputError, match="load"):
        tribometer.specific_wear_rate(volume=1e-12, load=0.0, distance=100.0)


def test_segment_means_and_the_lap_map() -> None:
    laps = np.arange(0, 3, 0.25)  # three laps, four readings each
    values = np.arange(laps.size, dtype=float)
    index, means, counts = tribometer.segment_means(np.floor(laps), values)
    assert index.tolist() == [0, 1, 2] and means.tolist() == [1.5, 5.5, 9.5]
    assert counts.tolist() == [4, 4, 4]
    found = tribometer.lap_map(laps=laps, values=values, rows=3, bins=4)
    assert found.values.tolist() == [[0, 1, 2, 3], [4, 5, 6, 7], [8, 9, 10, 11]]
    assert found.angle.tolist() == [45.0, 135.0, 225.0, 315.0]
    # two laps a row: the cells average the laps' readings at one angle; a row left empty
    grouped = tribometer.lap_map(laps=laps, values=values, rows=2, bins=4)
    assert grouped.lap.tolist() == [1.0, 3.0]
    assert grouped.values[0].tolist() == [2.0, 3.0, 4.0, 5.0]
    with pytest.raises(ModelInputError, match="decrease"):
        tribometer.segment_means([1, 0], [1.0, 2.0])


@given(mean=st.floats(0.05, 1.0), amplitude=st.floats(0.0, 0.2), phase=st.floats(0, 6.28))
def test_the_once_per_lap_part_is_found(mean: float, amplitude: float, phase: float) -> None:
    laps = np.arange(0, 10, 1 / 50)
    values = mean + amplitude * np.sin(2 * np.pi * laps + phase)
    c, a = tribometer.lap_harmonic(laps=laps, values=values)
    assert c == pytest.approx(mean, rel=1e-9)
    assert a == pytest.approx(amplitude, abs=1e-12)
