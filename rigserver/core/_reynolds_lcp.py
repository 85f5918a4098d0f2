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
keeps the half bandwidth at most 2m. Memory is O(n·m²) at worst, never (n·m)². A step
that only moves a few free nodes into A keeps the factor of the step before and holds those
nodes at zero with a capacitance system of their number (a few extra triangular solves).

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
        return (np.arange(n) + int(cuts[0]) + 1) % n
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


@dataclass(frozen=True, slots=True)
class BandedFactor:
    """K_FF of a set F of free nodes, factorised by banded Cholesky (LAPACK ``pbtrf``).

    The free nodes are numbered column by column in the order of :func:`_column_order`;
    ``nodes`` holds the flat block index of each, ``rank`` the number of each node (-1 off
    F). The band of K_FF in LAPACK's lower storage is filled from the coupled pairs.
    """

    free: BoolArray
    rank: IndexArray
    nodes: IndexArray
    band: int
    factor: FloatArray

    def serves(self, free: BoolArray) -> bool:
        """Whether :meth:`solve` on ``free`` costs less than a new factorisation: ``free``
        is F less a few nodes, each an extra pair of triangular solves, about 4·band
        operations a node against band² for a factorisation."""
        if np.any(free & ~self.free):
            return False
        return int(np.count_nonzero(self.free & ~free)) <= max(1, self.band // 6)

    def solve(self, rhs: FloatArray, free: BoolArray) -> FloatArray:
        """Π with K·Π = rhs on ``free`` (F or a subset of it) and 0 elsewhere.

        The nodes D of F that ``free`` drops are held at 0 by multipliers μ on their rows:
        with y = K_FF⁻¹ rhs and Z = K_FF⁻¹ E_D, μ = (E_Dᵀ Z)⁻¹ y_D and Π = y - Zμ (a
        capacitance system of |D| unknowns; the rows of D are the only ones μ changes).
        """
        out = np.zeros(self.free.shape)
        if not self.nodes.size:
            return out
        dropped = self.rank[(self.free & ~free).ravel()]
        columns = np.zeros((self.nodes.size, 1 + dropped.size), order="F")
        columns[:, 0] = rhs.ravel()[self.nodes]
        columns[dropped, np.arange(1, dropped.size + 1)] = 1.0
        solved, info = dpbtrs(self.factor, columns, lower=1, overwrite_b=1)
        if info != 0:
            raise LinAlgError(f"pbtrs failed: {info}")
        x = solved[:, 0]
        if dropped.size:
            z = solved[:, 1:]
            x -= z @ np.linalg.solve(z[dropped], x[dropped])
            x[dropped] = 0.0
        out.ravel()[self.nodes] = x
        return out


def factorise(st: Stencil, free: BoolArray) -> BandedFactor:
    """The banded Cholesky factor of K_FF on the free nodes ``free``."""
    n_phi, m = free.shape
    order = _column_order(np.logical_not(np.any(free, axis=1)))
    free_ordered = free[order].ravel()
    nodes = (order[:, None] * m + np.arange(m)).ravel()[free_ordered]
    rank = np.full(n_phi * m, -1, dtype=np.intp)
    rank[nodes] = np.arange(nodes.size)
    if not nodes.size:
        return BandedFactor(free, rank, nodes, 0, np.zeros((1, 0)))
    first, second = _pairs(n_phi, m)
    a = rank[first]
    c = rank[second]
    coupled = (a >= 0) & (c >= 0)
    a, c = a[coupled], c[coupled]
    offset = np.abs(a - c)
    band = int(offset.max()) if offset.size else 0
    ab = np.zeros((band + 1, nodes.size))
    ab[0] = st.diag.ravel()[nodes]
    ab[offset, np.minimum(a, c)] = -st.couplings[coupled]
    factor, info = dpbtrf(ab, lower=1, overwrite_ab=1)
    if info != 0:
        raise LinAlgError(f"the scheme's matrix is not positive definite (pbtrf: {info})")
    return BandedFactor(free, rank, nodes, band, factor)


@dataclass(frozen=True, slots=True)
class _Colour:
    """The nodes of one colour of a block's checkerboard (flat indices) and, per node, its
    four couplings: the neighbours' ranks among the other colour's nodes and the pairs'
    indices in :attr:`Stencil.couplings`; a missing neighbour (the block's edge) is the
    other colour's rank ``n`` and the pair ``len(couplings)``, both padding zeros."""

    nodes: IndexArray
    neighbours: IndexArray
    pairs: IndexArray


def _neighbours(
    own: IndexArray, other: IndexArray, n_own: int, n_other: int, n_pairs: int
) -> tuple[IndexArray, IndexArray]:
    """Per node of one colour (rank ``own`` of each pair), its neighbours (``other``) and
    pairs, four a node, padded."""
    by_node = np.argsort(own, kind="stable")
    starts = np.zeros(n_own + 1, dtype=np.intp)
    np.cumsum(np.bincount(own, minlength=n_own), out=starts[1:])
    slot = np.arange(own.size) - starts[own[by_node]]
    neighbours = np.full((n_own, 4), n_other, dtype=np.intp)
    pairs = np.full((n_own, 4), n_pairs, dtype=np.intp)
    neighbours[own[by_node], slot] = other[by_node]
    pairs[own[by_node], slot] = by_node
    return neighbours, pairs


@lru_cache(maxsize=16)
def _checkerboard(n_phi: int, m: int) -> tuple[_Colour, _Colour]:
    """The red and black nodes of a block (a checkerboard; n_phi even keeps it periodic).
    Every coupled pair joins a red node and a black one, so a colour's Gauss-Seidel update
    reads only the other colour."""
    i, j = np.indices((n_phi, m))
    is_red = ((i + j) % 2 == 0).ravel()
    red, black = np.flatnonzero(is_red), np.flatnonzero(~is_red)
    rank = np.empty(n_phi * m, dtype=np.intp)
    rank[red] = np.arange(red.size)
    rank[black] = np.arange(black.size)
    first, second = _pairs(n_phi, m)
    first_red = is_red[first]
    red_rank = rank[np.where(first_red, first, second)]
    black_rank = rank[np.where(first_red, second, first)]
    colours = (
        _Colour(red, *_neighbours(red_rank, black_rank, red.size, black.size, first.size)),
        _Colour(black, *_neighbours(black_rank, red_rank, black.size, red.size, first.size)),
    )
    for colour in colours:
        for arr in (colour.nodes, colour.neighbours, colour.pairs):
            arr.setflags(write=False)
    return colours


def smoothed_rupture(
    st: Stencil, fixed: BoolArray, fixed_values: FloatArray, start: FloatArray, sweeps: int
) -> BoolArray:
    """A guess of the cavitated set: ``start`` (a coarse grid's Π prolonged) after ``sweeps``
    red-black projected Gauss-Seidel sweeps, Π_P ← max(0, (b_P + Σ c_f Π_Q)/K_PP) (Cryer's
    projected SOR without over-relaxation), the ``fixed`` nodes held.

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
    flat = values.ravel()
    couplings = np.append(st.couplings, 0.0)
    colours = _checkerboard(n_phi, m)
    # per colour: its values with a padding zero after them, the couplings over K_PP, b/K_PP
    # and the nodes it updates (not held)
    own: list[FloatArray] = []
    weights: list[FloatArray] = []
    source: list[FloatArray] = []
    moves: list[BoolArray] = []
    for colour in colours:
        diag = st.diag.ravel()[colour.nodes]
        own.append(np.append(flat[colour.nodes], 0.0))
        weights.append(couplings[colour.pairs] / diag[:, None])
        source.append(st.rhs.ravel()[colour.nodes] / diag)
        moves.append(~fixed.ravel()[colour.nodes])
    for _ in range(sweeps):
        for c, colour in enumerate(colours):
            step = np.einsum("ij,ij->i", weights[c], own[1 - c][colour.neighbours])
            step += source[c]
            np.maximum(step, 0.0, out=step)
            np.copyto(own[c][:-1], step, where=moves[c])
    for c, colour in enumerate(colours):
        flat[colour.nodes] = own[c][:-1]
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
    return factorise(st, free).solve(st.rhs - st.apply(held), free) + held


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
    factor: BandedFactor | None = None
    for it in range(1, max_iter + 1):
        free = ~(active | fixed)
        if factor is None or not factor.serves(free):
            factor = factorise(st, free)
        values = factor.solve(rhs, free)
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
