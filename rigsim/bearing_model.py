"""The simulated journal bearing: where the journal runs, its friction and its pressure field.

One seam, two models, chosen by name:

- ``"finite"`` (the default): the finite-length Reynolds equation (3.1) with the Reynolds
  cavitation condition, solved by :mod:`rigserver.core.reynolds` on the simulator's own grid
  (72 x 16 nodes, about 0.1 % from the converged equilibrium at a fraction of the cost).
  The friction moment is the film's drag on the journal with the film fraction in the
  ruptured zone.
- ``"short"``: Ocvirk's short bearing (3.12) for the equilibrium (core
  :func:`~rigserver.core.bearing.short_bearing_eccentricity`, resultant = load) with two
  documented corrections, so that even this truth is not the theory a lab compares with:
  the shear in the ruptured zone (0 < φ < π) acts on the striated film fraction
  θ = h(0)/h(φ) = (1 - χ)/(1 - χ cos φ) (mass conservation of the Couette flow), so the
  shear moment is μωR1³B/h0·π[1/√(1-χ²) + (1-χ)/(1-χ²)^1.5] instead of (4.1)'s
  2π·μωR1³B/(h0√(1-χ²)); and the pressure field is Hirani's finite-length blend of the
  short (3.10) and long (3.15) solutions, Π = Π0·Π∞/(Π0 + Π∞) in the load zone, below both
  asymptotes as a finite bearing's is (its force is not re-balanced against the load: the
  equilibrium stays Ocvirk's).

Frame (both models, the manual's fig. 3.2): H = 1 - χ cos φ, thinnest at φ = 0 = 2π, the
load zone φ = π .. 2π; the attitude angle runs from the load line to the line of centres in
the direction of rotation. Journal radius R1 = R - h0 as in (4.1).

References
----------
.. [1] F. W. Ocvirk, NACA TN 2808, 1952.
.. [2] H. Hirani, K. Athre, S. Biswas, "Rapid performance evaluation of journal bearings",
   Tribology International 30 (1997) 825-834.
.. [3] H. G. Elrod, "A cavitation algorithm", J. Lubr. Technol. 103 (1981) 350-354.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rigserver.core import bearing, reynolds
from rigserver.core.errors import ModelInputError
from rigsim.errors import SettingsError

FloatArray = NDArray[np.float64]
BearingModel = Literal["short", "finite"]
MODELS: tuple[BearingModel, ...] = ("short", "finite")
DEFAULT_MODEL: BearingModel = "finite"

#: Grid of the finite-length truth: intervals in φ over 2π and in z over the width.
FINITE_GRID = (72, 16)


@dataclass(frozen=True, slots=True)
class Geometry:
    """A plain journal bearing.

    Attributes
    ----------
    radius : float
        Bearing radius R, m.
    width : float
        Bearing width B, m.
    clearance : float
        Radial clearance h0, m (< R).
    """

    radius: float
    width: float
    clearance: float

    def __post_init__(self) -> None:
        for name in ("radius", "width", "clearance"):
            if not getattr(self, name) > 0:
                raise SettingsError(f"{name} must be > 0 m, got {getattr(self, name)}")
        if self.clearance >= self.radius:
            raise SettingsError(
                f"clearance must be < radius ({self.radius} m), got {self.clearance} m"
            )

    @property
    def journal_radius(self) -> float:
        """R1 = R - h0, m."""
        return self.radius - self.clearance

    @property
    def psi(self) -> float:
        """Ψ = h0/R."""
        return self.clearance / self.radius


@dataclass(frozen=True, slots=True)
class Film:
    """The journal's steady running state under a load.

    Attributes
    ----------
    model : str
        The model that produced it.
    chi : float
        Eccentricity ratio χ = e/h0.
    attitude_angle : float
        From the load line to the line of centres, in the direction of rotation, rad.
    friction_moment : float
        The film's drag moment on the journal, N·m.
    pressure_scale : float
        μω/Ψ², Pa per unit of the dimensionless pressure Π (3.6) at μ0 = μ, ω0 = ω.
    """

    model: BearingModel
    chi: float
    attitude_angle: float
    friction_moment: float
    pressure_scale: float
    field: Callable[[FloatArray, FloatArray], FloatArray]

    @property
    def min_film_thickness_ratio(self) -> float:
        """h_min/h0 = 1 - χ."""
        return 1.0 - self.chi

    def pressure(self, *, phi: ArrayLike, z: ArrayLike) -> FloatArray:
        """Gauge pressure p - p_a, Pa, at φ (rad, manual frame) and z = Z/R."""
        ph, zz = np.broadcast_arrays(
            np.asarray(phi, dtype=np.float64), np.asarray(z, dtype=np.float64)
        )
        return np.asarray(self.pressure_scale * self.field(ph, zz), dtype=np.float64)


def film(
    *,
    model: BearingModel,
    load: float,
    omega: float,
    viscosity: float,
    geometry: Geometry,
) -> Film:
    """The steady film of ``geometry`` carrying ``load`` (N) at ω (rad/s) and μ (Pa·s).

    Raises
    ------
    SettingsError
        For an unknown model, or a load the film cannot carry (χ beyond the model's range).
    """
    if model == "short":
        return _short(load, omega, viscosity, geometry)
    if model == "finite":
        return _finite(load, omega, viscosity, geometry)
    raise SettingsError(f"bearing model must be one of {MODELS}, got {model!r}")


def refined(state: Film, *, half_width: float) -> Film:
    """The finite film's pressure field solved again at its χ on the solver's default grid.

    The equilibrium χ and ψ stay those of :data:`FINITE_GRID`; the pressures at the holes
    then match the analysis's finite solution at that χ point by point, where the coarse
    grid's rupture line is only known to a node (5°). The short model is returned as is.
    """
    if state.model != "finite":
        return state
    solution = reynolds.solve_reynolds(chi=state.chi, half_width=half_width)

    def field(phi: FloatArray, z: FloatArray) -> FloatArray:
        return solution.pressure_at(phi=phi, z=z)

    return replace(state, field=field)


def _short(load: float, omega: float, viscosity: float, g: Geometry) -> Film:
    sol = bearing.short_bearing_eccentricity(
        load=load,
        omega=omega,
        viscosity=viscosity,
        bearing_radius=g.radius,
        width=g.width,
        clearance=g.clearance,
    )
    if not sol.converged:
        raise SettingsError(f"the short-bearing film cannot carry the load: {sol.message}")
    chi = sol.chi
    force = bearing.short_bearing_load(
        chi=chi,
        omega=omega,
        viscosity=viscosity,
        bearing_radius=g.radius,
        width=g.width,
        clearance=g.clearance,
    )
    one_m = 1.0 - chi**2
    shear = (
        viscosity
        * omega
        * g.journal_radius**3
        * g.width
        / g.clearance
        * np.pi
        * (1.0 / np.sqrt(one_m) + (1.0 - chi) / one_m**1.5)
    )
    moment = -0.5 * float(force.tangential) * chi * g.clearance + float(shear)
    a = g.width / (2.0 * g.radius)

    def blended(phi: FloatArray, z: FloatArray) -> FloatArray:
        short = bearing.short_bearing_pressure(
            phi=phi, z=z, chi=chi, a=a, mu_bar=1.0, G=1.0, cavitated=True
        )
        long = bearing.long_bearing_pressure(phi=phi, chi=chi, mu_bar=1.0, G=1.0, cavitated=True)
        total = short + long
        return np.where(total > 0.0, short * long / np.where(total > 0.0, total, 1.0), 0.0)

    return Film(
        model="short",
        chi=chi,
        attitude_angle=float(force.attitude_angle),
        friction_moment=moment,
        pressure_scale=viscosity * omega / g.psi**2,
        field=blended,
    )


def _finite(load: float, omega: float, viscosity: float, g: Geometry) -> Film:
    n_phi, n_z = FINITE_GRID
    try:
        eq = reynolds.journal_equilibrium(
            load=load,
            speed=omega,
            viscosity=viscosity,
            radius=g.radius,
            radial_clearance=g.clearance,
            length=g.width,
            n_phi=n_phi,
            n_z=n_z,
        )
    except ModelInputError as exc:
        raise SettingsError(f"the finite-length film cannot carry {load:g} N: {exc}") from exc
    solution = eq.bearing.solution
    # Torques of the solver are in units of μωR⁴/h0 at μ̄ = Ω = 1.
    moment = solution.journal_torque * viscosity * omega * g.radius**4 / g.clearance

    def field(phi: FloatArray, z: FloatArray) -> FloatArray:
        return solution.pressure_at(phi=phi, z=z)

    return Film(
        model="finite",
        chi=eq.eccentricity_ratio,
        attitude_angle=float(np.radians(eq.attitude_deg)),
        friction_moment=float(moment),
        pressure_scale=viscosity * omega / g.psi**2,
        field=field,
    )
