"""Speed and accuracy of the finite journal bearing, ``rigserver.core.reynolds`` (issue 5).

Run from the repository root::

    .venv/bin/python benchmarks/bearing.py [--quick]

Prints one JSON object: the grid, median times of one cavitating solve, an equilibrium
(load → ε, attitude), the eight dynamic coefficients and a plain sparse direct solve of the
same grid without cavitation (and their ratios), the results of an MTOS run of 200 load
steps computed cold (no finite-bearing solve remembered, issue 25) and with one new step,
the accuracy against the closed forms and the grid-convergence table of
``docs/reynolds.md``. BLAS runs on one thread: one core.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from itertools import pairwise  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
from scipy.sparse.linalg import spsolve  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from rigserver.analysis.finite_steps import FiniteBearingSteps  # noqa: E402
from rigserver.core._reynolds_grid import make_grid, sparse_operator, stencil  # noqa: E402
from rigserver.core.reynolds import (  # noqa: E402
    DEFAULT_N_PHI,
    DEFAULT_N_Z,
    SupplyGroove,
    dynamic_coefficients,
    equilibrium,
    finite_bearing,
    solve_reynolds,
)
from schemas.stands import StandKind  # noqa: E402

# The closed forms and the 1-D Swift-Stieber solution are written once, in the tests.
from tests.core.test_reynolds import (  # noqa: E402
    attitude_deg,
    long_bearing_force,
    long_bearing_reynolds_force,
    short_bearing_force,
)

CHI, B_OVER_D = 0.6, 1.0
TARGETS_MS = {
    "solve_ms": 5.0,
    "equilibrium_ms": 150.0,
    "coefficients_ms": 200.0,
    "mtos_200_steps_cold_ms": 1000.0,
}
MTOS_STEPS = 200


#: CPU time of this process, beside each wall-clock median: on a machine shared with other
#: work the wall clock counts the others' time too (docs/speed.md)
CPU: dict[str, float] = {}


def median_ms(fn: Callable[[], object], repeat: int, name: str = "") -> float:
    """Median wall-clock ms of ``fn``; its median CPU ms is kept in :data:`CPU` by ``name``."""
    fn()  # warm caches
    times, cpu = [], []
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    if name:
        CPU[name] = round(statistics.median(cpu) * 1e3, 3)
    return round(statistics.median(times) * 1e3, 3)


def speed(repeat: int) -> dict[str, Any]:
    s = finite_bearing(CHI, B_OVER_D).sommerfeld
    grid = make_grid(DEFAULT_N_PHI, DEFAULT_N_Z, B_OVER_D, mirror=False)
    st = stencil(grid, chi_x=CHI, chi_y=0.0, vel_x=0.0, vel_y=0.0, omega=1.0, mu_bar=1.0)
    k = sparse_operator(st).tocsc()
    b = st.rhs.ravel()
    out: dict[str, Any] = {
        "solve_ms": median_ms(lambda: finite_bearing(CHI, B_OVER_D), repeat, "solve_cpu_ms"),
        "equilibrium_ms": median_ms(lambda: equilibrium(s, B_OVER_D), repeat),
        "coefficients_ms": median_ms(lambda: dynamic_coefficients(CHI, B_OVER_D), repeat),
        "direct_solve_ms": median_ms(lambda: spsolve(k, b), repeat),
        # the same solve without the mirror at z = 0 (all 144 x 47 unknowns)
        "solve_full_width_ms": median_ms(
            lambda: solve_reynolds(
                chi=CHI,
                half_width=B_OVER_D,
                supply=(SupplyGroove(angle=np.pi),),
                use_symmetry=False,
            ),
            repeat,
        ),
    }
    for key in ("solve_ms", "equilibrium_ms", "coefficients_ms", "solve_full_width_ms"):
        out[key.replace("_ms", "_to_direct")] = round(out[key] / out["direct_solve_ms"], 3)
    out["active_set_iterations"] = finite_bearing(CHI, B_OVER_D).solution.iterations
    out.update(CPU)
    return out


def mtos_run(steps: int) -> tuple[Any, Any]:
    """An MTOS run of ``steps`` load steps (300-3000 N, the simulator's short-bearing truth,
    the gauges' resolution and noise): the run and its readings."""
    from rigsim.simulators import mtos as simulated_mtos
    from tests.analysis.conftest import FakeReadings, make_run

    loads = tuple(float(n) for n in np.linspace(300.0, 3000.0, steps).round(1))
    settings = simulated_mtos.MtosSettings(
        loads_fluid=loads, loads_mixed=(), loads_boundary=(), model="short"
    )
    sim = simulated_mtos.simulate(settings, seed=1)
    columns: dict[str, list[float]] = {}
    measurements: dict[str, float] = {}
    for batch in sim.batches:
        for name, values in batch.columns.items():
            if batch.group == "steps":
                columns.setdefault(name, []).extend(np.atleast_1d(values).tolist())
            else:
                measurements[name] = float(np.atleast_1d(values)[-1])
    run = make_run(StandKind.MTOS, **sim.run_create.configuration)
    return run, FakeReadings({"steps": columns}, measurements)


def mtos_results(repeat: int) -> dict[str, Any]:
    """Medians of the results of an MTOS run of 200 steps: cold (every finite-bearing solve
    new), and after one more step arrived (one solve)."""
    from rigserver.analysis import analyse, mtos

    run, readings = mtos_run(MTOS_STEPS)
    cold, cold_cpu, warm = [], [], []
    solved: list[int] = []
    for _ in range(repeat):
        mtos.FINITE = FiniteBearingSteps()
        t0, c0 = time.perf_counter(), time.process_time()
        analyse(run, readings)
        cold.append(time.perf_counter() - t0)
        cold_cpu.append(time.process_time() - c0)
        solved.append(len(mtos.FINITE._known))
        more = readings.groups["steps"]
        readings.groups["steps"] = {k: np.append(v, v[-1:] * 1.001) for k, v in more.items()}
        t0 = time.perf_counter()
        analyse(run, readings)
        warm.append(time.perf_counter() - t0)
        readings.groups["steps"] = more
    return {
        "mtos_steps": MTOS_STEPS,
        "mtos_distinct_chi_solved": solved[0],
        "mtos_200_steps_cold_ms": round(statistics.median(cold) * 1e3, 1),
        "mtos_200_steps_cold_range_ms": [round(min(cold) * 1e3, 1), round(max(cold) * 1e3, 1)],
        "mtos_200_steps_cold_cpu_ms": round(statistics.median(cold_cpu) * 1e3, 1),
        "mtos_one_new_step_ms": round(statistics.median(warm) * 1e3, 1),
    }


def _row(
    check: str, cavitation: str, bd: float | str, chi: float, grid: list[int]
) -> dict[str, Any]:
    return {
        "check": check,
        "cavitation": cavitation,
        "b_over_d": bd,
        "eccentricity_ratio": chi,
        "grid": grid,
    }


def accuracy(chis: tuple[float, ...]) -> list[dict[str, Any]]:
    rows: list[dict[str, Any]] = []
    for chi in chis:
        for bd in (0.05, 0.02):
            grid = [576, 96]
            fb = finite_bearing(chi, bd, n_phi=grid[0], n_z=grid[1], cavitation="half_sommerfeld")
            ref = short_bearing_force(chi, bd)
            row = _row(
                "half-Sommerfeld vs short bearing (Ocvirk)", "half_sommerfeld", bd, chi, grid
            )
            row["load_error"] = fb.load / np.hypot(*ref) - 1
            row["attitude_error_deg"] = fb.attitude_deg - attitude_deg(*ref)
            rows.append(row)
        for cavitation, check, reference in (
            ("half_sommerfeld", "half-Sommerfeld vs long bearing (3.15)", long_bearing_force),
            (
                "reynolds",
                "Reynolds vs 1-D long bearing (Swift-Stieber)",
                long_bearing_reynolds_force,
            ),
        ):
            ref = reference(chi, 1.0)
            errors, attitudes = [], []
            for bd in (5, 10):
                grid = [288, 8 * bd]
                fb = finite_bearing(chi, bd, n_phi=grid[0], n_z=grid[1], cavitation=cavitation)
                row = _row(check, cavitation, bd, chi, grid)
                errors.append(fb.load / (bd * np.hypot(*ref)) - 1)
                attitudes.append(fb.attitude_deg - attitude_deg(*ref))
                row["load_error"], row["attitude_error_deg"] = errors[-1], attitudes[-1]
                rows.append(row)
            row = _row(check, cavitation, "inf (1/a extrapolation of 5, 10)", chi, [288, 0])
            row["load_error"] = 2 * errors[1] - errors[0]
            row["attitude_error_deg"] = 2 * attitudes[1] - attitudes[0]
            rows.append(row)
    for row in rows:
        row["load_error"] = float(f"{row['load_error']:.3e}")
        row["attitude_error_deg"] = float(f"{row['attitude_error_deg']:.3e}")
    return rows


FIGURES = (
    "sommerfeld",
    "attitude_deg",
    "friction_variable",
    "flow_variable",
    "side_flow_ratio",
    "max_pressure_ratio",
)


def convergence(levels: int) -> list[dict[str, Any]]:
    """Relative error of each design figure against a grid 4x finer in both directions."""
    cache: dict[int, dict[str, float]] = {}

    def figures(n: int) -> dict[str, float]:
        if n not in cache:
            fb = finite_bearing(CHI, B_OVER_D, n_phi=36 * n, n_z=12 * n)
            cache[n] = {f: float(getattr(fb, f)) for f in FIGURES}
        return cache[n]

    rows = []
    for level in range(levels):
        n = 2**level
        coarse, fine = figures(n), figures(4 * n)
        row: dict[str, Any] = {"grid": [36 * n, 12 * n], "reference_grid": [144 * n, 48 * n]}
        for f in FIGURES:
            row[f] = coarse[f]
            row[f + "_error"] = float(f"{abs(coarse[f] / fine[f] - 1):.3e}")
        rows.append(row)
    for prev, row in pairwise(rows):
        row["sommerfeld_order"] = round(
            float(np.log2(prev["sommerfeld_error"] / row["sommerfeld_error"])), 2
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats and cases")
    args = parser.parse_args()
    quick = args.quick
    result: dict[str, Any] = {
        "grid": [DEFAULT_N_PHI, DEFAULT_N_Z],
        "case": {"eccentricity_ratio": CHI, "b_over_d": B_OVER_D, "cavitation": "reynolds"},
        "threads": 1,
    }
    result.update(speed(5 if quick else 21))
    result.update(mtos_results(3 if quick else 5))
    result["meets_targets"] = all(result[key] <= limit for key, limit in TARGETS_MS.items())
    result["meets_targets_in_cpu_time"] = (
        result["solve_cpu_ms"] <= TARGETS_MS["solve_ms"]
        and result["mtos_200_steps_cold_cpu_ms"] <= TARGETS_MS["mtos_200_steps_cold_ms"]
    )
    result["targets_ms"] = TARGETS_MS
    result["accuracy"] = accuracy((0.6,) if quick else (0.3, 0.6, 0.9))
    result["grid_convergence"] = convergence(3 if quick else 4)
    print(dumps(result))


def dumps(result: dict[str, Any]) -> str:
    """JSON with one line per key, and per row of the tables."""
    lines = []
    for key, value in result.items():
        if isinstance(value, list) and value and isinstance(value[0], dict):
            rows = ",\n    ".join(json.dumps(row) for row in value)
            lines.append(f"  {json.dumps(key)}: [\n    {rows}\n  ]")
        else:
            lines.append(f"  {json.dumps(key)}: {json.dumps(value)}")
    return "{\n" + ",\n".join(lines) + "\n}"


if __name__ == "__main__":
    main()
