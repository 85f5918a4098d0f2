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


# --- roughness as the standards define it (ISO 21920-2, ISO 16610-21) --------------------


class IsoRoughnessResult(BaseModel):
    """The ISO 21920-2 parameters of a profile's roughness profile (ISO 16610-21 Gaussian
    filter), beside the manual's; ``docs/roughness.md`` compares the two methods."""

    lambda_c: float = quantity(..., "m", "λc, cut-off of the Gaussian roughness filter")
    lambda_s: float = quantity(..., "m", "λs, cut-off of the short-wave filter (0: none)")
    lambda_c_source: str = Field(description="how λc was chosen: given, or by a table")
    ends: str = Field(description="how the filter's end effects were handled")
    sections: int = quantity(..., "1", "sections of length λc in the evaluation length")
    evaluation_length: float = quantity(..., "m", "evaluation length")
    parts: int = quantity(
        1, "1", "parts of the trace between its gaps analysed (docs/roughness.md)"
    )
    ra: float = quantity(..., "m", "Ra, arithmetic mean height (ISO 4287 4.2.1)")
    rq: float = quantity(..., "m", "Rq, root-mean-square height (ISO 4287 4.2.2)")
    rsk: float = quantity(..., "1", "Rsk, skewness (ISO 4287 4.2.3)")
    rku: float = quantity(..., "1", "Rku, kurtosis (ISO 4287 4.2.4)")
    rp: float = quantity(..., "m", "Rp, maximum peak height, mean over the sections")
    rv: float = quantity(..., "m", "Rv, maximum pit depth, mean over the sections")
    rz: float = quantity(..., "m", "Rz, maximum height, mean over the sections")
    rt: float = quantity(..., "m", "Rt, total height over the evaluation length")
    rsm: float | None = quantity(None, "m", "RSm, mean width of the profile elements")
    rdq: float = quantity(..., "1", "RΔq, root-mean-square slope")
    rk: float = quantity(..., "m", "Rk, core height (ISO 13565-2)")
    rpk: float = quantity(..., "m", "Rpk, reduced peak height (ISO 13565-2)")
    rvk: float = quantity(..., "m", "Rvk, reduced valley depth (ISO 13565-2)")
    mr1: float = quantity(..., "%", "Mr1, material ratio at the top of the core")
    mr2: float = quantity(..., "%", "Mr2, material ratio at the bottom of the core")


# --- SMTs-2 -----------------------------------------------------------------------------


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


# --- slide-bearing stand ------------------------------------------------------------------


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


# --- MTOS stand ---------------------------------------------------------------------------


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


# --- profilometer -------------------------------------------------------------------------


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


# --- commercial tribometers: pin- or ball-on-disc, reciprocating ---------------------------


class WearEstimate(BaseModel):
    """One specimen's worn volume by one method and its specific wear rate k = V/(F·L)."""

    volume: float = quantity(..., "m^3", "V, the worn volume")
    volume_uncertainty: float | None = quantity(None, "m^3", "u(V), standard uncertainty")
    specific_wear_rate: float = quantity(..., "m^2/N", "k = V/(F·L), m³/(N·m)")
    specific_wear_rate_uncertainty: float | None = quantity(
        None, "m^2/N", "u(k), standard uncertainty (GUM)"
    )
    specific_wear_rate_expanded: float | None = quantity(
        None, "m^2/N", "U(k) = 2u, expanded (k = 2)"
    )


class TrackWear(WearEstimate):
    """The disc's (flat's) wear from profiles across its track (ASTM G99 9.2.2, G133)."""

    traces: int = Field(description="profiles across the track averaged")
    track_area: float = quantity(..., "m^2", "A, mean cross-section area of the track")
    track_area_std: float | None = quantity(None, "m^2", "s(A) over the traces")
    iso: IsoRoughnessResult | None = Field(
        default=None, description="ISO roughness of the first trace (the track's form filtered out)"
    )


class ScarWear(WearEstimate):
    """The ball's wear from its scar (a spherical cap), or a flat pin's from its height loss."""

    scar_diameter: float | None = quantity(None, "m", "d, the ball's wear scar diameter")
    height_loss: float | None = quantity(None, "m", "Δh, the flat pin's height loss")


class MassWear(WearEstimate):
    """A specimen's wear from its weighings: V = Δm/ρ."""

    mass_loss: float = quantity(..., "kg", "Δm = m_before - m_after")
    density: float = quantity(..., "kg/m^3", "ρ used")


class HertzResult(BaseModel):
    """The initial contact of the ball on the flat (Hertz)."""

    modulus: float = quantity(..., "Pa", "E*, contact modulus of the two materials")
    contact_radius: float = quantity(..., "m", "a = (3FR/(4E*))^(1/3)")
    max_pressure: float = quantity(..., "Pa", "p0 = (6FE*²/(π³R²))^(1/3)")
    mean_pressure: float = quantity(..., "Pa", "p_m = F/(πa²)")


