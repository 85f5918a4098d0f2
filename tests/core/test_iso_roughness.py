"""The ISO profile analysis (issue 23) against closed forms, the Gaussian transfer function,
Gaussian random profiles and profiles built with a known material ratio curve.

Each expected number says where it comes from."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.ndimage import gaussian_filter1d

from rigserver.core import iso_roughness as iso
from rigserver.core import profile_filter as pf
from rigserver.core.errors import ModelInputError

STEP = 0.5e-6  # m: ISO 3274's largest step for λs = 2.5 µm
A = 1e-6  # m, amplitude of the test waves
WAVE = 80e-6  # m: λc/10 for λc = 0.8 mm, well inside the roughness pass band


def trace(length: float, step: float = STEP) -> np.ndarray:
    return np.arange(round(length / step) + 1) * step


def passed(wavelength: float, lambda_c: float, lambda_s: float) -> float:
    """The fraction of a sine's amplitude in the roughness profile: the λc high-pass times
    the λs low-pass, both by ISO 16610-21 eq. (2)."""
    high = 1.0 - float(pf.transmission(wavelength=wavelength, cutoff=lambda_c))
    low = float(pf.transmission(wavelength=wavelength, cutoff=lambda_s)) if lambda_s else 1.0
    return high * low


# --- the filter -----------------------------------------------------------------------------


def test_alpha_is_that_of_the_standard() -> None:
    # ISO 16610-21, 4.2: α = √(ln 2 / π) = 0.4697
    assert math.isclose(pf.ALPHA, 0.469718639, abs_tol=1e-9)


def test_the_weighting_function_integrates_to_one() -> None:
    x = np.linspace(-2e-3, 2e-3, 40001)
    s = pf.weighting_function(x=x, cutoff=0.8e-3)
    assert np.trapezoid(s, x) == pytest.approx(1.0, rel=1e-9)


def test_a_sine_of_wavelength_lambda_c_passes_at_half_amplitude() -> None:
    # ISO 16610-21, 4.3: the mean line transmits 50 % at λ = λc (so does the roughness)
    lc = 0.8e-3
    x = trace(8e-3, 1e-6)
    z = np.sin(2 * np.pi * x / lc)
    mean = pf.gaussian_mean_line(z=z, step=1e-6, cutoff=lc)
    middle = slice(x.size // 4, 3 * x.size // 4)
    assert _amplitude(x[middle], mean[middle], lc) == pytest.approx(0.5, abs=1e-5)
    assert _amplitude(x[middle], (z - mean)[middle], lc) == pytest.approx(0.5, abs=1e-5)


def _amplitude(x: np.ndarray, y: np.ndarray, wavelength: float) -> float:
    """Amplitude of the sine of ``wavelength`` in ``y``, by least squares."""
    k = 2 * np.pi / wavelength
    basis = np.column_stack([np.sin(k * x), np.cos(k * x), np.ones_like(x)])
    coef, *_ = np.linalg.lstsq(basis, y, rcond=None)
    return float(math.hypot(coef[0], coef[1]))


@settings(max_examples=40, deadline=None)
@given(ratio=st.floats(min_value=0.125, max_value=8.0))
def test_the_filter_follows_the_gaussian_transfer_function(ratio: float) -> None:
    # ISO 16610-21, 4.3, eq. (2): a1/a0 = exp(-π (α λc / λ)²), at any wavelength
    lc = 0.25e-3
    wavelength = ratio * lc
    step = lc / 200
    x = trace(max(12 * lc, 6 * wavelength), step)
    mean = pf.gaussian_mean_line(z=np.sin(2 * np.pi * x / wavelength), step=step, cutoff=lc)
    middle = slice(round(2 * lc / step), x.size - round(2 * lc / step))
    expected = math.exp(-math.pi * (pf.ALPHA * lc / wavelength) ** 2)
    assert _amplitude(x[middle], mean[middle], wavelength) == pytest.approx(expected, abs=2e-5)


def test_the_end_correction_keeps_a_constant() -> None:
    # ISO 16610-28, order 0: renormalised weights pass a constant to the very ends
    mean = pf.gaussian_mean_line(z=np.full(1000, 3.0), step=1e-6, cutoff=0.8e-3)
    assert np.allclose(mean, 3.0, rtol=1e-12)


def test_primary_waviness_and_roughness_add_up() -> None:
    x = trace(4.8e-3)
    z = A * np.sin(2 * np.pi * x / WAVE) + 5 * A * np.sin(2 * np.pi * x / 4e-3) + 2e-3 * x
    fp = pf.filter_profile(x=x, z=z, lambda_c=0.8e-3, lambda_s=2.5e-6)
    assert np.allclose(fp.primary, fp.waviness + fp.roughness, atol=1e-18)
    # λs takes little of these waves; at the very ends the order-0 correction is biased by
    # the slope times the centroid of the one-sided kernel (0.08/µm·0.4 µm ≈ 0.03 A)
    inner = slice(10, -10)
    assert np.allclose((fp.form + fp.primary)[inner], z[inner], atol=0.002 * A)
    assert np.allclose(fp.form + fp.primary, z, atol=0.05 * A)


@pytest.mark.parametrize(
    ("value", "basis", "cutoff"),
    [
        # ISO 21920-3 (ex ISO 4288 tables 1-3): upper limits inclusive
        (0.02e-6, "ra", 0.08e-3),
        (0.05e-6, "ra", 0.25e-3),
        (0.4e-6, "ra", 0.8e-3),
        (2.0e-6, "ra", 0.8e-3),
        (5e-6, "ra", 2.5e-3),
        (20e-6, "ra", 8e-3),
        (0.5e-6, "rz", 0.25e-3),
        (3e-6, "rz", 0.8e-3),
        (50e-6, "rz", 2.5e-3),
        (0.1e-3, "rsm", 0.25e-3),
        (0.3e-3, "rsm", 0.8e-3),
        (1e-3, "rsm", 2.5e-3),
    ],
)
def test_the_table_of_cutoffs(value: float, basis: pf.Basis, cutoff: float) -> None:
    assert pf.cutoff_for(value=value, basis=basis) == cutoff


def test_lambda_s_by_lambda_c() -> None:
    # ISO 3274:1996 table 1, kept by ISO 21920-3
    assert [pf.lambda_s_for(lambda_c=c) for c in pf.CUTOFFS] == [
        2.5e-6,
        2.5e-6,
        2.5e-6,
        8e-6,
        25e-6,
    ]


# --- closed forms ---------------------------------------------------------------------------


def test_a_sine_well_inside_the_pass_band() -> None:
    # A·sin(2πx/λ): Ra = 2A/π, Rq = A/√2, Rsk = 0, Rku = 3/2 (the moments of a sine),
    # RSm = λ, RΔq = (2πA/λ)/√2, Rz = Rt = 2A; each amplitude times what the filters pass
    x = trace(4.8e-3)  # 6 λc: five sections after λc/2 of run-up and run-out
    p = iso.iso_profile(x, A * np.sin(2 * np.pi * x / WAVE) + 3e-4 * x)
    q = p.parameters
    amp = A * passed(WAVE, p.lambda_c, p.lambda_s)
    assert (p.lambda_c, p.lambda_s, p.lambda_c_basis) == (0.8e-3, 2.5e-6, "ra")
    assert (p.ends, p.sections) == ("discarded", 5)
    assert p.evaluation_length == pytest.approx(4e-3, rel=1e-9)
    # the mean of |sin| over 160 samples a period is (2/π)·(1 - O(1/160²))
    assert q.ra == pytest.approx(2 * amp / math.pi, rel=2e-4)
    # (rel 1e-4: the λs kernel, σ = 0.47 µm, is about one sample wide, so its discrete
    # transmission differs from eq. (2)'s by some 10⁻⁵)
    assert q.rq == pytest.approx(amp / math.sqrt(2), rel=1e-4)
    assert q.rsk == pytest.approx(0.0, abs=1e-9)
    assert q.rku == pytest.approx(1.5, rel=1e-4)
    assert q.rsm == pytest.approx(WAVE, rel=1e-4)
    assert q.rdq == pytest.approx(2 * math.pi * amp / WAVE / math.sqrt(2), rel=1e-4)
    assert q.rz == pytest.approx(2 * amp, rel=1e-3)
    assert q.rp == pytest.approx(amp, rel=1e-3) and q.rv == pytest.approx(amp, rel=1e-3)
    assert q.rt == pytest.approx(2 * amp, rel=1e-3)
    assert p.remarks == ()


def test_a_triangle_wave() -> None:
    # a symmetric triangle wave of amplitude A: Ra = A/2, Rq = A/√3, Rku = 9/5 (uniform
    # ordinates); no λs filter, which would round its corners
    x = trace(4.8e-3)
    z = A * (2 / np.pi) * np.arcsin(np.sin(2 * np.pi * x / WAVE))
    q = iso.iso_profile(x, z, lambda_s=0).parameters
    assert q.ra == pytest.approx(A / 2, rel=1e-3)
    assert q.rq == pytest.approx(A / math.sqrt(3), rel=1e-3)
    assert q.rku == pytest.approx(1.8, rel=2e-3)
    assert q.rsm == pytest.approx(WAVE, rel=1e-4)


def test_rsm_ignores_ripples_below_the_discrimination() -> None:
    # a ripple of 5 % of the amplitude at λ/40 crosses the mean line beside each crossing of
    # the sine (its slope is twice the sine's there); below 10 % of Rz it splits no element
    x = trace(4.8e-3)
    z = A * np.sin(2 * np.pi * x / WAVE) + 0.05 * A * np.sin(2 * np.pi * x / (WAVE / 40))
    q = iso.iso_profile(x, z, lambda_s=0).parameters
    assert q.rsm == pytest.approx(WAVE, rel=1e-3)
    assert iso.mean_width(x=x, z=z, height_discrimination=0, spacing_discrimination=0) < WAVE * 0.9


def test_the_material_ratio_of_a_sine() -> None:
    # Z = A sin: Rmr(c) = arccos(c/A)/π, so c(Rmr) = A cos(π Rmr) and
    # Rδc(Rmr1, Rmr2) = A (cos(π Rmr1) - cos(π Rmr2))
    n = 200_000  # one period, densely: the curve does not depend on the order of Z
    z = A * np.sin(2 * np.pi * (np.arange(n) + 0.5) / n)
    for c in (-0.9 * A, -0.3 * A, 0.0, 0.5 * A):
        assert iso.material_ratio(z, level=c) == pytest.approx(
            100 * math.acos(c / A) / math.pi, abs=1e-3
        )
    assert iso.section_height_difference(z, upper=10.0, lower=50.0) == pytest.approx(
        A * (math.cos(0.1 * math.pi) - math.cos(0.5 * math.pi)), rel=1e-4
    )


# --- the Rk family on a known material ratio curve -----------------------------------------


def _known_curve(mr: np.ndarray) -> np.ndarray:
    """Peaks from 3 µm at 0 % to 1 µm at 10 %, a core falling linearly to -1 µm at 90 %,
    valleys from -1 µm to -4 µm at 100 %."""
    return np.interp(mr, [0.0, 10.0, 90.0, 100.0], [3e-6, 1e-6, -1e-6, -4e-6])


def test_the_rk_family_of_a_known_material_ratio_curve() -> None:
    # the core's line c = 1 µm - 0.025 µm/% (Rmr - 10 %) meets 0 % at 1.25 µm and 100 % at
    # -1.25 µm: Rk = 2.5 µm; the peak line meets 1.25 µm at Mr1 = 8.75 % and the valley line
    # -1.25 µm at Mr2 = 90 + 0.25/0.3 = 90.833 %; the peak and valley zones are triangles,
    # so Rpk = 3 - 1.25 = 1.75 µm and Rvk = 4 - 1.25 = 2.75 µm (ISO 13565-2, 4.1-4.3)
    n = 200_000
    z = _known_curve(100 * (np.arange(n) + 0.5) / n)
    rng = np.random.default_rng(0)
    rk = iso.rk_family(rng.permutation(z))  # the order of the ordinates does not count
    assert rk.rk == pytest.approx(2.5e-6, rel=1e-4)
    assert rk.mr1 == pytest.approx(8.75, abs=1e-3)
    assert rk.mr2 == pytest.approx(90 + 0.25 / 0.3, abs=1e-3)
    assert rk.rpk == pytest.approx(1.75e-6, rel=1e-3)
    assert rk.rvk == pytest.approx(2.75e-6, rel=1e-3)


def test_the_rk_family_of_a_plateau_curve() -> None:
    # a steeper plateau: peaks 0-5 % from 2 to 0.5 µm, core 5-80 % from 0.5 to -0.25 µm,
    # valleys 80-100 % to -3 µm. Core slope 0.01 µm/%: line 0.55 µm at 0 %, -0.45 µm at
    # 100 %: Rk = 1 µm; Mr1 where 2 - 0.3 Rmr = 0.55: 4.833 %, Rpk = 2 - 0.55 = 1.45 µm;
    # Mr2 where -0.25 - 0.1375 (Rmr - 80) = -0.45: 81.4545 %, Rvk = 3 - 0.45 = 2.55 µm
    n = 200_000
    mr = 100 * (np.arange(n) + 0.5) / n
    z = np.interp(mr, [0.0, 5.0, 80.0, 100.0], [2e-6, 0.5e-6, -0.25e-6, -3e-6])
    rk = iso.rk_family(z)
    assert rk.rk == pytest.approx(1e-6, rel=1e-4)
    assert rk.mr1 == pytest.approx(1.45 / 0.3, abs=1e-3)
    assert rk.mr2 == pytest.approx(80 + 0.2 / 0.1375, abs=1e-3)
    assert rk.rpk == pytest.approx(1.45e-6, rel=1e-3)
    assert rk.rvk == pytest.approx(2.55e-6, rel=1e-3)


# --- a Gaussian random profile --------------------------------------------------------------


def test_a_gaussian_random_profile_has_rsk_0_and_rku_3() -> None:
    # White noise smoothed by a Gaussian kernel of s samples is a Gaussian process with
    # correlation ρ_k = exp(-k²/(4s²)). Over n ordinates the sample skewness (the mean line
    # at 0, and the high-pass making Σρ_k = 0) has variance (6/n)·Σρ_k³ and the sample
    # kurtosis (24/n)·Σρ_k⁴ (delta method, Hermite polynomials He3 and He4), with
    # Σρ_k^m = √(4πs²/m). Four standard deviations, at a fixed seed.
    s = 10.0
    x = trace(40e-3)  # 49 sections of 0.8 mm
    rng = np.random.default_rng(20)
    z = gaussian_filter1d(rng.standard_normal(x.size), s) * 3e-6
    p = iso.iso_profile(x, z)
    n = p.stop - p.start
    sd_rsk = math.sqrt(6 / n * math.sqrt(4 * math.pi * s**2 / 3))
    sd_rku = math.sqrt(24 / n * math.sqrt(4 * math.pi * s**2 / 4))
    assert abs(p.parameters.rsk) < 4 * sd_rsk
    assert abs(p.parameters.rku - 3.0) < 4 * sd_rku
    assert p.sections == 49


# --- the choice of λc and the short traces --------------------------------------------------


def test_lambda_c_follows_the_table_for_a_finer_profile() -> None:
    # Ra = 2A/π = 0.064 µm lies in (0.02, 0.1] µm: λc = 0.25 mm, λs = 2.5 µm
    x = trace(4.8e-3)
    p = iso.iso_profile(x, 0.1 * A * np.sin(2 * np.pi * x / 25e-6))
    assert (p.lambda_c, p.lambda_s, p.lambda_c_basis) == (0.25e-3, 2.5e-6, "ra")
    assert p.sections == 18


def test_a_trace_shorter_than_two_cutoffs_keeps_its_corrected_ends() -> None:
    x = trace(0.8e-3)
    p = iso.iso_profile(x, A * np.sin(2 * np.pi * x / WAVE))
    assert (p.lambda_c, p.ends, p.sections) == (0.8e-3, "corrected", 1)
    # the corrected ends pass a little less of the sine (the one-sided kernel does not
    # average it to 0): within 1 % here, where discarding them would leave nothing
    assert p.parameters.ra == pytest.approx(2 * A / math.pi, rel=1e-2)
    assert p.remarks == ("short", "few_sections")


def test_a_given_cutoff_is_used() -> None:
    x = trace(4.8e-3)
    p = iso.iso_profile(x, A * np.sin(2 * np.pi * x / WAVE), lambda_c=0.25e-3, lambda_s=0)
    assert (p.lambda_c, p.lambda_s, p.lambda_c_basis) == (0.25e-3, 0.0, "given")


def test_an_uneven_trace_is_resampled() -> None:
    x = trace(4.8e-3)
    x[1:-1] += np.random.default_rng(1).uniform(-0.1, 0.1, x.size - 2) * STEP
    p = iso.iso_profile(x, A * np.sin(2 * np.pi * x / WAVE))
    assert p.resampled and p.parameters.rq == pytest.approx(A / math.sqrt(2), rel=1e-3)


@pytest.mark.parametrize(
    "kwargs",
    [{"lambda_c": 5e-3}, {"lambda_c": -1.0}, {"lambda_s": -1e-6}, {"lambda_s": 1e-3}],
)
def test_bad_settings_are_refused(kwargs: dict[str, float]) -> None:
    x = trace(1e-3)
    with pytest.raises(ModelInputError):
        iso.iso_profile(x, A * np.sin(2 * np.pi * x / WAVE), **kwargs)


def test_a_trace_shorter_than_the_smallest_cutoff_is_refused() -> None:
    x = trace(0.05e-3)
    with pytest.raises(ModelInputError, match="shorter than the smallest"):
        iso.iso_profile(x, A * np.sin(2 * np.pi * x / 10e-6))


def test_every_remark_has_words_in_the_results() -> None:
    from schemas.labels import ISO_REMARKS

    assert set(iso.REMARKS) == set(ISO_REMARKS)


# --- gaps (issue 39, item 1) ----------------------------------------------------------------


@settings(max_examples=60, deadline=None)
@given(
    steps=st.lists(
        st.floats(min_value=1e-9, max_value=1.0, allow_nan=False), min_size=1, max_size=60
    )
)
def test_the_parts_of_any_trace_hold_at_most_the_limit_times_its_points(
    steps: list[float],
) -> None:
    """Whatever its gaps, a trace is resampled into at most RESAMPLING_LIMIT times its points
    (each part's steps are at most that many median steps)."""
    x = np.concatenate([[0.0], np.cumsum(steps)])
    x = x[np.concatenate([[True], np.diff(x) > 0])]
    found = pf.uniform_parts(x, np.zeros_like(x), min_points=1)
    made = sum(px.size for px, _ in found.parts)
    assert made <= pf.RESAMPLING_LIMIT * x.size


def test_a_trace_with_a_gap_is_analysed_in_its_parts() -> None:
    """Two stretches of 4.8 mm, 60 mm apart (a grid of 10⁵ points over 2·10⁴ received): the
    parts are filtered each on its own, and the parameters over both evaluation lengths are
    those of each part alone combined by the definitions: Ra and Rq as means over the
    ordinates (weighted by the evaluation lengths), Rz as the mean over the sections, Rt as
    the larger."""
    first = trace(4.8e-3)
    second = first + 65e-3
    rng = np.random.default_rng(7)
    x = np.concatenate([first, second])
    z = np.concatenate(
        [A * np.sin(2 * np.pi * first / WAVE), 2 * A * np.sin(2 * np.pi * second / WAVE)]
    ) + rng.normal(0, 0.05 * A, x.size)
    assert pf.resampling_size(x) > pf.RESAMPLING_LIMIT * x.size
    both = iso.iso_profile(x, z, lambda_c=0.8e-3)
    one = iso.iso_profile(x[: first.size], z[: first.size], lambda_c=0.8e-3)
    two = iso.iso_profile(x[first.size :], z[first.size :], lambda_c=0.8e-3)
    assert both.parts == 2 and "parts" in both.remarks and both.x.size <= x.size + 2
    assert both.sections == one.sections + two.sections
    le1, le2 = one.evaluation_length, two.evaluation_length
    assert both.evaluation_length == pytest.approx(le1 + le2)
    p, p1, p2 = both.parameters, one.parameters, two.parameters
    assert p.ra == pytest.approx((le1 * p1.ra + le2 * p2.ra) / (le1 + le2), rel=1e-3)
    assert p.rq == pytest.approx(
        math.sqrt((le1 * p1.rq**2 + le2 * p2.rq**2) / (le1 + le2)), rel=1e-3
    )
    s1, s2 = one.sections, two.sections
    assert p.rz == pytest.approx((s1 * p1.rz + s2 * p2.rz) / (s1 + s2), rel=1e-6)
    assert p.rt == pytest.approx(max(p1.rt, p2.rt), rel=1e-9)


def test_a_trace_whose_parts_are_all_too_short_is_refused() -> None:
    x = np.concatenate([trace(5e-6), trace(5e-6) + 1e-3, trace(5e-6) + 2e-3])
    with pytest.raises(ModelInputError, match="gaps"):
        iso.iso_profile(x, np.sin(x))
