"""An instrument's own roughness profile (issue 37, item 4): not filtered again, evaluated
over its whole length in its sampling lengths, each parameter the mean over them (ISO 4287,
ISO 4288); checked against a sine's closed forms (the API: tests/api/test_instrument_profile.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rigserver.core.errors import ModelInputError
from rigserver.core.iso_roughness import instrument_roughness, iso_profile


def sine(
    amplitude: float, wavelength: float, per_wave: int, waves: int
) -> tuple[np.ndarray, np.ndarray]:
    """A sine of ``waves`` whole periods, ``per_wave`` samples each (m)."""
    x = np.arange(per_wave * waves) * (wavelength / per_wave)
    return x, amplitude * np.sin(2.0 * math.pi * x / wavelength)


@settings(max_examples=40, deadline=None)
@given(
    amplitude=st.floats(0.05e-6, 20e-6),
    wavelength=st.floats(20e-6, 400e-6),
    per_wave=st.sampled_from([400, 800, 1200]),
    waves_per_section=st.integers(1, 4),
    sections=st.integers(1, 7),
)
def test_a_sine_gives_its_closed_forms(
    amplitude: float, wavelength: float, per_wave: int, waves_per_section: int, sections: int
) -> None:
    x, z = sine(amplitude, wavelength, per_wave, waves_per_section * sections)
    found = instrument_roughness(x, z, sections=sections, lambda_c=0.8e-3, lambda_s=2.5e-6)
    p = found.parameters
    # whole periods in every section, N samples a period, N a multiple of 4 (the crests
    # sampled): Rq = A/√2, Rku = 3/2 and Rp = Rv = A exactly; Ra = 2A/π as the rectangle
    # rule has it, the mean of |sin| over N samples (2/N)·cot(π/N) (Σ sin(2πk/N) over a
    # half period is cot(π/N)), 2A/π to π²/(3N²) + π⁴/(45N⁴) relative
    assert p.rq == pytest.approx(amplitude / math.sqrt(2.0), rel=1e-12)
    assert p.ra == pytest.approx(amplitude * 2.0 / per_wave / math.tan(math.pi / per_wave))
    assert p.ra == pytest.approx(
        2.0 * amplitude / math.pi, rel=math.pi**2 / (3 * per_wave**2) * 1.01
    )
    assert p.rsk == pytest.approx(0.0, abs=1e-9)
    assert p.rku == pytest.approx(1.5, rel=1e-9)
    assert p.rp == pytest.approx(amplitude, rel=1e-12)
    assert p.rv == pytest.approx(amplitude, rel=1e-12)
    assert p.rz == pytest.approx(2.0 * amplitude, rel=1e-12)
    assert p.rt == pytest.approx(2.0 * amplitude, rel=1e-12)
    # RΔq: the slope's rms, 2πA/(λ√2); ISO 4287's seven-point difference errs by O((kh)⁶),
    # the profile's three end samples at each side (second-order differences) by A·k·(kh)²/3
    # at most, kh = 2π/N: a section of n_s samples holding them moves its mean square by
    # 3/n_s·2·(Ak)²(kh)²/3, its rms by 2(kh)²/n_s relative; the first and the last section
    # of the n/n_s: the mean over them by 4(kh)²/n
    kh = 2.0 * math.pi / per_wave
    rdq = 2.0 * math.pi * amplitude / (wavelength * math.sqrt(2))
    assert p.rdq == pytest.approx(rdq, rel=4.0 * kh**2 / x.size + 1e-12)
    # RSm: one element a period (whole elements between upward crossings: two periods of a
    # section starting on a crossing hold one, and RSm needs two)
    if waves_per_section >= 3:
        assert p.rsm == pytest.approx(wavelength, rel=2.0 / per_wave)
    # evaluated whole, in the sections given, the instrument's cut-offs reported
    assert (found.start, found.stop, found.sections) == (0, x.size, sections)
    assert found.evaluation_length == pytest.approx(x.size * (wavelength / per_wave))
    assert (found.lambda_c, found.lambda_s, found.ends) == (0.8e-3, 2.5e-6, "instrument")


def test_the_parameters_are_means_over_the_sections() -> None:
    # two sections of sines of amplitudes 1 and 3 µm: Rq is the mean of A/√2 over them,
    # 2/√2 µm, where the whole length's Rq would be √((1 + 9)/4) = 1.58 µm; Rt the larger 6 µm
    x1, z1 = sine(1e-6, 100e-6, 400, 4)
    _, z2 = sine(3e-6, 100e-6, 400, 4)
    x = np.r_[x1, x1 + 400e-6]
    found = instrument_roughness(x, np.r_[z1, z2], sections=2).parameters
    assert found.rq == pytest.approx(2e-6 / math.sqrt(2.0), rel=1e-12)
    assert found.rz == pytest.approx(4e-6, rel=1e-12)
    assert found.rt == pytest.approx(6e-6, rel=1e-12)


def test_a_roughness_profile_is_not_filtered_again() -> None:
    # a sine of 1 mm on a 5 mm trace: the primary path's 0.8 mm Gaussian filter takes most
    # of it as waviness and cuts λc from the ends; the instrument's profile keeps it whole
    x, z = sine(1e-6, 1e-3, 400, 5)
    primary = iso_profile(x, z, lambda_c=0.8e-3)
    given_r = instrument_roughness(x, z, sections=5, lambda_c=0.8e-3)
    assert given_r.parameters.ra == pytest.approx(
        2e-6 / math.pi, rel=math.pi**2 / (3 * 400**2) * 1.01
    )
    assert primary.parameters.ra < 0.8 * given_r.parameters.ra
    assert primary.stop - primary.start < x.size


def test_bad_sections_are_refused() -> None:
    x, z = sine(1e-6, 100e-6, 400, 2)
    with pytest.raises(ModelInputError, match="sections must lie in"):
        instrument_roughness(x, z, sections=0)
    with pytest.raises(ModelInputError, match="lambda_c must be >= 0"):
        instrument_roughness(x, z, sections=1, lambda_c=-1.0)