class LapMapResult(BaseModel):
    """μ against the lap and the angular position on the disc (cell means)."""

    lap: list[float] = quantity(..., "1", "the middle lap of each row")
    angle: list[float] = quantity(..., "deg", "the middle of each angular bin")
    values: list[list[float | None]] = quantity(..., "1", "mean μ per cell; null: no reading")


class StrokeBlock(BaseModel):
    """Forward and backward strokes, averaged over a block of cycles."""

    cycle: float = quantity(..., "1", "middle cycle of the block")
    forward: float | None = quantity(None, "1", "mean μ of the forward strokes")
    backward: float | None = quantity(None, "1", "mean |μ| of the backward strokes")


class FrictionLoop(BaseModel):
    """One cycle's friction against the position: a friction loop."""

    cycle: int = Field(description="the cycle drawn")
    position: list[float] = quantity(..., "m", "x along the stroke")
    friction: list[float] = quantity(..., "1", "μ, signed by the direction of sliding")


class TribometerStep(BaseModel):
    """One step of a test's recipe (a speed or load sweep), in the record's order."""

    step: int = quantity(..., "1", "the step's number, as the record gives it")
    sliding_speed: float | None = quantity(
        None, "m/s", "v, mean sliding speed: recorded, or 2πRn/60 from the rotational speed"
    )
    track_radius: float | None = quantity(None, "m", "R, mean track radius of the step")
    normal_load: float = quantity(..., "N", "F, mean normal load of the step")
    duration: float = quantity(..., "s", "time from the step's first to its last reading")
    distance: float = quantity(..., "m", "sliding distance of the step")
    friction_mean: float = quantity(..., "1", "μ, mean over the step")
    friction_steady: float | None = quantity(
        None, "1", "μ, mean over the step's steady part; null when it did not settle"
    )


class TribometerResults(BaseModel):
    """What both tribometers report (ASTM G99, G133, ISO 20808)."""

    rows: int = Field(description="rows of the friction record analysed")
    duration: float = quantity(..., "s", "time from the first to the last reading")
    sliding_distance: float = quantity(..., "m", "L, sliding distance of the record")
    laps: float = quantity(..., "1", "laps (cycles) run")
    mean_load: float = quantity(..., "N", "F, mean normal load")
    friction_mean: float = quantity(..., "1", "μ, mean over the whole record")
    friction_static: float = quantity(..., "1", "μ_s, the peak μ at the start (static)")
    running_in_distance: float | None = quantity(
        ...,
        "m",
        "sliding distance of the running-in: where μ's lap means settle within ±5 % of the "
        "steady mean; null when the friction did not settle",
    )
    running_in_laps: float | None = quantity(..., "1", "laps (cycles) of the running-in")
    change_points: int = Field(description="changes in the mean found by PELT")
    friction_steady: float | None = quantity(
        ..., "1", "μ, mean over the steady part; null when the friction did not settle"
    )
    friction_steady_std: float | None = quantity(..., "1", "standard deviation of μ there")
    friction_steady_uncertainty: float | None = quantity(
        None, "1", "u(μ): batch means of the steady part and the sensors' limits (GUM)"
    )
    friction_steady_expanded: float | None = quantity(None, "1", "U(μ) = 2u, expanded (k = 2)")
    temperature_mean: float | None = quantity(None, "degC", "mean temperature of the record")
    wear_depth_change: float | None = quantity(
        None, "m", "last minus first reading of the displacement sensor"
    )
    hertz: HertzResult | None = None
    nominal_pressure: float | None = quantity(None, "Pa", "F/(πD²/4) of a flat pin")
    disc_track: TrackWear | None = None
    disc_mass: MassWear | None = None
    pin_scar: ScarWear | None = None
    pin_mass: MassWear | None = None
    disc_mass_below: float | None = quantity(
        None,
        "kg",
        "the balance's resolution, when the disc's mass changed by no more: no wear by mass",
    )
    pin_mass_below: float | None = quantity(
        None,
        "kg",
        "the balance's resolution, when the pin's mass changed by no more: no wear by mass",
    )
    friction: Series = Field(description="μ against the sliding distance, block means")
    steps: list[TribometerStep] = Field(
        default_factory=list, description="the recipe's steps in order (a record with `step`)"
    )
    pending: list[str] = Field(default_factory=list)
    notes: list[str] = Field(default_factory=list)


class PinOnDiscResults(TribometerResults):
    stand: Literal["pin_on_disc"] = "pin_on_disc"
    lap_amplitude: float | None = quantity(
        None, "1", "amplitude of μ's once-per-lap part in the steady state"
    )
    friction_map: LapMapResult | None = None


class ReciprocatingResults(TribometerResults):
    stand: Literal["reciprocating"] = "reciprocating"
    friction_forward: float | None = quantity(None, "1", "mean μ of the steady forward strokes")
    friction_backward: float | None = quantity(None, "1", "mean |μ| of the steady backward strokes")
    strokes: list[StrokeBlock] = Field(default_factory=list)
    loops: list[FrictionLoop] = Field(default_factory=list)
