"""The fluid-film criterion (seed 001, (2.104)-(2.105))."""

from __future__ import annotations

import numpy as np
import pytest

from rigserver.core.errors import ModelInputError
from rigserver.core.film import (
    critical_film_thickness,
    film_parameter,
    film_regime,
    lambda_regime,
    minimum_film_thickness,
)


def test_critical_thickness_is_the_sum_of_the_five_terms() -> None:
    # Seed 001 gives no numbers (its table 1 is not in the excerpt); terms chosen here:
    # Rz 0.8 μm journal, 1.6 μm bush, 2, 3, 1.5 μm allowances: total 8.9 μm.
    got = critical_film_thickness(
        journal_roughness=0.8e-6,
        bush_roughness=1.6e-6,
        misalignment=2e-6,
        deflection=3e-6,
        shape_error=1.5e-6,
    )
    assert got.total == pytest.approx(8.9e-6, rel=1e-12)
    assert got.bush_roughness == 1.6e-6
    rough_only = critical_film_thickness(journal_roughness=0.8e-6, bush_roughness=1.6e-6)
    assert rough_only.total == pytest.approx(2.4e-6, rel=1e-12)
    assert rough_only.misalignment == 0.0


def test_critical_thickness_rejects_negative_terms() -> None:
    with pytest.raises(ModelInputError, match=r"deflection must be >= 0, got -1e-06"):
        critical_film_thickness(journal_roughness=1e-6, bush_roughness=1e-6, deflection=-1e-6)


def test_regime_flag_edges() -> None:
    h_crit = 5e-6
    assert film_regime(h_min=h_crit, h_crit=h_crit) == "fluid"  # (2.104): h_min >= h_crit
    assert film_regime(h_min=np.nextafter(h_crit, 0.0), h_crit=h_crit) == "mixed"
    assert film_regime(h_min=0.0, h_crit=h_crit) == "mixed"
    assert film_regime(h_min=2e-5, h_crit=h_crit) == "fluid"


def test_minimum_film_thickness() -> None:
    np.testing.assert_allclose(
        minimum_film_thickness(clearance=60e-6, chi=np.array([0.0, 0.75, 1.0])),
        [60e-6, 15e-6, 0.0],
        atol=1e-18,
    )
    with pytest.raises(ModelInputError, match=r"chi must lie in \[0.0, 1.0\], got 1.2"):
        minimum_film_thickness(clearance=60e-6, chi=1.2)


def test_film_parameter_and_its_bands() -> None:
    # Λ = h_min/√(Rq_j² + Rq_b²): 3-4-5 triangle, Rq 0.3 and 0.4 μm -> 0.5 μm composite
    lam = film_parameter(h_min=[0.25e-6, 0.5e-6, 1.5e-6, 2.0e-6], journal_rq=0.3e-6, bush_rq=0.4e-6)
    assert lam == pytest.approx([0.5, 1.0, 3.0, 4.0], rel=1e-12)
    # Hamrock, Schmid and Jacobson: < 1 boundary, 1..3 mixed (both edges), > 3 full film
    assert [lambda_regime(film_parameter=x) for x in lam] == [
        "boundary",
        "mixed",
        "mixed",
        "full film",
    ]
    with pytest.raises(ModelInputError, match="composite roughness"):
        film_parameter(h_min=1e-6, journal_rq=0.0, bush_rq=0.0)
