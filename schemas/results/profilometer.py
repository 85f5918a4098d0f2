"""The profilometer's results (lab work 1): the roughness of a run-in surface."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from schemas.quantity import quantity
from schemas.results.common import IsoRoughnessResult


class BearingFitResult(BaseModel):
    method: Literal["manual", "lsq"]
    b: float = quantity(..., "1", "b of t_p = b·ε^ν (1.8)")
    nu: float = quantity(..., "1", "ν of t_p = b·ε^ν (1.8)")
    residuals: list[float] = quantity(..., "1", "t_p,e - t_p,t per level (table 1.8)")
    nu_partial: list[float] = quantity(..., "1", "ν_1,3, ν_2,5, ν_3,6 (1.16), manual method")
    b_partial: list[float] = quantity(..., "1", "b_1, b_3, b_5 (1.18), manual method")


class ProfilometerResults(BaseModel):
    stand: Literal["profilometer"] = "profilometer"
    rows: int
    base_length: float | None = quantity(None, "m", "l, length of the trace analysed")
    ra: float | None = quantity(None, "m", "Ra (1.3)")
    rq: float | None = quantity(None, "m", "Rq = ρ")
    rz: float | None = quantity(None, "m", "Rz, ten-point height (1.4)")
    rmax: float | None = quantity(None, "m", "Rmax, peak line to valley line")
    sm: float | None = quantity(None, "m", "Sm, mean spacing of profile elements")
    asperity_radius: float | None = quantity(None, "m", "R = √(π/2)/ρ2 (1.1, corrected E5)")
    ra_error: float | None = quantity(None, "m", "instrument error of Ra (1.14)")
    rz_error: float | None = quantity(None, "m", "instrument error of Rz (1.14)")
    rmax_error: float | None = quantity(None, "m", "instrument error of Rmax (1.14)")
    sm_error: float | None = quantity(None, "m", "instrument error of Sm (1.14)")
    ra_uncertainty: float | None = quantity(None, "m", "u(Ra) = ΔRa/√3 (1.14, GUM type B)")
    ra_expanded: float | None = quantity(None, "m", "U(Ra) = 2u, expanded (k = 2)")
    rz_uncertainty: float | None = quantity(None, "m", "u(Rz) = ΔRz/√3 (1.14, GUM type B)")
    rz_expanded: float | None = quantity(None, "m", "U(Rz) = 2u, expanded (k = 2)")
    levels: list[float] = quantity([], "m", "p_i, depth below the peak line (table 1.6)")
    eps: list[float] = quantity([], "1", "ε = p/Rmax (1.7)")
    tp: list[float] = quantity([], "1", "t_p = η_p/l (1.6)")
    bearing_lengths: list[float] = quantity([], "m", "η_p = t_p·l, bearing length (table 1.6)")
    outside_subrange: list[str] = Field(
        default_factory=list,
        description="parameters outside the ranges of the subrange of the base length (1.14)",
    )
    rmax_difference: float | None = quantity(
        None, "%", "δ = (Rmax1 - Rmax2)/Rmax1: profilometer against profilogram (1.20)"
    )
    rz_difference: float | None = quantity(
        None, "%", "δ_Rz = (Rz1 - Rz2)/Rz1: profilometer against profilogram (1.20, E10)"
    )
    ra_difference: float | None = quantity(
        None, "%", "δ_Ra = (Ra1 - Ra2)/Ra1: profilometer against profilogram (1.20, E10)"
    )
    rz_peaks: list[float] = quantity(
        [], "m", "y_p,i: the five highest peaks above the mean line behind Rz (1.4)"
    )
    rz_valleys: list[float] = quantity(
        [], "m", "y_v,i: the five deepest valleys below the mean line behind Rz (1.4)"
    )
    fit_manual: BearingFitResult | None = None
    fit_lsq: BearingFitResult | None = None
    complex_parameter: float | None = quantity(None, "1", "Δ = Rmax/(R·b^(1/ν)) (1.9)")
    ra_from_complex: float | None = quantity(None, "m", "Ra = 4.3·Δ^(1/2) μm (1.10)")
    complex_parameter_equilibrium: float | None = quantity(
        None, "1", "Δ_T for the configured material and load (1.11)"
    )
    iso: IsoRoughnessResult | None = Field(
        default=None, description="ISO 21920-2 parameters of the filtered roughness profile"
    )
    pending: list[str] = Field(default_factory=list)
    notes: list[str] = Field(default_factory=list)
