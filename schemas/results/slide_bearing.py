"""The slide-bearing stand's results (lab work 3): the pressure along the angle and the axis."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from schemas.quantity import quantity


class SlideBearingRow(BaseModel):
    """One row of tables 3.1 and 3.3: a limb position."""

    limb_angle: float = quantity(..., "deg", "φ_limb")
    phi_model: float = quantity(..., "deg", "φ in the model frame (3.20)")
    pressure: float = quantity(..., "Pa", "gauge pressure at the central manometer (z = 0)")
    e_x: float = quantity(..., "m", "e_x (3.16)")
    e_y: float = quantity(..., "m", "e_y (3.16)")
    e: float = quantity(..., "m", "e (3.16)")
    chi: float = quantity(..., "1", "χ = e/h0 (3.17)")
    attitude: float = quantity(..., "deg", "ψ = atan2(e_y, e_x) - (135° - φ_limb)")
    pi_measured: float = quantity(..., "1", "Π_e (3.18)")
    pi_short: float | None = quantity(None, "1", "Π0 at z = 0, χ_mean (3.10)")
    pi_long: float | None = quantity(None, "1", "Π∞ at χ_mean (3.15)")
    pi_finite: float | None = quantity(
        None,
        "1",
        "Π of the finite bearing (3.1) with the Reynolds condition, z = 0, χ_mean, at φ_mod + φ_r",
    )
    error_short: float | None = quantity(None, "%", "(Π0 - Π_e)/Π0 (3.26)")
    error_long: float | None = quantity(None, "%", "(Π∞ - Π_e)/Π∞ (3.27)")


class AxialPoint(BaseModel):
    """One manometer of table 3.2, at the angle of the largest pressure."""

    z: float = quantity(..., "1", "z = Z/R")
    pressure: float = quantity(..., "Pa", "gauge pressure")
    pi_measured: float = quantity(..., "1", "Π_z (3.18)")
    pi_short: float | None = quantity(None, "1", "Π_m, short bearing (3.10)")
    pi_finite: float | None = quantity(None, "1", "Π of the finite bearing (3.1)")
    error: float | None = quantity(None, "%", "(Π_m - Π_z)/Π_m (3.25)")


class SlideBearingResults(BaseModel):
    stand: Literal["slide_bearing"] = "slide_bearing"
    rows: int
    load: float | None = quantity(None, "N", "load from the loader scale (16.2 N/mm)")
    temperature: float | None = quantity(None, "degC", "t = (t1 + t2)/2 (3.21)")
    viscosity: float | None = quantity(None, "Pa*s", "μ_t (3.21)")
    mu_bar: float | None = quantity(None, "1", "μ̄ = μ_t/μ0 (3.22)")
    chi_mean: float | None = quantity(None, "1", "χ_mean (3.23)")
    chi_mean_uncertainty: float | None = quantity(
        None, "1", "u(χ_mean), standard uncertainty (GUM)"
    )
    chi_mean_expanded: float | None = quantity(None, "1", "U(χ_mean) = 2u, expanded (k = 2)")
    attitude_angle: float | None = quantity(
        None, "deg", "ψ, mean over the rows, from the load line to the line of centres"
    )
    rupture_angle: float | None = quantity(
        None, "deg", "φ_r, where the finite film ruptures past the thinnest film"
    )
    half_width: float = quantity(..., "1", "a = B/(2R) (corrected E3)")
    phi_max: float | None = quantity(None, "deg", "model angle of the largest pressure")
    pressure_max: float | None = quantity(None, "Pa", "largest gauge pressure at z = 0")
    table: list[SlideBearingRow] = Field(default_factory=list)
    axial: list[AxialPoint] = Field(default_factory=list)
    pending: list[str] = Field(default_factory=list)
    notes: list[str] = Field(default_factory=list)
