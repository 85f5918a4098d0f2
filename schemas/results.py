"""The results of each stand's analysis, declared with units (what `/results` answers).

The wire form is ``{"stand": ..., "values": <one of the models below>, "units": {path: unit}}``
with the units of every quantity, nested paths joined by dots (``rows[].chi``).
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from schemas.quantity import quantity


class Series(BaseModel):
    """A long record reduced for display: block means over equal runs of rows."""

    x_name: str
    y_name: str
    x: list[float]
    y: list[float]
    y_min: list[float] = Field(description="smallest value in each block")
    y_max: list[float] = Field(description="largest value in each block")


# --- SMTs-2 -----------------------------------------------------------------------------


class ExperimentalWearResult(BaseModel):
    mass_loss: float = quantity(..., "kg", "Δm = m1 - m2 (2.9)")
    volume: float = quantity(..., "m^3", "V = Δm/ρ (2.10)")
    wear_depth: float = quantity(..., "m", "h = V/(π r1²) (2.11)")
    sliding_distance: float = quantity(..., "m", "L = 2π r2 M_rev (2.12)")
    intensity: float = quantity(..., "1", "I_h = h/L (2.13)")


class TheoreticalWearResult(BaseModel):
    intensity: float = quantity(..., "1", "I_h, fatigue wear (2.1)")
    contact: Literal["elastic", "plastic"] = Field(description="contact mode by (2.7)")
    fatigue_t: float = quantity(..., "1", "t used for this contact mode")
    contour_pressure: float = quantity(..., "Pa", "p_c = N/A_c (2.3)")
    nominal_area: float = quantity(..., "m^2", "A_a = 4π r2 r1 (2.5)")
    contour_area: float = quantity(..., "m^2", "A_c = π r1² (2.4)")
    eta_c: float = quantity(..., "1", "η_c = A_c/A_a")
    complex_parameter: float = quantity(..., "1", "Δ of the disc (2.6, corrected)")
    rmax_over_r: float = quantity(..., "1", "Rmax/R = Δ·b^(1/ν)")
    C: float = quantity(..., "1", "C of (2.1)")
    beta: float = quantity(..., "1", "β = 1/(1+2ν)")
    k_nu: float = quantity(..., "1", "k_ν of (2.1)")
    k_f: float = quantity(..., "1", "k_f of the contact mode")


class AdequacyResult(BaseModel):
    relative_error_percent: float = quantity(..., "%", "ΔI_h = (I_exp - I_theor)/I_exp (2.14)")
    adequate: bool = Field(description="0.4·I_theor <= I_exp <= 2.6·I_theor (2.15)")
    lower: float = quantity(..., "1", "0.4·I_theor")
    upper: float = quantity(..., "1", "2.6·I_theor")


class Smts2Results(BaseModel):
    stand: Literal["smts2"] = "smts2"
    rows: int = Field(description="rows of the friction record analysed")
    duration: float = quantity(..., "s", "time from the first to the last reading")
    revolutions: float = quantity(..., "rev", "M_rev, disc revolutions (counter difference)")
    sliding_distance: float = quantity(..., "m", "L = 2π r2 M_rev (2.12)")
    mean_load: float = quantity(..., "N", "mean load over the steady part")
    friction_steady: float = quantity(..., "1", "f (2.8), mean over the steady part")
    friction_steady_std: float = quantity(..., "1", "standard deviation of f there")
    steady_from_time: float = quantity(..., "s", "start of the steady part")
    friction: Series = Field(description="f (2.8) against time, block means")
    experimental: ExperimentalWearResult | None = None
    theoretical: TheoreticalWearResult | None = None
    adequacy: AdequacyResult | None = None
    pending: list[str] = Field(
        default_factory=list, description="what is missing for the results still empty"
    )
    notes: list[str] = Field(default_factory=list)
