"""rigsim.simulators.profilometer: the trace's Ra, the bearing-curve shape, the correlation."""

from __future__ import annotations

import numpy as np
import pytest

from rigserver.core import roughness
from rigsim.errors import SettingsError
from rigsim.simulators import profilometer as pm
from schemas.channels import check_columns
from schemas.stands import PROFILOMETER_GROUPS


def test_trace_passes_the_check_and_gives_back_ra() -> None:
    run = pm.simulate(seed=2)
    groups = {g.name: g for g in PROFILOMETER_GROUPS}
    last: dict[str, float] = {}
    for batch in run.batches:
        assert check_columns(groups[batch.group], batch.columns, last) == []
        if batch.group == "profile":
            last = {k: float(v[-1]) for k, v in batch.columns.items()}
    trace = run.columns("profile")
    # 0.8 mm at 0.5 μm steps: 1601 points (Ra 0.8 μm is in the 0.4-3.2 μm subrange, cutoff 0.8 mm)
    assert trace["x"].size == 1601
    assert run.columns("measurements")["base_length"].tolist() == [0.8]
    assert run.columns("measurements")["subrange"].tolist() == [3.2]
    # the truth is the Ra asked for; the instrument's tilt, offset, noise and 1 nm steps
    # (removed or averaged by (1.3)) leave it within 1 %
    assert run.truth.ra == pytest.approx(0.8e-6, rel=1e-9)
    measured = roughness.profile_parameters(x=trace["x"] * 1e-3, y=trace["y"] * 1e-6)
    assert measured.ra == pytest.approx(run.truth.ra, rel=0.01)
    assert measured.rq == pytest.approx(run.truth.rq, rel=0.01)
    assert measured.rmax == pytest.approx(run.truth.rmax, rel=0.01)


@pytest.mark.parametrize(
    ("ra", "subrange", "cutoff"), [(0.3e-6, 0.4e-6, 0.25e-3), (5e-6, 12.5e-6, 2.5e-3)]
)
def test_subrange_and_base_length_follow_ra(ra: float, subrange: float, cutoff: float) -> None:
    # ABRIS-PM7 technical data: Ra 0.04-0.4 μm at 0.25 mm, 3.2-12.5 μm at 2.5 mm
    settings = pm.ProfilometerSettings(ra=ra)
    assert settings.subrange == pytest.approx(subrange)
    assert settings.length == pytest.approx(cutoff)


def test_depth_of_material_ratio_inverts_the_bearing_curve() -> None:
    nu, b = 2.0, 2.0
    t = np.array([0.0, 0.02, 0.1, 0.3, 0.5])
    eps = pm.depth_of_material_ratio(t, nu=nu, b=b)
    # (1.8): t_p = b·ε^ν on the initial part, up to t_p = 1/2 (ε1 = (1/4)^(1/2) = 0.5)
    assert b * eps**nu == pytest.approx(t, abs=1e-15)
    tail = pm.depth_of_material_ratio(np.array([0.5, 0.5 + 1e-9, 0.9, 1.0]), nu=nu, b=b)
    assert tail[0] == pytest.approx(tail[1], abs=1e-8)  # continuous at the join
    assert tail[-1] == 1.0  # the valley line
    grid = pm.depth_of_material_ratio(np.linspace(0, 1, 1001), nu=1.5, b=1.2)
    assert np.all(np.diff(grid) > 0)


def test_correlation_length_of_the_generator() -> None:
    # autocorrelation exp(-(τ/β)²): e^-1 at τ = β; 200 000 samples with β = 10 give an
    # estimate within about 1/√(n/β) = 0.007
    g = pm._correlated(200_000, 10.0, np.random.default_rng(0))
    lag = 10
    rho = float(np.mean(g[:-lag] * g[lag:]))
    assert rho == pytest.approx(np.exp(-1.0), abs=0.03)
    assert float(np.mean(g[:-30] * g[30:])) == pytest.approx(np.exp(-9.0), abs=0.03)


def test_deterministic_from_the_seed() -> None:
    a, b, c = (pm.simulate(seed=s).columns("profile")["y"] for s in (4, 4, 5))
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)


def test_settings_are_checked() -> None:
    with pytest.raises(SettingsError, match="ra must lie in"):
        pm.ProfilometerSettings(ra=20e-6)
    with pytest.raises(SettingsError, match=r"need nu >= 1 and b > 0\.5"):
        pm.ProfilometerSettings(b=0.4)
    with pytest.raises(SettingsError, match="correlation_length must lie in"):
        pm.ProfilometerSettings(correlation_length=0.2e-3)
