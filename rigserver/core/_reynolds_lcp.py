"""Banded Cholesky solves of the Reynolds scheme and the primal-dual active-set LCP solver.

The Reynolds (Swift-Stieber) condition Π ≥ 0, ∂Π/∂n = 0 at rupture is the linear
complementarity problem [1]

    Π ≥ 0,   λ = KΠ - b ≥ 0,   Π·λ = 0,

with K the symmetric M-matrix of the scheme. The primal-dual active-set method [2] guesses the
cavitated (active) set A, solves K_II Π_I = b_I on the rest with Π_A = 0, and updates
A ← {i ∈ A: λ_i > 0} ∪ {i ∉ A: Π_i < 0} until A stops changing; for an M-matrix it ends after
finitely many steps, in practice a handful when started from a coarse grid's answer.

Each step factorises K_II by banded Cholesky (LAPACK ``pbtrf``): ordered column by column in
φ, the free nodes couple within one column of m rows, so the half bandwidth is at most m.
When a column is blocked entirely (a supply groove, or cavitated across the width), the
periodic ring is cut there; otherwise the columns are interleaved (0, n-1, 1, n-2, ...), which
keeps the half bandwidth at most 2m. Memory is O(n·m²) at worst, never (n·m)².

References
----------
[1] Kinderlehrer D., Stampacchia G. An Introduction to Variational Inequalities and Their
    Applications. Academic Press, 1980 (the obstacle problem; the journal bearing, ch. VII).
[2] Hintermüller M., Ito K., Kunisch K. The primal-dual active set strategy as a semismooth
    Newton method. SIAM J. Optim. 13 (2003) 865-888.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import cho_solve_banded, cholesky_banded

from rigserver.core._reynolds_grid import FloatArray, Stencil

BoolArray = NDArray[np.bool_]

#: Relative size below which a negative pressure or multiplier is taken as round-off.
ROUND_OFF = 1e-12


def _column_order(blocked: NDArray[np.bool_]) -> NDArray[np.intp]:
    """Order of the φ columns: cut after a blocked column, else interleave both ends."""
    n = blocked.size
    cuts = np.flatnonzero(blocked)
    if cuts.size:
        return np.roll(np.arange(n), -int(cuts[0]) - 1)
    order = np.empty(n, dtype=np.intp)
    order[0::2] = np.arange((n + 1) // 2)
    order[1::2] = np.arange(n - 1, (n + 1) // 2 - 1, -1)
    return order


def solve_free(st: Stencil, free: BoolArray, rhs: FloatArray) -> FloatArray:
    """Solve K_FF·Π_F = rhs_F on the free nodes ``free``; 0 elsewhere. Banded Cholesky."""
    n_phi, m = free.shape
    out = np.zeros((n_phi, m))
    n_free = int(np.count_nonzero(free))
    if n_free == 0:
        return out
    order = _column_order(np.logical_not(np.any(free, axis=1)))
    pos = np.full((n_phi, m), -1, dtype=np.intp)
    free_ordered = free[order]
    ranks = np.full(free_ordered.shape, -1, dtype=np.intp)
    ranks[free_ordered] = np.arange(n_free)
    pos[order] = ranks
    pos_east = np.roll(pos, -1, axis=0)
    pe = (pos >= 0) & (pos_east >= 0)
    pn = (pos[:, :-1] >= 0) & (pos[:, 1:] >= 0)
    a = np.concatenate([pos[pe], pos[:, :-1][pn]])
    c = np.concatenate([pos_east[pe], pos[:, 1:][pn]])
    coef = np.concatenate([st.east[pe], st.north[:, :-1][pn]])
    lo = np.minimum(a, c)
    hi = np.maximum(a, c)
    band = int((hi - lo).max()) if hi.size else 0
    ab = np.zeros((band + 1, n_free))
    ab[band, pos[free]] = st.diag[free]
    ab[band - (hi - lo), hi] = -coef
    factor = cholesky_banded(ab, lower=False, check_finite=False)
    b = np.empty(n_free)
    b[pos[free]] = rhs[free]
    x = cho_solve_banded((factor, False), b, check_finite=False)
    out[free] = x[pos[free]]
    return out


@dataclass(frozen=True, slots=True)
class ComplementaritySolution:
    """Π on the block, the cavitated (active) set, and how the iteration ended."""

    values: FloatArray
    active: BoolArray
    iterations: int
    converged: bool


def solve_fixed(
    st: Stencil, fixed: BoolArray, fixed_values: FloatArray, free: BoolArray
) -> FloatArray:
    """Π with the ``fixed`` nodes at their values, 0 on the rest of ``~free``, K·Π = b on
    ``free``."""
    rhs = st.rhs - st.apply(np.where(fixed, fixed_values, 0.0))
    return solve_free(st, free, rhs) + np.where(fixed, fixed_values, 0.0)


def solve_complementarity(
    st: Stencil,
    fixed: BoolArray,
    fixed_values: FloatArray,
    active: BoolArray,
    *,
    max_iter: int,
) -> ComplementaritySolution:
    """Primal-dual active-set iteration for Π ≥ 0, KΠ - b ≥ 0, Π·(KΠ - b) = 0 off ``fixed``.

    ``active`` is the initial guess of the cavitated set (nodes where Π = 0).
    """
    active = active & ~fixed
    values = np.zeros_like(st.rhs)
    for it in range(1, max_iter + 1):
        free = ~active & ~fixed
        values = solve_fixed(st, fixed, fixed_values, free)
        multiplier = st.apply(values) - st.rhs
        # Round-off must not flip nodes where Π = λ = 0 back and forth.
        tol_p = ROUND_OFF * float(np.max(np.abs(values), initial=0.0))
        tol_m = ROUND_OFF * float(np.max(np.abs(st.rhs)) + np.max(np.abs(multiplier)))
        new = (active & (multiplier > -tol_m)) | (free & (values < -tol_p))
        if np.array_equal(new, active):
            values[free] = np.maximum(values[free], 0.0)
            return ComplementaritySolution(values, active, it, True)
        active = new
    return ComplementaritySolution(values, active, max_iter, False)
