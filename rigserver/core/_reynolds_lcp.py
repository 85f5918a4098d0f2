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
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import LinAlgError
from scipy.linalg.lapack import dpbtrf, dpbtrs

from rigserver.core._reynolds_grid import FloatArray, Stencil

BoolArray = NDArray[np.bool_]
IndexArray = NDArray[np.intp]

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


@lru_cache(maxsize=16)
def _pairs(n_phi: int, m: int) -> tuple[IndexArray, IndexArray]:
    """The coupled node pairs of a block, as flat indices: every (i, j)-(i+1, j) (periodic),
    then every (i, j)-(i, j+1); in the order of :attr:`Stencil.couplings`."""
    idx = np.arange(n_phi * m).reshape(n_phi, m)
    first = np.concatenate([idx.ravel(), idx[:, :-1].ravel()])
    second = np.concatenate([np.roll(idx, -1, axis=0).ravel(), idx[:, 1:].ravel()])
    first.setflags(write=False)
    second.setflags(write=False)
    return first, second


def solve_free(st: Stencil, free: BoolArray, rhs: FloatArray) -> FloatArray:
    """Solve K_FF·Π_F = rhs_F on the free nodes ``free``; 0 elsewhere. Banded Cholesky.

    The free nodes are numbered column by column in the order of :func:`_column_order`; the
    band of K_FF in LAPACK's lower storage is filled from the coupled pairs of the block.
    """
    n_phi, m = free.shape
    out = np.zeros((n_phi, m))
    order = _column_order(np.logical_not(np.any(free, axis=1)))
    free_ordered = free[order].ravel()
    n_free = int(np.count_nonzero(free_ordered))
    if n_free == 0:
        return out
    ranks = np.cumsum(free_ordered) - 1
    pos = np.empty((n_phi, m), dtype=np.intp)
    pos[order] = np.where(free_ordered, ranks, -1).reshape(n_phi, m)
    pos_flat = pos.ravel()
    first, second = _pairs(n_phi, m)
    a = pos_flat[first]
    c = pos_flat[second]
    coupled = (a >= 0) & (c >= 0)
    a, c = a[coupled], c[coupled]
    offset = np.abs(a - c)
    band = int(offset.max()) if offset.size else 0
    ab = np.zeros((band + 1, n_free))
    ab[0] = st.diag[order].ravel()[free_ordered]
    ab[offset, np.minimum(a, c)] = -st.couplings[coupled]
    factor, info = dpbtrf(ab, lower=1, overwrite_ab=1)
    if info != 0:
        raise LinAlgError(f"the scheme's matrix is not positive definite (pbtrf: {info})")
    x, info = dpbtrs(factor, rhs[order].ravel()[free_ordered], lower=1, overwrite_b=1)
    if info != 0:
        raise LinAlgError(f"pbtrs failed: {info}")
    solved = np.zeros(n_phi * m)
    solved[free_ordered] = x
    out[order] = solved.reshape(n_phi, m)
    return out


@lru_cache(maxsize=16)
def _colours(n_phi: int, m: int) -> tuple[BoolArray, BoolArray]:
    """The red and black nodes of a block (a checkerboard; n_phi even keeps it periodic)."""
    i, j = np.indices((n_phi, m))
    red = (i + j) % 2 == 0
    black = ~red
    red.setflags(write=False)
    black.setflags(write=False)
    return red, black


def smoothed_rupture(
    st: Stencil, fixed: BoolArray, fixed_values: FloatArray, start: FloatArray, sweeps: int
) -> BoolArray:
    """A guess of the cavitated set: ``start`` (a coarse grid's Π prolonged) after ``sweeps``
    red-black projected Gauss-Seidel sweeps, Π ← max(0, Π + (b - KΠ)/K_PP) (Cryer's
    projected SOR without over-relaxation).

    A prolonged field is right but for the rupture line, which the coarse grid placed to
    within its cells; a few smoothing sweeps move it there on the fine grid, so that the
    active-set iteration started from the result needs one or two factorisations instead of
    three or four (Cryer C.W. The solution of a quadratic programming problem using
    systematic overrelaxation. SIAM J. Control 9 (1971) 385-392).
    """
    values = np.where(fixed, fixed_values, start)
    n_phi, m = values.shape
    if n_phi % 2:
        return (values <= 0.0) & ~fixed
    colours = [c & ~fixed for c in _colours(n_phi, m)]
    for _ in range(sweeps):
        for colour in colours:
            step = st.rhs - st.apply(values)
            step /= st.diag
            step += values
            np.maximum(step, 0.0, out=step)
            np.copyto(values, step, where=colour)
    return (values <= 0.0) & ~fixed


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
    held = np.where(fixed, fixed_values, 0.0)
    return solve_free(st, free, st.rhs - st.apply(held)) + held


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
    held = np.where(fixed, fixed_values, 0.0)
    rhs = st.rhs - st.apply(held)  # the supplies' part of the right side, once
    rhs_size = float(np.max(np.abs(st.rhs)))
    for it in range(1, max_iter + 1):
        free = ~(active | fixed)
        values = solve_free(st, free, rhs)
        values += held
        multiplier = st.apply(values)
        multiplier -= st.rhs
        # Round-off must not flip nodes where Π = λ = 0 back and forth.
        tol_p = ROUND_OFF * float(np.max(np.abs(values), initial=0.0))
        tol_m = ROUND_OFF * (rhs_size + float(np.max(np.abs(multiplier))))
        new = (active & (multiplier > -tol_m)) | (free & (values < -tol_p))
        if np.array_equal(new, active):
            values[free] = np.maximum(values[free], 0.0)
            return ComplementaritySolution(values, active, it, True)
        active = new
    return ComplementaritySolution(values, active, max_iter, False)
