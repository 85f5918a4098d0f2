"""The SMTs-2's results (lab work 2): friction, the experimental and the theoretical wear."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from schemas.quantity import quantity
from schemas.results.common import IsoRoughnessResult, Series


class ExperimentalWearResult(BaseModel):
    mass_loss: float = quantity(..., "kg", "Δm = m1 - m2 (2.9)")
    volume: float = quantity(..., "m^3", "V = Δm/ρ (2.10)")
    wear_depth: float = quantity(..., "m", "h = V/(π r1²) (2.11)")
    sliding_distance: float = quantity(..., "m", "L = 2π r2 M_rev (2.12)")
    intensity: float = quantity(..., "1", "I_h = h/L (2.13)")
    specific_wear_rate: float = quantity(
        ..., "m^2/N", "k = V/(F·L), the pin's specific wear rate (ASTM G99), m³/(N·m)"
    )
    intensity_uncertainty: float | None = quantity(None, "1", "u(I_h), standard uncertainty (GUM)")
    intensity_expanded: float | None = quantity(None, "1", "U(I_h) = 2u, expanded (k = 2)")
    specific_wear_rate_uncertainty: float | None = quantity(
        None, "m^2/N", "u(k), standard uncertainty"
    )
    specific_wear_rate_expanded: float | None = quantity(
        None, "m^2/N", "U(k) = 2u, expanded (k = 2)"
    )


class DiscWearResult(BaseModel):
    """The disc's wear from a profile across its wear track (ASTM G99)."""

    profile_run: str = Field(description="the profilometer run traced across the track")
    track_area: float = quantity(..., "m^2", "cross-section area of the wear track")
    volume: float = quantity(..., "m^3", "V = area × 2π r2, the disc's worn volume")
    specific_wear_rate: float = quantity(..., "m^2/N", "k = V/(F·L) of the disc, m³/(N·m)")
    iso: IsoRoughnessResult | None = Field(
        default=None, description="ISO roughness across the track (its form filtered out)"
    )


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


class WearValidityResult(BaseModel):
    """Whether (2.1) applies to the run: its own applicability figures (docs/validity.md)."""

    within_range: bool = Field(description="the branch chosen by (2.7) applies")
    reasons: list[str] = Field(default_factory=list, description="why not, if not")
    approach: float = quantity(..., "1", "ε = a/Rmax, relative approach at p_c")
    real_area_ratio: float = quantity(..., "1", "η_r = A_r/A_c = b·ε^ν/2")
    real_contact_pressure: float = quantity(..., "Pa", "p_r = p_c/η_r, elastic asperities")
    hardness: float = quantity(..., "Pa", "HB of the pin, against p_r")
    asperity_stress: float = quantity(..., "Pa", "σ = k_f^y·p_r")
    fatigue_strength: float = quantity(..., "Pa", "σ0 of n = (σ0/σ)^t (σ_B in (2.1))")
    cycles_to_failure: float = quantity(..., "1", "n = (σ0/σ)^t, needs n ≫ 1")
    plastic_k_f: float | None = quantity(None, "1", "k_f^n; empty when σ_T <= 2f·HB")


class SensitivityPoint(BaseModel):
    """I_h of (2.1) at one t and σ0/σ_B, the run's other data unchanged."""

    fatigue_t: float = quantity(..., "1", "t")
    strength_ratio: float = quantity(..., "1", "σ0/σ_B")
    intensity: float | None = quantity(None, "1", "I_h (2.1)")
    cycles_to_failure: float | None = quantity(None, "1", "n = (σ0/σ)^t")


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
    friction_steady_uncertainty: float | None = quantity(
        None, "1", "u(f): batch means of the record and the sensors' limits (GUM)"
    )
    friction_steady_expanded: float | None = quantity(None, "1", "U(f) = 2u, expanded (k = 2)")
    steady_from_time: float = quantity(..., "s", "start of the steady part")
    friction: Series = Field(description="f (2.8) against time, block means")
    experimental: ExperimentalWearResult | None = None
    disc_wear: DiscWearResult | None = None
    theoretical: TheoreticalWearResult | None = None
    adequacy: AdequacyResult | None = None
    validity: WearValidityResult | None = None
    verdict: str | None = Field(
        default=None,
        description="(2.15)'s verdict, or 'theory outside its range' with the reason",
    )
    sensitivity: list[SensitivityPoint] = Field(
        default_factory=list, description="I_h against t (table 2.1's range) and σ0/σ_B"
    )
    pending: list[str] = Field(
        default_factory=list, description="what is missing for the results still empty"
    )
    notes: list[str] = Field(default_factory=list)
