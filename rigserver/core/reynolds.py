"""The finite-length journal bearing: the Reynolds equation (3.1) solved on a (φ, z) grid.

Between the two asymptotes of lab work 3, the short bearing (3.10)-(3.12) and the infinitely
long one (3.15), lies the real bearing of finite B/D. This module solves the manual's
dimensionless Reynolds equation (3.1)-(3.6) for it, with the Reynolds (Swift-Stieber)
cavitation condition or the mass-conserving Jakobsson-Floberg-Olsson one (film reformation)
as complementarity problems, the half-Sommerfeld (Gümbel) condition, or none, and
integrates what the design tables give: load, attitude, Sommerfeld number, friction, flows,
pressure maximum; the inverse problem (load → eccentricity) and the eight
linearised stiffness and damping coefficients.

Frame and signs (figure 3.2 of the manual): the bush is fixed; φ is measured from the X axis
of the bush frame in the direction of the journal's rotation; the journal centre sits at
χ·(cos δ, sin δ) (in units of h0), so H = 1 - χ cos(φ - δ) (3.2) is thinnest at φ = δ and
thickest at φ = δ + π. The classical h = c(1 + ε cos θ), with θ from the thickest film, is the
same with ε = χ, c = h0 and θ = φ - δ - π. The attitude angle ψ is the angle from the load line
to the line of centres, positive in the direction of rotation (0 < ψ < 90° for a loaded
bearing): the load acts at φ = δ - ψ.

Dimensionless scales (3.6): z = Z/R, Π = (p - p_a)ψ²/(μ0ω0) with ψ = h0/R, τ = ω0 t; forces
in μ0ω0R⁴/h0² (= P*/(4a) with the P* of (4.2)), torques in μ0ω0R⁴/h0, flows in ω0R²h0. The
half-width is a = B/(2R) = B/D (3.5, corrected E3).

See ``docs/reynolds.md`` for the method, its validation and the grid-convergence table.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import brentq

from rigserver.core import _reynolds_lcp as lcp
from rigserver.core._checks import finite, non_negative, one_of, positive, within
from rigserver.core._reynolds_grid import FloatArray, Grid, film_thickness, make_grid, stencil
from rigserver.core._reynolds_jfo import solve_mass_conserving
from rigserver.core._reynolds_lcp import BoolArray
from rigserver.core._reynolds_post import Integrals, film_force, integrate
from rigserver.core.errors import ModelInputError

__all__ = [
    "CAVITATION_MODELS",
    "DEFAULT_N_PHI",
    "DEFAULT_N_Z",
    "EQUILIBRIUM_CHI_RANGE",
    "MAX_ACTIVE_SET_ITERATIONS",
    "DynamicCoefficients",
    "FiniteBearing",
    "JournalEquilibrium",
    "ReynoldsSolution",
    "Supply",
    "SupplyGroove",
    "SupplyHole",
    "dynamic_coefficients",
    "equilibrium",
    "finite_bearing",
    "journal_equilibrium",
    "solve_reynolds",
]

#: Cavitation conditions: Swift-Stieber as a complementarity problem, the mass-conserving
#: Jakobsson-Floberg-Olsson condition (Elrod's p-θ model, film reformation included) as
#: another, Gümbel's clipping of the Sommerfeld field, and none (negative pressures kept, the
#: full Sommerfeld film).
CAVITATION_MODELS = ("reynolds", "jfo", "half_sommerfeld", "sommerfeld")
#: Default grid: intervals in φ over 2π and in z over the full width (issue 5).
DEFAULT_N_PHI = 144
DEFAULT_N_Z = 48
#: Limit of the active-set iteration; it ends in far fewer steps (docs/reynolds.md).
MAX_ACTIVE_SET_ITERATIONS = 200
#: Coarsest grid of the coarse-to-fine start of the active-set iteration.
_COARSEST_N_PHI = 36
_COARSEST_N_Z = 8
#: Projected Gauss-Seidel sweeps smoothing a coarse grid's field into the next grid's start.
_SMOOTHING_SWEEPS = 10
#: The same from the coarsest grid to the next (whose factorisations cost little).
_COARSE_SMOOTHING_SWEEPS = 5
#: Eccentricity ratios bracketing the inverse problem; beyond 0.99 the default grid no longer
#: resolves the pressure spike at the thinnest film.
EQUILIBRIUM_CHI_RANGE = (1e-6, 0.99)


@dataclass(frozen=True, slots=True)
class SupplyGroove:
    """An axial oil groove held at the supply pressure Π_ok (3.5).

    Attributes
    ----------
    angle : float
        Angle φ of the groove's centre line in the bush frame, rad.
    width : float
        Angular width, rad (0: a line; it takes at least the nearest grid column).
    length : float
        Axial length as a fraction of B, centred on z = 0, in (0, 1].
    pressure : float
        Π_ok, dimensionless supply pressure (3.6), >= 0.
    """

    angle: float
    width: float = 0.0
    length: float = 1.0
    pressure: float = 0.0


@dataclass(frozen=True, slots=True)
class SupplyHole:
    """A round oil hole held at the supply pressure Π_ok (3.5).

    Attributes
    ----------
    angle : float
        Angle φ of the hole's centre in the bush frame, rad.
    diameter : float
        Diameter over R (takes at least the nearest grid node).
    z : float
        Axial position of the centre, z = Z/R, |z| < a.
    pressure : float
        Π_ok, dimensionless supply pressure (3.6), >= 0.
    """

    angle: float
    diameter: float
    z: float = 0.0
    pressure: float = 0.0


Supply = SupplyGroove | SupplyHole


@dataclass(frozen=True, slots=True)
class ReynoldsSolution:
    """The pressure field of (3.1) and its integrals, dimensionless in the scales of (3.6).

    Attributes
    ----------
    phi : ndarray, shape (n_phi,)
        Node angles φ, rad, bush frame.
    z : ndarray, shape (n_z + 1,)
        Node positions z = Z/R from -a to a.
    pressure : ndarray, shape (n_phi, n_z + 1)
        Π(φ, z) (3.6); 0 at the edges; >= 0 unless ``cavitation == "sommerfeld"``.
    film : ndarray, shape (n_phi,)
        H(φ) (3.2).
    ruptured : ndarray of bool, shape (n_phi, n_z + 1)
        Nodes of the ruptured (cavitated) film; with the half-Sommerfeld condition, those where
        the Sommerfeld field was negative.
    film_fraction : ndarray, shape (n_phi, n_z + 1)
        θ, the share of the clearance filled with oil (1 in the full film): solved for by
        ``"jfo"``; otherwise carried from the rupture line by the streamers.
    force_x, force_y : float
        Film force on the journal in the bush frame, unit μ0ω0R⁴/h0².
    load : float
        |F|, the load the film carries, same unit.
    journal_torque, bush_torque : float
        Friction torques, unit μ0ω0R⁴/h0: the film's drag on the journal (against its rotation)
        and on the bush (along it), with the film fraction θ in the ruptured zone.
    journal_torque_full_film : float
        Journal torque with a full film's Couette shear all round (the convention of the
        classical tables and of (4.1)).
    ruptured_torque : float
        The part of ``journal_torque`` from the ruptured zone.
    inflow : float
        Flow out of the supplies into the film, unit ω0R²h0.
    side_flow : float
        Flow out through both edges z = ±a, unit ω0R²h0.
    max_pressure, max_pressure_phi, max_pressure_z : float
        Π_max and where it is (rad, units of R), refined by a parabola through the nodes.
    cavitation : str
        The condition used.
    iterations : int
        Active-set steps on the finest grid (1 for a linear solve).
    converged : bool
        Whether the complementarity iteration ended with a stable active set.
    """

    phi: FloatArray
    z: FloatArray
    pressure: FloatArray
    film: FloatArray
    ruptured: BoolArray
    film_fraction: FloatArray
    force_x: float
    force_y: float
    load: float
    journal_torque: float
    bush_torque: float
    journal_torque_full_film: float
    ruptured_torque: float
    inflow: float
    side_flow: float
    max_pressure: float
    max_pressure_phi: float
    max_pressure_z: float
    cavitation: str
    iterations: int
    converged: bool

    def pressure_at(self, *, phi: ArrayLike, z: ArrayLike) -> FloatArray:
        """Π at angles ``phi`` (rad, bush frame) and axial positions ``z`` (units of R).

        Bilinear interpolation between the nodes (second order, like the scheme), periodic
        in φ; for comparing with manometers at given holes. Broadcasts ``phi`` with ``z``.
        """
        ph, zz = np.broadcast_arrays(finite("phi", phi), finite("z", z))
        a = float(self.z[-1])
        if np.any(np.abs(zz) > a):
            bad = zz[np.abs(zz) > a].flat[0]
            raise ModelInputError(f"z must lie in [-{a}, {a}] (the bearing's edges), got {bad}")
        n = self.phi.size
        d_phi = 2.0 * np.pi / n
        s = np.mod(ph, 2.0 * np.pi) / d_phi
        i0 = np.floor(s).astype(np.intp) % n
        u = s - np.floor(s)
        t = (zz + a) / (2.0 * a) * (self.z.size - 1)
        j0 = np.minimum(np.floor(t).astype(np.intp), self.z.size - 2)
        v = t - j0
        i1 = (i0 + 1) % n
        p = self.pressure
        return np.asarray(
            (1 - u) * (1 - v) * p[i0, j0]
            + u * (1 - v) * p[i1, j0]
            + (1 - u) * v * p[i0, j0 + 1]
            + u * v * p[i1, j0 + 1],
            dtype=np.float64,
        )


def _grid_size(name: str, value: int | None, default: int, minimum: int) -> int:
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < minimum:
        raise ModelInputError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


@dataclass(frozen=True, slots=True)
class _Problem:
    """What stays fixed while the journal moves: grid, speed, viscosity, supplies."""

    n_phi: int
    n_z: int
    half_width: float
    omega: float
    mu_bar: float
    supply: tuple[Supply, ...]
    cavitation: str
    mirror: bool


def _check_supply(supply: Sequence[Supply], half_width: float) -> tuple[Supply, ...]:
    out: list[Supply] = []
    for k, s in enumerate(supply):
        name = f"supply[{k}]"
        finite(f"{name}.angle", s.angle)
        non_negative(f"{name}.pressure", s.pressure)
        if isinstance(s, SupplyGroove):
            non_negative(f"{name}.width", s.width)
            within(f"{name}.length", s.length, 0.0, 1.0, closed=(False, True))
        elif isinstance(s, SupplyHole):
            positive(f"{name}.diameter", s.diameter)
            within(f"{name}.z", s.z, -half_width, half_width, closed=(False, False))
        else:
            raise ModelInputError(f"{name} must be a SupplyGroove or SupplyHole, got {s!r}")
        out.append(s)
    return tuple(out)


@lru_cache(maxsize=64)
def _supply_nodes(grid: Grid, supply: tuple[Supply, ...]) -> tuple[BoolArray, FloatArray]:
    """Nodes of the full grid held at the supply pressures, and the values (read-only,
    remembered per grid and supply).

    The edge nodes of a groove that runs the whole length belong to it too (they stay at
    ambient pressure), so that the flow out of it is counted over the full width.
    """
    phi, z = grid.phi, grid.z
    fixed = np.zeros((grid.n_phi, grid.n_z + 1), dtype=bool)
    values = np.zeros(fixed.shape)
    interior = np.arange(1, grid.n_z)
    for s in supply:
        dphi = np.abs(np.angle(np.exp(1j * (phi - s.angle))))
        mask = np.zeros_like(fixed)
        if isinstance(s, SupplyGroove):
            cols = dphi <= s.width / 2.0 + 1e-12
            if not cols.any():
                cols = dphi == dphi.min()
            rows = np.abs(z[interior]) <= s.length * grid.half_width + 1e-12
            if not rows.any():
                rows = np.abs(z[interior]) == np.abs(z[interior]).min()
            mask[np.ix_(cols, interior[rows])] = True
            if rows.all():
                # A groove over the whole length meets the edges: its edge nodes (ambient)
                # belong to it when the flow out of it is counted.
                mask[np.ix_(cols, [0, grid.n_z])] = True
        else:
            dist2 = dphi[:, None] ** 2 + (z[None, interior] - s.z) ** 2
            inside = dist2 <= (s.diameter / 2.0) ** 2 + 1e-12
            if not inside.any():
                inside = dist2 == dist2.min()
            mask[:, interior] = inside
        fixed |= mask
        values[mask] = s.pressure
    values[:, [0, -1]] = 0.0
    fixed.setflags(write=False)
    values.setflags(write=False)
    return fixed, values


def _symmetric(supply: tuple[Supply, ...]) -> bool:
    return all(isinstance(s, SupplyGroove) or s.z == 0.0 for s in supply)


def _prolong(coarse: BoolArray, n_phi: int, n_z: int) -> BoolArray:
    """A fine-grid guess of the ruptured set: ruptured where all nearby coarse nodes are."""
    c = coarse.copy()
    c[:, [0, -1]] = True  # the edges do not veto
    n_c = c.shape[0]
    i = np.arange(n_phi)
    j = np.arange(n_z + 1)
    out = np.ones((n_phi, n_z + 1), dtype=bool)
    for ii in ((i // 2) % n_c, ((i + 1) // 2) % n_c):
        for jj in (j // 2, (j + 1) // 2):
            out &= c[np.ix_(ii, jj)]
    out[:, [0, -1]] = False
    return out


def _prolong_pressure(coarse: FloatArray) -> FloatArray:
    """A coarse grid's Π on the grid twice as fine in both directions (bilinear; the coarse
    nodes are every other fine node, φ periodic)."""
    n_c, rows_c = coarse.shape
    fine = np.empty((2 * n_c, 2 * rows_c - 1))
    fine[0::2, 0::2] = coarse
    fine[1:-1:2, 0::2] = 0.5 * (coarse[:-1] + coarse[1:])
    fine[-1, 0::2] = 0.5 * (coarse[-1] + coarse[0])
    fine[:, 1::2] = 0.5 * (fine[:, 0:-1:2] + fine[:, 2::2])
    return fine


@dataclass(frozen=True, slots=True)
class _Field:
    """Π, the ruptured set and θ (solved for by "jfo", else None) on the full node grid, the
    supply nodes, how the solve ended."""

    grid: Grid
    pressure: FloatArray
    ruptured: BoolArray
    film_fraction: FloatArray | None
    fixed: BoolArray
    iterations: int
    converged: bool


def _field(
    pb: _Problem,
    chi_x: float,
    chi_y: float,
    vel_x: float,
    vel_y: float,
    guess: BoolArray | None,
) -> _Field:
    """Solve on the grid of ``pb``; ``guess`` is a ruptured-set start for the LCP."""
    grid = make_grid(pb.n_phi, pb.n_z, pb.half_width, mirror=pb.mirror)
    rows = slice(grid.first_row, grid.n_z)
    st = stencil(
        grid,
        chi_x=chi_x,
        chi_y=chi_y,
        vel_x=vel_x,
        vel_y=vel_y,
        omega=pb.omega,
        mu_bar=pb.mu_bar,
    )
    fixed_full, values_full = _supply_nodes(grid, pb.supply)
    fixed, fixed_values = fixed_full[:, rows], values_full[:, rows]
    iterations, converged = 1, True
    theta_block: FloatArray | None = None
    if pb.cavitation == "jfo":
        if guess is None:  # start from the Swift-Stieber rupture
            reynolds = replace(pb, cavitation="reynolds")
            guess = _field(reynolds, chi_x, chi_y, vel_x, vel_y, None).ruptured
        jfo = solve_mass_conserving(
            st,
            fixed,
            fixed_values,
            guess[:, rows],
            omega=pb.omega,
            max_iter=MAX_ACTIVE_SET_ITERATIONS,
        )
        block, ruptured_block, theta_block = jfo.values, jfo.ruptured, jfo.film_fraction
        iterations, converged = jfo.iterations, jfo.converged
    elif pb.cavitation == "reynolds":
        coarse_pb = _coarser(pb) if guess is None else None
        if coarse_pb is not None:
            coarse = _field(coarse_pb, chi_x, chi_y, vel_x, vel_y, None)
            prolonged = _prolong_pressure(coarse.pressure)[:, rows]
            sweeps = _SMOOTHING_SWEEPS if _coarser(coarse_pb) else _COARSE_SMOOTHING_SWEEPS
            start = lcp.smoothed_rupture(st, fixed, fixed_values, prolonged, sweeps)
        else:
            start = guess[:, rows] if guess is not None else st.rhs < 0.0
        res = lcp.solve_complementarity(
            st, fixed, fixed_values, start, max_iter=MAX_ACTIVE_SET_ITERATIONS
        )
        block, ruptured_block = res.values, res.active
        iterations, converged = res.iterations, res.converged
    else:
        block = lcp.solve_fixed(st, fixed, fixed_values, ~fixed)
        ruptured_block = (block < 0.0) & ~fixed
        if pb.cavitation == "half_sommerfeld":
            block = np.maximum(block, 0.0)
        else:
            ruptured_block = np.zeros_like(fixed)

    p = np.zeros((grid.n_phi, grid.n_z + 1))
    ruptured = np.zeros(p.shape, dtype=bool)
    p[:, rows] = block
    ruptured[:, rows] = ruptured_block
    theta = None
    if theta_block is not None:
        theta = np.ones(p.shape)
        theta[:, rows] = theta_block
    if grid.mirror:
        mirrored = grid.n_z - np.arange(grid.first_row)  # z_j = -z_(n_z - j)
        p[:, : grid.first_row] = p[:, mirrored]
        ruptured[:, : grid.first_row] = ruptured[:, mirrored]
        if theta is not None:
            theta[:, : grid.first_row] = theta[:, mirrored]
    return _Field(grid, p, ruptured, theta, fixed_full, iterations, converged)


def _solve(
    pb: _Problem,
    chi_x: float,
    chi_y: float,
    vel_x: float,
    vel_y: float,
    guess: BoolArray | None,
) -> ReynoldsSolution:
    """The field of :func:`_field` and its integrals."""
    f = _field(pb, chi_x, chi_y, vel_x, vel_y, guess)
    h = film_thickness(f.grid, chi_x, chi_y)[0]
    ig: Integrals = integrate(
        f.grid,
        f.pressure,
        f.ruptured,
        f.fixed,
        h,
        omega=pb.omega,
        mu_bar=pb.mu_bar,
        film_fraction=None if f.film_fraction is None else f.film_fraction[:, 1:-1],
    )
    return ReynoldsSolution(
        phi=f.grid.phi,
        z=f.grid.z,
        pressure=f.pressure,
        film=h,
        ruptured=f.ruptured,
        film_fraction=ig.film_fraction,
        force_x=ig.force_x,
        force_y=ig.force_y,
        load=float(np.hypot(ig.force_x, ig.force_y)),
        journal_torque=ig.journal_torque,
        bush_torque=ig.bush_torque,
        journal_torque_full_film=ig.journal_torque_full_film,
        ruptured_torque=ig.ruptured_torque,
        inflow=ig.inflow,
        side_flow=ig.side_flow,
        max_pressure=ig.max_pressure,
        max_pressure_phi=ig.max_pressure_phi,
        max_pressure_z=ig.max_pressure_z,
        cavitation=pb.cavitation,
        iterations=f.iterations,
        converged=f.converged,
    )


def _problem(
    *,
    half_width: float,
    omega: float,
    mu_bar: float,
    supply: Sequence[Supply],
    n_phi: int | None,
    n_z: int | None,
    cavitation: str,
    use_symmetry: bool,
) -> _Problem:
    a = float(positive("half_width", half_width))
    sup = _check_supply(supply, a)
    if cavitation == "jfo" and not sup:
        raise ModelInputError(
            "cavitation 'jfo' conserves the oil's mass and needs a supply to fill the film "
            "(supply=[SupplyGroove(...)] or [SupplyHole(...)]); without one the film is "
            "starved"
        )
    return _Problem(
        n_phi=_grid_size("n_phi", n_phi, DEFAULT_N_PHI, 16),
        n_z=_grid_size("n_z", n_z, DEFAULT_N_Z, 4),
        half_width=a,
        omega=float(finite("omega", omega)),
        mu_bar=float(positive("mu_bar", mu_bar)),
        supply=sup,
        cavitation=one_of("cavitation", cavitation, CAVITATION_MODELS),
        mirror=use_symmetry and _symmetric(sup),
    )


def _guess(warm_start: ReynoldsSolution | None, pb: _Problem) -> BoolArray | None:
    if warm_start is None:
        return None
    if warm_start.ruptured.shape != (pb.n_phi, pb.n_z + 1):
        raise ModelInputError(
            f"warm_start must come from the same grid ({pb.n_phi} x {pb.n_z}), "
            f"got a field of shape {warm_start.ruptured.shape}"
        )
    return warm_start.ruptured


def solve_reynolds(
    *,
    chi: float,
    half_width: float,
    delta: float = 0.0,
    chi_dot: float = 0.0,
    delta_dot: float = 0.0,
    omega: float = 1.0,
    mu_bar: float = 1.0,
    supply: Sequence[Supply] = (),
    n_phi: int | None = None,
    n_z: int | None = None,
    cavitation: str = "reynolds",
    use_symmetry: bool = True,
    warm_start: ReynoldsSolution | None = None,
) -> ReynoldsSolution:
    """Pressure field of a finite journal bearing from the Reynolds equation (3.1)-(3.5).

    .. math::
        \\frac{\\partial}{\\partial\\varphi}\\Big(H^3\\frac{\\partial\\Pi}{\\partial\\varphi}\\Big)
        + \\frac{\\partial}{\\partial z}\\Big(H^3\\frac{\\partial\\Pi}{\\partial z}\\Big)
        = 6\\bar\\mu\\,[G\\chi\\sin(\\varphi-\\delta) - E\\cos(\\varphi-\\delta)],
        \\quad H = 1 - \\chi\\cos(\\varphi-\\delta),

    G = Ω - 2δ', E = 2χ' (3.3)-(3.4); Π = 0 at z = ±a, Π = Π_ok on the supplies (3.5), and
    the cavitation condition: ``"reynolds"`` Π ≥ 0 with ∂Π/∂n = 0 at rupture (solved as the
    complementarity problem Π ≥ 0, KΠ - b ≥ 0, Π·(KΠ - b) = 0); ``"jfo"`` the
    mass-conserving Jakobsson-Floberg-Olsson condition, in which the ruptured film runs in
    streamers filling a fraction θ of the clearance and reforms where they fill it again
    (Elrod's p-θ model as the complementarity problem Π ≥ 0, 1 - θ ≥ 0, Π·(1 - θ) = 0;
    needs a supply; the squeeze term takes θ frozen); ``"half_sommerfeld"`` the full-film
    field with its negative part set to 0 (Gümbel); ``"sommerfeld"`` none.

    Parameters
    ----------
    chi : float
        Relative eccentricity χ = e/h0, 0 <= χ < 1.
    half_width : float
        a = B/(2R) = B/D (3.5, corrected E3), > 0.
    delta : float
        Angle δ of the line of centres in the bush frame, rad.
    chi_dot, delta_dot : float
        dχ/dτ and dδ/dτ, τ = ω0 t (3.4).
    omega : float
        Ω = (ω1 - ω2)/ω0, the journal's relative angular speed.
    mu_bar : float
        μ̄ = μ/μ0, mean viscosity over the film (3.6), > 0.
    supply : sequence of SupplyGroove or SupplyHole
        Oil feeds held at their pressure; none: ambient only at the edges.
    n_phi, n_z : int, optional
        Grid intervals in φ (over 2π, >= 16) and in z (over the full width, >= 4);
        144 x 48 by default.
    cavitation : {"reynolds", "jfo", "half_sommerfeld", "sommerfeld"}
        Condition where the film would go below ambient pressure.
    use_symmetry : bool
        Solve the upper half z >= 0 only when the problem is symmetric about z = 0 (no hole
        off the mid-plane); the field is the same, at a quarter of the cost.
    warm_start : ReynoldsSolution, optional
        A solution on the same grid whose ruptured zone starts the active-set iteration
        (otherwise a coarse grid's answer does).

    Returns
    -------
    ReynoldsSolution
        The field Π(φ, z), forces, friction torques, flows, the pressure maximum.

    Notes
    -----
    Finite volumes on a vertex-centred grid, periodic in φ (second order); the Reynolds
    condition by a primal-dual active-set iteration with a banded Cholesky factorisation of
    the free nodes per step; see ``docs/reynolds.md``. The right side is used in the
    Cartesian form 6μ̄[Ω ∂H/∂φ + 2 ∂H/∂τ], equal to (3.3) and regular at χ = 0.

    Integrals [1]: film force on the journal F = -∫∫Π(cos φ, sin φ) dφ dz; shear stress on
    the journal θμ̄Ω/H + (H/2)∂Π/∂φ and on the bush θμ̄Ω/H - (H/2)∂Π/∂φ (the Couette and
    Poiseuille parts of the film's velocity profile), so that T_journal - T_bush = χ_x F_y -
    χ_y F_x, the pressure torque; θ = 1 in the full film and θ = H_r/H in the ruptured zone,
    H_r the film at the last full-film node upstream on the same z (streamers carried by the
    journal, mass kept from rupture on). Flows per unit length q_φ = ΩH/2 - H³∂Π/∂φ/(12μ̄),
    q_z = -H³∂Π/∂z/(12μ̄): the side flow is q_z at z = ±a, the inflow the flow out of the
    supplies into the film. Isoviscous film; rigid, aligned surfaces.

    References
    ----------
    [1] Hamrock B.J., Schmid S.R., Jacobson B.O. Fundamentals of Fluid Film Lubrication,
        2nd ed. Marcel Dekker, 2004, ch. 7, 9, 10.
    [2] Raimondi A.A., Boyd J. A solution for the finite journal bearing and its application
        to analysis and design. ASLE Trans. 1 (1958) 159-209.
    """
    pb = _problem(
        half_width=half_width,
        omega=omega,
        mu_bar=mu_bar,
        supply=supply,
        n_phi=n_phi,
        n_z=n_z,
        cavitation=cavitation,
        use_symmetry=use_symmetry,
    )
    x = float(within("chi", chi, 0.0, 1.0, closed=(True, False)))
    d = float(finite("delta", delta))
    xd = float(finite("chi_dot", chi_dot))
    dd = float(finite("delta_dot", delta_dot))
    c, s = np.cos(d), np.sin(d)
    return _solve(
        pb, x * c, x * s, xd * c - x * dd * s, xd * s + x * dd * c, _guess(warm_start, pb)
    )


@dataclass(frozen=True, slots=True)
class FiniteBearing:
    """A stationary, centrally loaded full bearing in the figures of the design tables [2].

    Attributes
    ----------
    eccentricity_ratio : float
        ε = χ = e/c.
    length_to_diameter : float
        B/D (= the half-width a, E3).
    sommerfeld : float
        S = (R/c)²·μN/P, N in rev/s, P = W/(B·D).
    attitude_deg : float
        ψ, from the load line to the line of centres in the direction of rotation, degrees.
    friction_variable : float
        (R/c)·f with a full film's shear all round, as in the tables [2] and (4.1).
    friction_variable_film_fraction : float
        (R/c)·f with the shear of the ruptured zone reduced by the film fraction θ.
    flow_variable : float
        Q/(R·c·N·B), Q the flow entering the film from the supply at the thickest film.
    side_flow_ratio : float
        Q_s/Q, Q_s the flow out through both edges.
    max_pressure_ratio : float
        P/p_max.
    max_pressure_angle_deg : float
        Position of p_max from the thickest film in the direction of rotation, degrees.
    load : float
        Dimensionless load |F|, unit μωR⁴/c² (the scale of (3.6) with ω0 = ω, μ0 = μ).
    cavitation : str
        The cavitation condition.
    converged : bool
        The complementarity iteration (and, from :func:`equilibrium`, the root search) ended.
    solution : ReynoldsSolution
        The field and its integrals.
    """

    eccentricity_ratio: float
    length_to_diameter: float
    sommerfeld: float
    attitude_deg: float
    friction_variable: float
    friction_variable_film_fraction: float
    flow_variable: float
    side_flow_ratio: float
    max_pressure_ratio: float
    max_pressure_angle_deg: float
    load: float
    cavitation: str
    converged: bool
    solution: ReynoldsSolution


def _design_problem(
    length_to_diameter: float, n_phi: int | None, n_z: int | None, cavitation: str
) -> _Problem:
    # Raimondi and Boyd's full bearing [2]: the film starts at ambient pressure at the
    # thickest film, here a line groove at φ = π (δ = 0).
    return _problem(
        half_width=length_to_diameter,
        omega=1.0,
        mu_bar=1.0,
        supply=(SupplyGroove(angle=np.pi),),
        n_phi=n_phi,
        n_z=n_z,
        cavitation=cavitation,
        use_symmetry=True,
    )


def _design_figures(chi: float, pb: _Problem, sol: ReynoldsSolution, ok: bool) -> FiniteBearing:
    a = pb.half_width
    load = sol.load
    if load <= 0.0:
        raise ModelInputError(f"eccentricity_ratio must be > 0 for a loaded bearing, got {chi}")
    return FiniteBearing(
        eccentricity_ratio=chi,
        length_to_diameter=a,
        sommerfeld=2.0 * a / (np.pi * load),
        attitude_deg=float(np.degrees(np.arctan2(sol.force_y, -sol.force_x))),
        friction_variable=sol.journal_torque_full_film / load,
        friction_variable_film_fraction=sol.journal_torque / load,
        flow_variable=np.pi * sol.inflow / a,
        side_flow_ratio=sol.side_flow / sol.inflow,
        max_pressure_ratio=load / (4.0 * a * sol.max_pressure),
        max_pressure_angle_deg=float(np.degrees(sol.max_pressure_phi - np.pi)),
        load=load,
        cavitation=pb.cavitation,
        converged=ok and sol.converged,
        solution=sol,
    )


def finite_bearing(
    eccentricity_ratio: float,
    length_to_diameter: float,
    *,
    n_phi: int | None = None,
    n_z: int | None = None,
    cavitation: str = "reynolds",
) -> FiniteBearing:
    """Design-table figures of a plain full journal bearing at a given eccentricity ratio.

    Solves (3.1) with δ = 0, χ' = δ' = 0, Ω = μ̄ = 1 (stationary, isoviscous, centrally
    loaded, bush fixed) and ambient pressure on a line groove at the thickest film, as
    Raimondi and Boyd [2]. With the load |F| in units of μωR⁴/c²:

    .. math::
        S = \\frac{2a}{\\pi |F|},\\quad \\frac{R}{c}f = \\frac{T_j}{|F|},\\quad
        \\frac{Q}{RcNB} = \\frac{\\pi q}{a},\\quad \\frac{P}{p_{max}} = \\frac{|F|}{4a\\Pi_{max}},

    a = B/D, T_j the journal torque (μωR⁴/c), q the inflow (ωR²c).

    Parameters
    ----------
    eccentricity_ratio : float
        ε = e/c, 0 < ε < 1.
    length_to_diameter : float
        B/D, > 0.
    n_phi, n_z : int, optional
        Grid (default 144 x 48, n_z over the full width).
    cavitation : {"reynolds", "jfo", "half_sommerfeld", "sommerfeld"}
        Cavitation condition (see :func:`solve_reynolds`; with the groove at the thickest
        film "jfo" gives the Reynolds condition's field, the film reforming at the groove).

    Returns
    -------
    FiniteBearing

    Notes
    -----
    The friction variable follows the tables' convention (a full film's Couette shear all
    round plus the pressure-gradient shear; for the long bearing
    (R/c)f = 2π²S/√(1-ε²) + ε sin ψ/2); the film-fraction variant is given beside it.

    References
    ----------
    [2] Raimondi A.A., Boyd J. ASLE Trans. 1 (1958) 159-209.
    """
    chi = float(within("eccentricity_ratio", eccentricity_ratio, 0.0, 1.0, closed=(False, False)))
    pb = _design_problem(length_to_diameter, n_phi, n_z, cavitation)
    return _design_figures(chi, pb, _solve(pb, chi, 0.0, 0.0, 0.0, None), True)


def equilibrium(
    sommerfeld: float,
    length_to_diameter: float,
    *,
    n_phi: int | None = None,
    n_z: int | None = None,
    cavitation: str = "reynolds",
) -> FiniteBearing:
    """The bearing of :func:`finite_bearing` at the eccentricity ratio that carries a load.

    Solves S(ε) = S for ε by Brent's method on ln S against logit ε (S falls monotonically
    from ∞ at ε = 0 to 0 at ε = 1), first on coarser grids, whose root brackets the next
    one's; each field starts from the ruptured zone of the nearest one solved.

    Parameters
    ----------
    sommerfeld : float
        S = (R/c)²·μN/P, N in rev/s, P = W/(B·D), > 0.
    length_to_diameter : float
        B/D, > 0.
    n_phi, n_z, cavitation
        As in :func:`finite_bearing`.

    Returns
    -------
    FiniteBearing
        At the equilibrium ε; ``converged`` tells whether the root search ended.

    Raises
    ------
    ModelInputError
        If S needs ε outside ``EQUILIBRIUM_CHI_RANGE`` (0.99 is the grid's limit).
    """
    s_target = float(positive("sommerfeld", sommerfeld))
    pb = _design_problem(length_to_diameter, n_phi, n_z, cavitation)
    root = _load_root(pb, s_target)
    if root is None:
        s_min, s_max = (
            2.0 * pb.half_width / (np.pi * _solve(pb, c, 0.0, 0.0, 0.0, None).load)
            for c in EQUILIBRIUM_CHI_RANGE[::-1]
        )
        raise ModelInputError(
            f"sommerfeld must lie in [{s_min:.4g}, {s_max:.4g}] for B/D = {pb.half_width} on "
            f"this grid (eccentricity ratio {EQUILIBRIUM_CHI_RANGE[0]} .. "
            f"{EQUILIBRIUM_CHI_RANGE[1]}), got {s_target}"
        )
    chi, sol, ok = root
    return _design_figures(chi, pb, sol, ok)


def _coarser(pb: _Problem) -> _Problem | None:
    """The problem on the grid halved in both directions, if it is not too coarse."""
    if (
        pb.n_phi % 2 == 0
        and pb.n_z % 2 == 0
        and pb.n_phi // 2 >= _COARSEST_N_PHI
        and pb.n_z // 2 >= _COARSEST_N_Z
    ):
        return replace(pb, n_phi=pb.n_phi // 2, n_z=pb.n_z // 2)
    return None


def _load_root(pb: _Problem, s_target: float) -> tuple[float, ReynoldsSolution, bool] | None:
    """ε with S(ε) = s_target on the grid of ``pb``, its solution and whether Brent's method
    converged; None if S is out of reach in ``EQUILIBRIUM_CHI_RANGE``.

    Brent's method on ln S against u = logit ε, bracketed around the root of the coarser
    grid when there is one (widening the bracket as needed), else over the whole range.
    Each field starts from the ruptured zone of the nearest one solved, or the coarse root's.
    """
    fields: dict[float, tuple[BoolArray, float]] = {}
    starts: list[tuple[float, BoolArray]] = []

    def chi_of(u: float) -> float:
        return float(1.0 / (1.0 + np.exp(-u)))

    def residual(u: float) -> float:
        if u not in fields:
            known = starts + [(v, rup) for v, (rup, _) in fields.items()]
            near = min(known, key=lambda k: abs(k[0] - u), default=None)
            guess = near[1] if near is not None and abs(near[0] - u) < 0.5 else None
            f = _field(pb, chi_of(u), 0.0, 0.0, 0.0, guess)
            load = float(np.hypot(*film_force(f.grid, f.pressure)))
            fields[u] = f.ruptured, float(np.log(2.0 * pb.half_width / (np.pi * load) / s_target))
        return fields[u][1]

    lo_end, hi_end = (float(np.log(c / (1.0 - c))) for c in EQUILIBRIUM_CHI_RANGE)
    lo, hi = lo_end, hi_end
    coarse_pb = _coarser(pb)
    coarse = _load_root(coarse_pb, s_target) if coarse_pb is not None else None
    if coarse is not None:
        u_c, width = float(np.log(coarse[0] / (1.0 - coarse[0]))), 0.05
        starts.append((u_c, _prolong(coarse[1].ruptured, pb.n_phi, pb.n_z)))
        lo, hi = max(u_c - width, lo_end), min(u_c + width, hi_end)
        while not residual(lo) > 0.0 > residual(hi) and (lo, hi) != (lo_end, hi_end):
            width *= 4.0
            lo, hi = max(u_c - width, lo_end), min(u_c + width, hi_end)
    if not residual(lo) > 0.0 > residual(hi):
        return None
    u, info = brentq(residual, lo, hi, xtol=1e-11, rtol=1e-13, full_output=True, disp=False)
    residual(u)
    sol = _solve(pb, chi_of(u), 0.0, 0.0, 0.0, fields[u][0])
    return chi_of(u), sol, bool(info.converged)


@dataclass(frozen=True, slots=True)
class JournalEquilibrium:
    """Where a journal runs under a steady load, in SI units.

    Attributes
    ----------
    eccentricity : float
        e, m.
    eccentricity_ratio : float
        ε = e/c.
    attitude_deg : float
        ψ, from the load line to the line of centres in the direction of rotation, degrees.
    min_film_thickness : float
        h_min = c(1 - ε), m.
    friction_coefficient : float
        f = T/(W·R), with the tables' full-film shear convention.
    friction_torque : float
        T on the journal, N·m.
    power_loss : float
        T·ω, W.
    inflow : float
        Oil flow into the film at the thickest film, m³/s.
    side_flow : float
        Oil flow out through both ends, m³/s.
    max_pressure : float
        Peak film pressure above ambient, Pa.
    bearing : FiniteBearing
        The dimensionless figures.
    """

    eccentricity: float
    eccentricity_ratio: float
    attitude_deg: float
    min_film_thickness: float
    friction_coefficient: float
    friction_torque: float
    power_loss: float
    inflow: float
    side_flow: float
    max_pressure: float
    bearing: FiniteBearing


def journal_equilibrium(
    *,
    load: float,
    speed: float,
    viscosity: float,
    radius: float,
    radial_clearance: float,
    length: float,
    n_phi: int | None = None,
    n_z: int | None = None,
    cavitation: str = "reynolds",
) -> JournalEquilibrium:
    """Eccentricity, attitude, friction and flows of a journal under a steady load.

    .. math:: S = \\Big(\\frac{R}{c}\\Big)^2 \\frac{\\mu N}{P},\\quad N = \\frac{\\omega}{2\\pi},
              \\quad P = \\frac{W}{2RB}

    then :func:`equilibrium` at S and B/D = B/(2R). The viscosity is the effective one of the
    film, e.g. μ_t = A·exp(α·t) (3.21) at the mean oil temperature (3.22) or (4.17)-(4.18).

    Parameters
    ----------
    load : float
        W, N, > 0.
    speed : float
        ω, the journal's angular speed, rad/s, > 0 (bush fixed).
    viscosity : float
        μ, Pa·s, > 0.
    radius : float
        R, m, > 0.
    radial_clearance : float
        c = h0, m, 0 < c < R.
    length : float
        B, m, > 0.
    n_phi, n_z, cavitation
        As in :func:`finite_bearing`.

    Returns
    -------
    JournalEquilibrium
    """
    w = float(positive("load", load))
    omega = float(positive("speed", speed))
    mu = float(positive("viscosity", viscosity))
    r = float(positive("radius", radius))
    c = float(within("radial_clearance", radial_clearance, 0.0, r, closed=(False, False)))
    b = float(positive("length", length))
    n_rev = omega / (2.0 * np.pi)
    s = (r / c) ** 2 * mu * n_rev / (w / (2.0 * r * b))
    fb = equilibrium(s, b / (2.0 * r), n_phi=n_phi, n_z=n_z, cavitation=cavitation)
    f = fb.friction_variable * c / r
    q = fb.flow_variable * r * c * n_rev * b
    return JournalEquilibrium(
        eccentricity=fb.eccentricity_ratio * c,
        eccentricity_ratio=fb.eccentricity_ratio,
        attitude_deg=fb.attitude_deg,
        min_film_thickness=c * (1.0 - fb.eccentricity_ratio),
        friction_coefficient=f,
        friction_torque=f * w * r,
        power_loss=f * w * r * omega,
        inflow=q,
        side_flow=q * fb.side_flow_ratio,
        max_pressure=w / (2.0 * r * b) / fb.max_pressure_ratio,
        bearing=fb,
    )


@dataclass(frozen=True, slots=True)
class DynamicCoefficients:
    """The eight linearised film coefficients, dimensionless, in the load frame.

    The film force changes by ΔF_i = -K_ij·Δx_j - C_ij·Δẋ_j for small journal displacements
    Δx and velocities Δẋ; x points along the load, y is 90° ahead of it in the direction of
    rotation.

    Attributes
    ----------
    stiffness : ndarray, shape (2, 2)
        K̄_ij = K_ij·c/W, rows/columns (x, y).
    damping : ndarray, shape (2, 2)
        C̄_ij = C_ij·c·ω/W.
    eccentricity_ratio, length_to_diameter, sommerfeld, attitude_deg : float
        The operating point (see :class:`FiniteBearing`).
    converged : bool
        All nine complementarity solves ended.
    """

    stiffness: FloatArray
    damping: FloatArray
    eccentricity_ratio: float
    length_to_diameter: float
    sommerfeld: float
    attitude_deg: float
    converged: bool


def dynamic_coefficients(
    eccentricity_ratio: float,
    length_to_diameter: float,
    *,
    n_phi: int | None = None,
    n_z: int | None = None,
    cavitation: str = "reynolds",
    step: float = 1e-4,
) -> DynamicCoefficients:
    """Stiffness and damping coefficients of the bearing of :func:`finite_bearing`.

    .. math::
        \\bar K_{ij} = -\\frac{1}{|F|}\\frac{\\partial F_i}{\\partial \\chi_j},\\qquad
        \\bar C_{ij} = -\\frac{1}{|F|}\\frac{\\partial F_i}{\\partial \\chi'_j}

    by central differences of the film force F (unit μωR⁴/c²) in the journal's displacement
    χ_j (unit c) and velocity χ'_j = dχ_j/dτ (unit cω), which enter (3.3) through
    G = Ω - 2δ' and E = 2χ' (3.4). The supply groove stays where it is in the bush; each
    perturbed solve starts from the ruptured zone of the steady one.

    Parameters
    ----------
    eccentricity_ratio, length_to_diameter, n_phi, n_z, cavitation
        As in :func:`finite_bearing`.
    step : float
        Perturbation of χ_j and χ'_j, in (0, 0.01].

    Returns
    -------
    DynamicCoefficients

    References
    ----------
    [3] Lund J.W. Review of the concept of dynamic coefficients for fluid film journal
        bearings. J. Tribol. 109 (1987) 37-41.
    """
    chi = float(within("eccentricity_ratio", eccentricity_ratio, 0.0, 1.0, closed=(False, False)))
    h = float(within("step", step, 0.0, 0.01, closed=(False, True)))
    pb = _design_problem(length_to_diameter, n_phi, n_z, cavitation)
    base = _design_figures(chi, pb, _solve(pb, chi, 0.0, 0.0, 0.0, None), True)
    sol = base.solution
    if chi + h >= 1.0:
        raise ModelInputError(f"eccentricity_ratio + step must be < 1, got {chi + h}")
    beta = np.arctan2(-sol.force_y, -sol.force_x)  # direction of the load
    axes = np.array([[np.cos(beta), np.sin(beta)], [-np.sin(beta), np.cos(beta)]])
    k = np.empty((2, 2))
    c = np.empty((2, 2))
    ok = base.converged
    for j, (ex, ey) in enumerate(axes):
        for target, moves in ((k, (h * ex, h * ey, 0.0, 0.0)), (c, (0.0, 0.0, h * ex, h * ey))):
            dx, dy, vx, vy = moves
            plus = _field(pb, chi + dx, dy, vx, vy, sol.ruptured)
            minus = _field(pb, chi - dx, -dy, -vx, -vy, sol.ruptured)
            ok = ok and plus.converged and minus.converged
            df = np.subtract(
                film_force(plus.grid, plus.pressure), film_force(minus.grid, minus.pressure)
            )
            target[:, j] = -(axes @ df) / (2.0 * h * sol.load)
    return DynamicCoefficients(
        stiffness=k,
        damping=c,
        eccentricity_ratio=chi,
        length_to_diameter=pb.half_width,
        sommerfeld=base.sommerfeld,
        attitude_deg=base.attitude_deg,
        converged=ok,
    )
