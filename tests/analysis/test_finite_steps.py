"""The finite bearing at many χ, warm-started and remembered, is the cold solve (issue 14)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rigserver.analysis import mtos
from rigserver.analysis.finite_steps import FiniteBearingSteps
from rigserver.core.reynolds import ReynoldsSolution, solve_reynolds
from tests.analysis.conftest import mtos_on_the_diagonal

#: The active-set iteration ends on the one solution of the complementarity problem whatever
#: it starts from; what may differ is round-off (its flip tolerance is 1e-12 relative).
SOLVER_TOLERANCE = 1e-9


#: A coarser grid than the service's, for the property's many examples
GRID = {"n_phi": 48, "n_z": 16}


@settings(max_examples=25, deadline=None)
@given(
    chis=st.lists(st.floats(0.0, 0.95), min_size=2, max_size=6),
    half_width=st.floats(0.25, 1.5),
)
def test_warm_started_steps_are_the_cold_solves(chis: list[float], half_width: float) -> None:
    steps = FiniteBearingSteps(**GRID)
    steps.solve_all(chis, half_width)
    for chi in chis:
        _same(steps, solve_reynolds(chi=chi, half_width=half_width, **GRID), chi, half_width)


def test_the_service_grid_warm_started_is_the_cold_solve() -> None:
    steps = FiniteBearingSteps()
    chis, half_width = [0.2, 0.31, 0.45, 0.62], 1.0  # the spacing of a run's load steps
    steps.solve_all(chis, half_width)
    for chi in chis:
        _same(steps, solve_reynolds(chi=chi, half_width=half_width), chi, half_width)


def _same(steps: FiniteBearingSteps, cold: ReynoldsSolution, chi: float, a: float) -> None:
    warm = steps.figures(chi=chi, half_width=a)
    assert warm.load == pytest.approx(cold.load, rel=SOLVER_TOLERANCE, abs=1e-12)
    assert warm.journal_torque_full_film == pytest.approx(
        cold.journal_torque_full_film, rel=SOLVER_TOLERANCE
    )


def test_each_chi_is_solved_once_and_the_oldest_forgotten(monkeypatch: pytest.MonkeyPatch) -> None:
    from rigserver.analysis import finite_steps

    solved: list[float] = []
    real = finite_steps.reynolds.solve_reynolds

    def counting(**kwargs: object) -> object:
        solved.append(float(kwargs["chi"]))  # type: ignore[arg-type]
        return real(**kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(finite_steps.reynolds, "solve_reynolds", counting)
    steps = FiniteBearingSteps(size=3, **GRID)
    steps.solve_all([0.5, 0.3, 0.5, 0.4], 1.0)
    assert solved == [0.3, 0.4, 0.5]  # ascending, each once
    steps.solve_all([0.3, 0.4, 0.5, 0.6], 1.0)  # one new step: one solve
    assert solved == [0.3, 0.4, 0.5, 0.6]
    steps.figures(chi=0.3, half_width=1.0)  # the oldest, forgotten when 0.6 came
    assert solved == [0.3, 0.4, 0.5, 0.6, 0.3]


def test_the_finite_bearing_of_a_run_is_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    """One results computation solves (3.1) for MAX_FINITE_STEPS steps at most."""
    monkeypatch.setattr(mtos, "MAX_FINITE_STEPS", 2)
    n = 3
    res = mtos_on_the_diagonal(
        [500.0, 1000.0, 1500.0],
        [0.05] * n,
        [-40.0, -35.0, -30.0],  # μm from the zero reading: χ about 0.3-0.4 ((4.11))
        {f"t{k}": [40.0] * n for k in range(1, 6)},
    )
    assert [s.friction_finite is not None for s in res.steps] == [True, True, False]
    assert "solved for the first 2 steps only" in " ".join(res.notes)
