"""Integrals of a solved pressure field: forces, friction torques, flows, pressure maximum.

All quantities are dimensionless in the scales of (3.6): force μ0ω0R⁴/h0², torque
μ0ω0R⁴/h0, flow ω0R²h0. The field ``p`` has shape (n_phi, n_z + 1) with the edges included
(Π = 0 there); the trapezoidal rule in z is then a plain sum with weight Δz.

References
----------
[1] Hamrock B.J., Schmid S.R., Jacobson B.O. Fundamentals of Fluid Film Lubrication, 2nd ed.
    Marcel Dekker, 2004 (ch. 9: cavitation and film rupture; ch. 10: journal-bearing shear).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rigserver.core._reynolds_grid import FloatArray, Grid
from rigserver.core._reynolds_lcp import BoolArray


@dataclass(frozen=True, slots=True)
class Integrals:
    """Forces on the journal, torques, flows and the pressure maximum (dimensionless)."""

    force_x: float
    force_y: float
    journal_torque: float
    bush_torque: float
    journal_torque_full_film: float
    ruptured_torque: float
    inflow: float
    side_flow: float
    max_pressure: float
    max_pressure_phi: float
    max_pressure_z: float
    film_fraction: FloatArray


def streamer_fraction(ruptured: BoolArray, film: FloatArray, omega: float) -> FloatArray:
    """θ = H_r/H in the ruptured film, 1 elsewhere.

    Downstream of rupture the oil runs in streamers carried by the journal without a
    pressure gradient, so θ·H keeps the value H_r it had at the last full-film node upstream
    on the same z line (JFO streamer picture; Hamrock [1], ch. 9). A line that is ruptured
    all round keeps θ = 1. ``film`` has shape (n_phi,).
    """
    n = ruptured.shape[0]
    full = ~ruptured
    if omega < 0:
        full = full[::-1]
        film = film[::-1]
    doubled = np.concatenate([full, full], axis=0)
    last = np.where(doubled, np.arange(2 * n)[:, None], -1)
    last = np.maximum.accumulate(last, axis=0)[n:]
    h_rupture = np.where(last >= 0, film[last % n], film[:, None])
    theta = np.where(full, 1.0, np.minimum(1.0, h_rupture / film[:, None]))
    return theta[::-1] if omega < 0 else theta


def _one_sided(p0: FloatArray, p1: FloatArray, p2: FloatArray, step: float) -> FloatArray:
    """Second-order one-sided derivative at the first of three equally spaced points."""
    return (-3.0 * p0 + 4.0 * p1 - p2) / (2.0 * step)


def _supply_outflow(
    grid: Grid, p: FloatArray, fixed: BoolArray, film: FloatArray, omega: float, mu_bar: float
) -> float:
    """Gross flow out of the supply nodes into the film (positive parts of face fluxes).

    The flux leaving a supply node towards a film neighbour is taken at the supply node with
    a second-order one-sided pressure gradient: circumferentially Ω·H/2 - H³∂φΠ/(12μ̄) per
    unit z, axially -H³∂zΠ/(12μ̄) per unit φ.
    """
    if not fixed.any():  # no supply: nothing flows out of one
        return 0.0
    dphi, dz = grid.d_phi, grid.d_z
    h = film[:, None]
    zw = np.full(grid.n_z + 1, dz)
    zw[[0, -1]] = dz / 2.0
    total = 0.0
    for sign in (1, -1):
        nb = np.roll(fixed, -sign, axis=0)
        # derivative of Π along the direction ``sign`` out of the node
        grad = _one_sided(p, np.roll(p, -sign, axis=0), np.roll(p, -2 * sign, axis=0), dphi)
        flux = sign * omega * h / 2.0 - h**3 * grad / (12.0 * mu_bar)
        out = fixed & ~nb
        total += float(np.sum(np.maximum(flux, 0.0) * out * zw))
    nz = grid.n_z
    h3 = np.broadcast_to(h**3, p.shape)
    for sign in (1, -1):
        # Towards increasing (sign = 1) or decreasing z; the edges are film boundary nodes.
        q = p if sign == 1 else p[:, ::-1]
        f = fixed if sign == 1 else fixed[:, ::-1]
        src = f[:, : nz - 1] & ~f[:, 1:nz]
        grad = _one_sided(q[:, : nz - 1], q[:, 1:nz], q[:, 2 : nz + 1], dz)
        flux = -h3[:, : nz - 1] * grad / (12.0 * mu_bar)
        total += float(np.sum(np.maximum(flux[src], 0.0))) * dphi
        # A supply reaching the last interior row spills straight over the edge.
        last = f[:, nz - 1]
        edge_flux = h3[:, nz - 1] * q[:, nz - 1] / (12.0 * mu_bar * dz)
        total += float(np.sum(np.maximum(edge_flux[last], 0.0))) * dphi
    return total


def _parabola_peak(fm: float, f0: float, fp: float) -> tuple[float, float]:
    """Offset (in steps, |offset| < 1/2) and value of the vertex of the parabola through
    three samples of which the middle one is a strict maximum; else the middle sample."""
    if not (fm < f0 and fp < f0):
        return 0.0, f0
    curv = fm - 2.0 * f0 + fp
    return 0.5 * (fm - fp) / curv, f0 - 0.125 * (fp - fm) ** 2 / curv


def film_force(grid: Grid, p: FloatArray) -> tuple[float, float]:
    """F = -∫∫Π·(cos φ, sin φ) dφ dz, the film's force on the journal."""
    column = p.sum(axis=1) * (grid.d_phi * grid.d_z)
    return -float(np.dot(np.cos(grid.phi), column)), -float(np.dot(np.sin(grid.phi), column))


