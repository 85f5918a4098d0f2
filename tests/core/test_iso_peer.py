"""The ISO analysis against surfalize (a peer, not a reference) on the same profiles.

Where both follow the standard they agree; where they differ the difference is one that
``docs/roughness.md`` explains: surfalize re-centres the ordinates on their own mean (the
standard measures them from the λc mean line), cuts its Gaussian kernel at 4σ = 0.75 λc
(here at λc) and extends the ends by reflection (here: discarded, or renormalised weights),
takes the slope by a forward difference (here: the seven-point formula) and samples the
material ratio curve at 10 000 classes (here: every ordinate).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from scipy.ndimage import gaussian_filter1d

from rigserver.core import iso_roughness as iso

surfalize = pytest.importorskip("surfalize", reason="surfalize (dev dependency) not installed")
from surfalize.filter import GaussianFilter  # noqa: E402

UM = 1e6  # surfalize works in µm
STEP = 0.5e-6


def _profiles() -> dict[str, np.ndarray]:
    x = np.arange(9601) * STEP  # 4.8 mm: five sections of 0.8 mm after the run-up and -out
    rng = np.random.default_rng(3)
    honed = gaussian_filter1d(rng.standard_normal(x.size), 8) * 3e-6
    return {
        "sine": 1e-6 * np.sin(2 * np.pi * x / 80e-6),
        "gaussian": gaussian_filter1d(rng.standard_normal(x.size), 10) * 3e-6,
        "plateau": np.where(honed > 0, 0.3 * honed, honed),  # peaks cut: Rsk < 0
    }


PROFILES = _profiles()


@pytest.fixture(params=list(PROFILES), scope="module")
def pair(request: pytest.FixtureRequest) -> tuple[iso.IsoProfile, np.ndarray]:
    """Our analysis of a profile, and surfalize's roughness profile of the same primary
    profile over our evaluation length (µm)."""
    z = PROFILES[request.param]
    ours = iso.iso_profile(np.arange(z.size) * STEP, z)
    primary = surfalize.Profile(ours.primary * UM, STEP * UM)
    theirs = GaussianFilter(ours.lambda_c * UM, "highpass")(primary)
    return ours, np.asarray(theirs.data[ours.start : ours.stop])


def same_ordinates(ours: iso.IsoProfile) -> tuple[np.ndarray, Any]:
    """Our roughness profile over the evaluation length, and surfalize's profile of these
    same ordinates (µm)."""
    r = ours.roughness[ours.start : ours.stop]
    return r, surfalize.Profile(r * UM, STEP * UM)


def test_the_filters_agree_over_the_evaluation_length(
    pair: tuple[iso.IsoProfile, np.ndarray],
) -> None:
    # the same Gaussian (σ = αλc/√(2π)); the kernels' lengths differ by the weight beyond
    # 0.75 λc, e^(-π(0.75/α)²) ≈ 3·10⁻⁴ of the peak. At the edges of the evaluation length,
    # λc/2 = 2.67σ from the trace's ends, 0.4 % of either kernel still reaches the end
    # handling (reflection there, renormalisation here); λc/4 further in, none does
    ours, theirs = pair
    r = ours.roughness[ours.start : ours.stop] * UM
    rq = np.sqrt(np.mean(r**2))
    assert np.max(np.abs(r - theirs)) < 5e-3 * rq
    inner = slice(round(ours.lambda_c / 4 / STEP), -round(ours.lambda_c / 4 / STEP))
    assert np.max(np.abs(r - theirs)[inner]) < 2e-4 * rq


def test_the_parameters_agree_on_the_same_ordinates(
    pair: tuple[iso.IsoProfile, np.ndarray],
) -> None:
    ours, _ = pair
    r, peer = same_ordinates(ours)
    centred = r - r.mean()  # surfalize measures from the ordinates' own mean
    n = ours.sections
    heights = iso.section_heights(centred, sections=n)
    assert iso.arithmetic_mean_height(centred) * UM == pytest.approx(peer.Ra(), rel=1e-9)
    assert iso.root_mean_square_height(centred) * UM == pytest.approx(peer.Rq(), rel=1e-9)
    assert iso.skewness(centred) == pytest.approx(peer.Rsk(), rel=1e-9, abs=1e-12)
    assert iso.kurtosis(centred) == pytest.approx(peer.Rku(), rel=1e-9)
    assert heights.rp * UM == pytest.approx(peer.Rp(n), rel=1e-9)
    assert heights.rv * UM == pytest.approx(peer.Rv(n), rel=1e-9)
    assert heights.rz * UM == pytest.approx(peer.Rz(n), rel=1e-9)
    assert iso.total_height(r) * UM == pytest.approx(peer.Rt(), rel=1e-9)


def test_the_centring_is_the_only_difference_of_the_height_parameters(
    pair: tuple[iso.IsoProfile, np.ndarray],
) -> None:
    # the mean of R over the evaluation length is a small fraction of Rq: Ra, Rq, Rku, Rz
    # move by O((mean/Rq)²), Rsk by 3·mean/Rq (d/dm of E(z-m)³/Rq³ at m = 0)
    ours, _ = pair
    r, peer = same_ordinates(ours)
    q = ours.parameters
    shift = abs(float(r.mean())) / q.rq
    assert shift < 0.05
    assert q.ra * UM == pytest.approx(peer.Ra(), rel=2 * shift + 1e-9)
    assert q.rq * UM == pytest.approx(peer.Rq(), rel=shift**2 + 1e-9)
    assert q.rku == pytest.approx(peer.Rku(), rel=10 * shift + 1e-9)
    assert abs(q.rsk - peer.Rsk()) < 3.5 * shift + 1e-9


def test_the_slope_differs_by_the_difference_formula(
    pair: tuple[iso.IsoProfile, np.ndarray],
) -> None:
    # a forward difference has an error of order (k·Δx)²/24 at wavenumber k: below 0.5 %
    # for these profiles, whose shortest wavelengths are some 50 samples long
    ours, _ = pair
    _, peer = same_ordinates(ours)
    assert ours.parameters.rdq == pytest.approx(peer.Rdq(), rel=5e-3)


def test_the_rk_family_agrees(pair: tuple[iso.IsoProfile, np.ndarray]) -> None:
    # both: the 40 % window of least secant gradient, then least squares in it (surfalize
    # since 0.17.1); surfalize's curve has 10 000 classes and its peak and valley areas
    # stop at the class nearest the core's levels, which moves Rpk and Rvk by up to 3 %
    ours, _ = pair
    _, peer = same_ordinates(ours)
    q = ours.parameters
    assert q.rk * UM == pytest.approx(peer.Rk(), rel=5e-3)
    assert q.rpk * UM == pytest.approx(peer.Rpk(), rel=3e-2, abs=1e-4)
    assert q.rvk * UM == pytest.approx(peer.Rvk(), rel=3e-2, abs=1e-4)
    assert q.mr1 == pytest.approx(peer.Rmr1(), abs=0.05)
    assert q.mr2 == pytest.approx(peer.Rmr2(), abs=0.05)


def test_the_ends_differ_by_their_handling() -> None:
    # in the run-up (λc/2) surfalize reflects the profile, the analysis renormalises the
    # weights; both leave the evaluation length alone, which is why it starts λc/2 in
    z = PROFILES["gaussian"]
    ours = iso.iso_profile(np.arange(z.size) * STEP, z)
    theirs = GaussianFilter(ours.lambda_c * UM, "highpass")(
        surfalize.Profile(ours.primary * UM, STEP * UM)
    ).data
    rq = ours.parameters.rq * UM
    head = slice(0, ours.start)
    inside = slice(ours.start, ours.stop)
    assert np.max(np.abs(ours.roughness[head] * UM - theirs[head])) > 0.02 * rq
    assert np.max(np.abs(ours.roughness[inside] * UM - theirs[inside])) < 5e-3 * rq
