"""Mass-conserving cavitation (Jakobsson-Floberg-Olsson) as a complementarity problem.

In the ruptured film the oil runs in streamers at ambient pressure, filling a fraction θ of
the clearance, and the film reforms where the streamers fill it again. Taking θ upwind in
the Couette fluxes of the scheme (:mod:`~rigserver.core._reynolds_grid`), the balance of
the cell P in column i is

    Σ_f c_f (Π_P - Π_Q) = -w·[q_i·θ_e - q_(i-1)·θ_w + s_i·θ_P],

q the full-film Couette flux through a face (``Stencil.couette``), s the squeeze term
(``Stencil.squeeze``, with θ frozen: ∂θ/∂τ is not modelled), w the row weight, θ_e, θ_w
the fractions upwind of the east and west faces. With r = 1 - θ this is K·Π - G·r = b,
and Elrod's p-θ model [2] is the linear complementarity problem of Giacopini et al. [1]

    Π ≥ 0,   r ≥ 0,   Π·r = 0

(r = 0 in the full film, Π = 0 in the ruptured one). It is solved by the primal-dual
active-set idea of :mod:`~rigserver.core._reynolds_lcp`: guess the ruptured set C, solve
the linear system for Π off C and r on C (a sparse LU: G is not symmetric), move the nodes
where Π < 0 into C and those where r < 0 (θ > 1) out of it, until C stops changing.
Started from the Swift-Stieber solution's ruptured set, it ends in a few steps. The matrix
is no M-matrix, and the iteration can cycle: a set seen before is then left by moving only
the node that violates its condition most.

A film fed by a supply at ambient pressure that does not reach every z line (a hole, a
short groove) starves the lines it does not reach: no oil gets there, any amount could run
round them, and the system is singular; the iteration then reports that it did not
converge. A supply above ambient pressure, or a groove along the whole length, feeds them.

References
----------
[1] Giacopini M., Fowell M.T., Dini D., Strozzi A. A mass-conserving complementarity
    formulation to study lubricant films in the presence of cavitation. J. Tribol. 132
    (2010) 041702.
[2] Elrod H.G. A cavitation algorithm. J. Lubr. Technol. 103 (1981) 350-354.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.linalg import MatrixRankWarning, spsolve

from rigserver.core._reynolds_grid import FloatArray, Stencil, sparse_operator
from rigserver.core._reynolds_lcp import ROUND_OFF, BoolArray


@dataclass(frozen=True, slots=True)
class MassConservingSolution:
    """Π and θ on the block, the ruptured set, and how the iteration ended."""

    values: FloatArray
    film_fraction: FloatArray
    ruptured: BoolArray
    iterations: int
    converged: bool


def transport_operator(st: Stencil, omega: float) -> sp.csr_matrix:
    """G of the module docstring (index ``i·m + j``): the Couette and squeeze fluxes of the
    missing fraction r, taken upwind (from the west for Ω ≥ 0, from the east for Ω < 0)."""
    n_phi, m = st.rhs.shape
    idx = np.arange(n_phi * m).reshape(n_phi, m)
    w = st.row_weight[None, :]
    q = st.couette[:, None] * w  # east face of column i
    q_west = np.roll(st.couette, 1)[:, None] * w
    s = st.squeeze[:, None] * w
    if omega >= 0:  # θ_e = θ_i, θ_w = θ_(i-1)
        diag, other, other_idx = q + s, -q_west, np.roll(idx, 1, axis=0)
    else:  # θ_e = θ_(i+1), θ_w = θ_i
        diag, other, other_idx = s - q_west, q, np.roll(idx, -1, axis=0)
    rows = np.concatenate([idx.ravel(), idx.ravel()])
    cols = np.concatenate([idx.ravel(), other_idx.ravel()])
    vals = np.concatenate([diag.ravel(), other.ravel()])
    return sp.csr_matrix((vals, (rows, cols)), shape=(n_phi * m, n_phi * m))


def solve_mass_conserving(
    st: Stencil,
    fixed: BoolArray,
    fixed_values: FloatArray,
    ruptured: BoolArray,
    *,
    omega: float,
    max_iter: int,
) -> MassConservingSolution:
    """Active-set iteration for the LCP of the module docstring; the ``fixed`` nodes (the
    supplies) hold their values with θ = 1; ``ruptured`` is the initial guess of C."""
    k = sparse_operator(st)
    g = transport_operator(st, omega)
    fixed_flat = fixed.ravel()
    unknown = np.flatnonzero(~fixed_flat)
    k_rows = k[unknown]
    g_rows = g[unknown]
    rhs = st.rhs.ravel()[unknown] - k_rows[:, fixed_flat] @ fixed_values.ravel()[fixed_flat]
    in_c = ruptured.ravel()[unknown].copy()
    pressure = np.zeros(st.rhs.size)
    missing = np.zeros(st.rhs.size)
    pressure[fixed_flat] = fixed_values.ravel()[fixed_flat]
    seen: set[bytes] = set()
    solved = in_c  # the set of the last solve
    it = 0
    for it in range(1, max_iter + 1):
        system = sp.hstack([k_rows[:, unknown[~in_c]], -g_rows[:, unknown[in_c]]]).tocsc()
        with warnings.catch_warnings():
            warnings.simplefilter("error", MatrixRankWarning)
            try:
                x = spsolve(system, rhs)
            except MatrixRankWarning:
                break
        if not np.all(np.isfinite(x)):
            break
        n_full = int(np.count_nonzero(~in_c))
        p_u, r_u = np.zeros(unknown.size), np.zeros(unknown.size)
        p_u[~in_c], r_u[in_c] = x[:n_full], x[n_full:]
        # Round-off must not flip nodes where Π = r = 0 back and forth.
        scale_p = float(np.max(np.abs(p_u), initial=0.0))
        violation = np.where(in_c, -r_u, -p_u / scale_p if scale_p > 0 else 0.0)
        flip = violation > ROUND_OFF
        pressure[unknown], missing[unknown], solved = p_u, r_u, in_c
        if not flip.any():
            return _solution(pressure, missing, unknown[in_c], st.rhs.shape, it, converged=True)
        seen.add(in_c.tobytes())
        new = in_c ^ flip
        if new.tobytes() in seen:  # a cycle (G is no M-matrix): flip the worst node alone
            new = in_c.copy()
            worst = int(np.argmax(violation))
            new[worst] = not new[worst]
        in_c = new
    return _solution(pressure, missing, unknown[solved], st.rhs.shape, it, converged=False)


def _solution(
    pressure: FloatArray,
    missing: FloatArray,
    ruptured: NDArray[np.intp],
    shape: tuple[int, int],
    iterations: int,
    *,
    converged: bool,
) -> MassConservingSolution:
    mask = np.zeros(shape[0] * shape[1], dtype=bool)
    mask[ruptured] = True
    theta = 1.0 - np.clip(missing, 0.0, 1.0)
    return MassConservingSolution(
        values=np.maximum(pressure, 0.0).reshape(shape),
        film_fraction=theta.reshape(shape),
        ruptured=mask.reshape(shape),
        iterations=iterations,
        converged=converged,
    )