def integrate(
    grid: Grid,
    p: FloatArray,
    ruptured: BoolArray,
    fixed: BoolArray,
    film: FloatArray,
    *,
    omega: float,
    mu_bar: float,
    film_fraction: FloatArray | None = None,
) -> Integrals:
    """Integrals of the field ``p`` (edges included); see the module docstring for scales.

    Forces on the journal F = -∫∫Π·(cos φ, sin φ) dφ dz. Shear stress on the journal
    τ = θ·μ̄Ω/H + (H/2)∂Π/∂φ, on the bush θ·μ̄Ω/H - (H/2)∂Π/∂φ (Couette plus Poiseuille
    parts of the film's velocity profile; Hamrock [1], ch. 10), θ the film fraction: as
    solved for (``film_fraction``, interior rows, shape (n_phi, n_z - 1)), else from the
    streamers of :func:`streamer_fraction`.
    """
    dphi, dz = grid.d_phi, grid.d_z
    phi = grid.phi
    fx, fy = film_force(grid, p)

    theta = (
        streamer_fraction(ruptured[:, 1:-1], film, omega)
        if film_fraction is None
        else film_fraction
    )
    theta = np.concatenate([theta[:, :1], theta, theta[:, -1:]], axis=1)
    zw = np.full(grid.n_z + 1, dz)
    zw[[0, -1]] = dz / 2.0
    h = film[:, None]
    couette = mu_bar * omega / h
    dp = np.empty_like(p)  # central difference in φ, periodic
    dp[1:-1] = p[2:] - p[:-2]
    dp[0] = p[1] - p[-1]
    dp[-1] = p[0] - p[-2]
    dp /= 2.0 * dphi
    poiseuille = 0.5 * h * dp
    weights = dphi * zw[None, :]
    journal = float(np.sum((theta * couette + poiseuille) * weights))
    bush = float(np.sum((theta * couette - poiseuille) * weights))
    full_film = float(np.sum((couette + poiseuille) * weights))
    ruptured_part = float(np.sum(np.where(ruptured, theta * couette, 0.0) * weights))

    outflow_edges = (4.0 * p[:, -2] - p[:, -3]) + (4.0 * p[:, 1] - p[:, 2])
    side = float(np.sum(film**3 * outflow_edges)) * dphi / (24.0 * mu_bar * dz)
    inflow = _supply_outflow(grid, p, fixed, film, omega, mu_bar)

    i, j = np.unravel_index(int(np.argmax(p)), p.shape)
    n = grid.n_phi
    off_phi, val_phi = off_z, val_z = 0.0, p[i, j]
    if not fixed[i, j] and 0 < j < grid.n_z:  # a peak in the film, not on a supply
        off_phi, val_phi = _parabola_peak(p[(i - 1) % n, j], p[i, j], p[(i + 1) % n, j])
        off_z, val_z = _parabola_peak(p[i, j - 1], p[i, j], p[i, j + 1])
    return Integrals(
        force_x=fx,
        force_y=fy,
        journal_torque=journal,
        bush_torque=bush,
        journal_torque_full_film=full_film,
        ruptured_torque=ruptured_part,
        inflow=inflow,
        side_flow=side,
        max_pressure=float(val_phi + val_z - p[i, j]),
        max_pressure_phi=float((phi[i] + off_phi * dphi) % (2.0 * np.pi)),
        max_pressure_z=float(grid.z[j] + off_z * dz),
        film_fraction=theta,
    )
