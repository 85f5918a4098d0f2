"""The MTOS stand's results (lab work 4): the friction of a journal bearing by load step."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from schemas.quantity import quantity


class MtosStep(BaseModel):
    """One load step: a row of tables 4.4-4.6."""

    load: float = quantity(..., "N", "N")
    regime: Literal["fluid", "mixed", "boundary"] = Field(description="the experiment's oil feed")
    e_x: float = quantity(..., "m", "e_x (4.11)")
    e_y: float = quantity(..., "m", "e_y (4.11)")
    e: float = quantity(..., "m", "e (4.11)")
    chi: float = quantity(..., "1", "χ = e/h0 (4.11)")
    chi_uncertainty: float | None = quantity(None, "1", "u(χ), standard uncertainty (GUM)")
    chi_expanded: float | None = quantity(None, "1", "U(χ) = 2u, expanded (k = 2)")
    angle: float = quantity(..., "deg", "δ (fluid film) or γ (mixed, boundary) (4.12)")
    spring_force: float = quantity(..., "N", "F = k·Δl (4.13)")
    friction_moment: float = quantity(..., "N*m", "M_tr = F·l1 (4.14)")
    friction_force: float = quantity(..., "N", "F_tr = M_tr/l2 (4.15)")
    friction_measured: float = quantity(..., "1", "f_e = F_tr/N (4.16)")
    friction_measured_uncertainty: float | None = quantity(None, "1", "u(f_e), standard (GUM)")
    friction_measured_expanded: float | None = quantity(None, "1", "U(f_e) = 2u, expanded (k = 2)")
    viscosity: float = quantity(..., "Pa*s", "μ_t = (μ3 + μ4 + μ5)/3 (4.18)")
    bearing_characteristic: float = quantity(..., "1", "S1 = μ_t·ω/p̄, p̄ = N/(BD) (4.21, E9)")
    temperature_rise: dict[str, float] = quantity(..., "degC", "Δt_i = t_i - t1 (4.19, E4)")
    viscosity_at: dict[str, float] = quantity({}, "Pa*s", "μ_i = A·exp(α·t_i), i = 1..5 (4.17)")
    bearing_characteristic_inverse: float | None = quantity(
        None, "1", "S1⁻¹ = p̄/(μ_t·ω) (table 4.4)"
    )
    viscosity_ratio: float | None = quantity(
        None, "1", "μ_t/μ0, μ0 = μ at 50 °C (table 4.4, note), fluid film only"
    )
    a1_00: float | None = quantity(None, "1", "A1^00 = π/√(1 - χ²) (4.5)")
    a2_00: float | None = quantity(None, "1", "A2^00 = A1^00/(1 - χ²) (4.5)")
    a3_00: float | None = quantity(None, "1", "A3^00 = (3A2^00 - A1^00)/(2(1 - χ²)) (4.5)")
    a3_02: float | None = quantity(None, "1", "A3^02 = (A1^00 - 2A2^00 + A3^00)/χ² (4.5)")
    a3_20: float | None = quantity(None, "1", "A3^20 = A3^00 - A3^02 (4.5)")
    a3_11: float | None = quantity(None, "1", "A3^11 = -2χ/(1 - χ²)² (table 4.4)")
    v_factor: float | None = quantity(None, "1", "V = -χ·a²·(μ_t/μ0)·A3^20·ω/ω0 (4.4)")
    tangential_force: float | None = quantity(None, "N", "P_τ = P*·V (4.2)-(4.3)")
    friction_theory: float | None = quantity(None, "1", "f_T (4.10), fluid film only")
    friction_error: float | None = quantity(None, "%", "Δf = (f_e - f_T)/f_e")
    friction_finite: float | None = quantity(
        None, "1", "f of the finite bearing (3.1) at the measured χ, full-film shear as (4.1)"
    )
    load_finite: float | None = quantity(
        None, "N", "load the finite bearing carries at the measured χ (compare with N)"
    )
    h_min: float = quantity(..., "m", "h_min = h0 - e")
    film: Literal["fluid", "mixed"] = Field(
        description="h_min against h_min,cr (2.104) of the film-thickness excerpt (docs/models.md)"
    )
    film_parameter: float = quantity(..., "1", "Λ = h_min/√(Rq_journal² + Rq_bush²)")
    film_lambda: Literal["full film", "mixed", "boundary"] = Field(
        description="regime by Λ: < 1 boundary, 1-3 mixed, > 3 full film (Hamrock et al.)"
    )


class MtosResults(BaseModel):
    stand: Literal["mtos"] = "mtos"
    rows: int
    h_crit: float = quantity(
        ..., "m", "h_min,cr, sum of the five terms (2.105) of the film-thickness excerpt"
    )
    half_width: float = quantity(..., "1", "a = B/(2R) = B/D (corrected E3)")
    friction_fluid: float | None = quantity(None, "1", "mean f_e of the fluid-film steps")
    h_min_smallest: float | None = quantity(None, "m", "smallest h_min of the run")
    journal_rq: float = quantity(..., "m", "Rq of the journal used for Λ")
    bush_rq: float = quantity(..., "m", "Rq of the bush used for Λ")
    roughness_source: str = Field(
        description="where the Rq come from: the profilometer runs named, or the configuration"
    )
    regime_disagreements: list[str] = Field(
        default_factory=list,
        description="steps whose film criterion or Λ band differs from the experiment's regime",
    )
    steps: list[MtosStep] = Field(default_factory=list)
    pending: list[str] = Field(default_factory=list)
    notes: list[str] = Field(default_factory=list)
