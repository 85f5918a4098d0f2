"""Grid and finite-volume stencil of the Reynolds equation (3.1) on the (φ, z) plane.

Vertex-centred nodes: ``φ_i = i·Δφ`` (``i = 0 .. n_phi-1``, periodic) and
``z_j = -a + j·Δz`` (``j = 0 .. n_z``, the edges ``z = ±a`` included, where ``Π = 0``).
Each node owns the cell ``[φ_i ± Δφ/2] × [z_j ± Δz/2]``; integrating (3.1) over it gives the
5-point scheme

    Σ_faces c_f (Π_P - Π_Q) = b_P,
    c_east = H(φ_i + Δφ/2)³·Δz/Δφ,  c_north = H(φ_i)³·Δφ/Δz,
    b_P = -6μ̄·Δz·[Ω·(H_e - H_w) + 2·∫_cell ∂H/∂τ dφ],

in which the wedge term is the exact difference of the Couette fluxes at the cell faces, so
the scheme is conservative and second order. The matrix ``K`` (Σ c_f on the diagonal, -c_f
off it) is a symmetric M-matrix.

The unknowns form a block of rows of the node grid: all interior rows ``j = 1 .. n_z-1``, or,
when the problem is symmetric about ``z = 0``, the upper half with a mirror condition
``∂Π/∂z = 0`` at ``z = 0`` (a half cell at ``z = 0`` if ``n_z`` is even; a flux-free face
there if it is odd). Block arrays have shape ``(n_phi, m)``, ``φ`` first.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class Grid:
    """Nodes of the (φ, z) grid and the block of rows that carries unknowns.

    Attributes
    ----------
    n_phi, n_z : int
        Intervals in φ over 2π and in z over the full width ``-a .. a``.
    half_width : float
        a = B/D, the edges are at z = ±a (3.5, corrected E3).
    first_row : int
        z index of the first unknown row (1, or the row at/above z = 0 with symmetry).
    mirror : bool
        Whether the block is the upper half with the mirror condition at z = 0.
    """

    n_phi: int
    n_z: int
    half_width: float
    first_row: int
    mirror: bool

    @property
    def d_phi(self) -> float:
        """Node spacing in φ, rad."""
        return 2.0 * np.pi / self.n_phi

    @property
    def d_z(self) -> float:
        """Node spacing in z (units of R)."""
        return 2.0 * self.half_width / self.n_z

    @property
    def n_rows(self) -> int:
        """Number of unknown rows m in the block."""
        return self.n_z - self.first_row

    @property
    def phi(self) -> FloatArray:
        """Node angles φ_i, rad, shape (n_phi,)."""
        return _trig(self.n_phi)[0]

    @property
    def z(self) -> FloatArray:
        """Node positions z_j including both edges, shape (n_z + 1,)."""
        return np.linspace(-self.half_width, self.half_width, self.n_z + 1)

    @property
    def row_weight(self) -> FloatArray:
        """Cell height of each block row in units of Δz (1/2 for the half cell at z = 0)."""
        w = np.ones(self.n_rows)
        if self.mirror and self.n_z % 2 == 0:
            w[0] = 0.5
        return w


def make_grid(n_phi: int, n_z: int, half_width: float, *, mirror: bool) -> Grid:
    """Grid with the full block of interior rows, or the upper half when ``mirror``."""
    first = (n_z + 1) // 2 if mirror else 1
    return Grid(n_phi=n_phi, n_z=n_z, half_width=half_width, first_row=first, mirror=mirror)


@lru_cache(maxsize=32)
def _trig(n_phi: int) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """φ_i, cos and sin at nodes and at the east faces φ_i + Δφ/2 (read-only, cached)."""
    d = 2.0 * np.pi / n_phi
    phi: FloatArray = np.arange(n_phi, dtype=np.float64) * d
    east: FloatArray = phi + d / 2
    out = (phi, np.cos(phi), np.sin(phi), np.cos(east), np.sin(east))
    for arr in out:
        arr.setflags(write=False)
    return out


def film_thickness(grid: Grid, chi_x: float, chi_y: float) -> tuple[FloatArray, FloatArray]:
    """H = 1 - χ_x cos φ - χ_y sin φ (3.2) at the nodes and at the east faces.

    ``χ_x = χ cos δ``, ``χ_y = χ sin δ``: the journal centre in the bush frame.
    """
    _, c, s, ce, se = _trig(grid.n_phi)
    return 1.0 - chi_x * c - chi_y * s, 1.0 - chi_x * ce - chi_y * se


@dataclass(frozen=True, slots=True)
class Stencil:
    """The 5-point scheme on the block of unknown rows, arrays of shape (n_phi, m).

    ``east[i, j]`` couples (i, j) with (i+1, j) (periodic); ``north[i, j]`` couples (i, j)
    with (i, j+1), and its last column is the face to the edge z = a (Π = 0 there);
    ``diag`` is the sum of all face coefficients of the cell; ``rhs`` is b. What b is made
    of, per column i (shape (n_phi,)): ``couette[i] = 6μ̄·Δz·Ω·H(φ_i + Δφ/2)``, the Couette
    flux through the east face of a full film, and ``squeeze[i] = 12μ̄·Δz·∫_cell ∂H/∂τ dφ``;
    ``b = -(couette - couette_west + squeeze)·row_weight``.
    """

    east: FloatArray
    north: FloatArray
    diag: FloatArray
    rhs: FloatArray
    couette: FloatArray
    squeeze: FloatArray
    row_weight: FloatArray
    #: the face coefficients of every coupled pair: ``east`` (all), then ``north[:, :-1]``,
    #: flattened (the pairs of ``_reynolds_lcp``)
    couplings: FloatArray

    def apply(self, values: FloatArray) -> FloatArray:
        """K·Π on the block (edge values 0; the mirror condition built in)."""
        east, north = self.east, self.north[:, :-1]
        r = self.diag * values
        flux = east * values
        r[:-1] -= east[:-1] * values[1:]
        r[-1] -= east[-1] * values[0]
        r[1:] -= flux[:-1]
        r[0] -= flux[-1]
        r[:, :-1] -= north * values[:, 1:]
        r[:, 1:] -= north * values[:, :-1]
        return r


def stencil(
    grid: Grid,
    *,
    chi_x: float,
    chi_y: float,
    vel_x: float,
    vel_y: float,
    omega: float,
    mu_bar: float,
) -> Stencil:
    """Assemble the scheme for the journal at (χ_x, χ_y) moving at (vel_x, vel_y) = dχ/dτ.

    The right side of (3.1)-(3.4) in Cartesian form, without the singularity of χ' and δ'
    at χ = 0:  M = 6μ̄·[Ω ∂H/∂φ + 2 ∂H/∂τ],  ∂H/∂τ = -vel_x cos φ - vel_y sin φ.
    """
    _, _, _, ce, se = _trig(grid.n_phi)
    h, h_east = film_thickness(grid, chi_x, chi_y)
    # ∫ over the cell of ∂H/∂τ dφ, exactly: -vel_x·[sin φ] + vel_y·[cos φ] from west to east.
    sq = -vel_x * (se - np.roll(se, 1)) + vel_y * (ce - np.roll(ce, 1))
    couette = 6.0 * mu_bar * grid.d_z * omega * h_east
    squeeze = 12.0 * mu_bar * grid.d_z * sq
    source = couette - np.roll(couette, 1) + squeeze
    w = grid.row_weight
    m = grid.n_rows
    east = np.outer(h_east**3 * (grid.d_z / grid.d_phi), w)
    north = np.repeat((h**3 * (grid.d_phi / grid.d_z))[:, None], m, axis=1)
    south = np.empty_like(north)
    south[:, 1:] = north[:, :-1]
    # First row: the edge z = -a (full block), the half cell (no south face), or the
    # flux-free mirror face (odd n_z).
    south[:, 0] = 0.0 if grid.mirror else north[:, 0]
    diag = east + np.roll(east, 1, axis=0) + north + south
    rhs = -np.outer(source, w)
    return Stencil(
        east=east,
        north=north,
        diag=diag,
        rhs=rhs,
        couette=couette,
        squeeze=squeeze,
        row_weight=w,
        couplings=np.concatenate([east.ravel(), north[:, :-1].ravel()]),
    )


def sparse_operator(st: Stencil) -> sp.csr_matrix:
    """K of the stencil as a scipy sparse matrix (index ``i·m + j``); the direct reference."""
    n_phi, m = st.diag.shape
    idx = np.arange(n_phi * m).reshape(n_phi, m)
    east_idx = np.roll(idx, -1, axis=0)
    rows = [idx.ravel(), idx.ravel(), east_idx.ravel(), idx[:, :-1].ravel(), idx[:, 1:].ravel()]
    cols = [idx.ravel(), east_idx.ravel(), idx.ravel(), idx[:, 1:].ravel(), idx[:, :-1].ravel()]
    vals = [
        st.diag.ravel(),
        -st.east.ravel(),
        -st.east.ravel(),
        -st.north[:, :-1].ravel(),
        -st.north[:, :-1].ravel(),
    ]
    return sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(n_phi * m, n_phi * m),
    )
