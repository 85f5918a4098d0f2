"""How people read the results: a label, a display unit and digits for every result.

Declared apart from the code that computes the results (as openHTF declares its
measurements): one table per stand, keyed by the result's path in the results payload
(``"ra"``, ``"experimental.intensity"``, ``"steps[].chi"``), in the order the report
prints them. SI stays the unit of storage and of the JSON API; the label says how a page,
a report, a CSV or a console shows the value: in the manual's unit (µm for roughness, film
thickness, clearance and displacements; mg for masses; mm³ for wear volume), rounded to
its significant digits, and 0 below its resolution (no ``e_x = 2.7·10⁻²⁰ m``).

The English words are the message ids of the gettext catalogs
(``rigserver/locale/<lang>/LC_MESSAGES/messages.po``): a label's Russian lives there.
A new result gets one line in its stand's table; ``tests/schemas/test_labels.py`` fails
while any result the pipelines produce, or any channel, has no label or no translation.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum

from schemas.messages import N_
from schemas.units import UNITS, UnitSymbol


class Part(StrEnum):
    """The part of the report a result belongs to."""

    MEASURED = "measured"
    THEORY = "theory"
    COMPARISON = "comparison"


PARTS: dict[Part, str] = {
    Part.MEASURED: N_("Results of the measurements"),
    Part.THEORY: N_("Theory"),
    Part.COMPARISON: N_("Theory against experiment"),
}


@dataclass(frozen=True, slots=True)
class Label:
    """A result as people read it.

    ``text`` is the English name (a message id), ``symbol`` the manual's symbol in the
    TeX-like syntax of the reports (``"I_{h,exp}"``), ``equation`` its number in the manual
    (``"2.13"``) or a correction (``"E3"``); ``unit`` the display unit; ``digits`` the
    significant digits shown; ``resolution`` (display unit) the smallest magnitude that is
    not rounding noise; ``count`` a number of things (cycles, rows), printed whole
    (:mod:`schemas.digits`).
    """

    text: str
    symbol: str = ""
    equation: str = ""
    unit: UnitSymbol = "1"
    digits: int = 4
    resolution: float = 0.0
    part: Part = Part.MEASURED
    count: bool = False

    def displayed(self, value: float, stored: str) -> float:
        """``value`` (stored in ``stored``) in the display unit, to full precision."""
        if stored == self.unit:
            return value
        have, want = UNITS[stored], UNITS[self.unit]
        if have.si != want.si:
            raise ValueError(f"{stored} cannot be shown in {self.unit}")
        return value * (have.factor / want.factor)

    def shown(self, value: float, stored: str) -> float:
        """``value`` (stored in ``stored``) in the display unit, rounded to the label's
        digits, 0 below its resolution."""
        return round_to(self.displayed(value, stored), self.digits, self.resolution)

    def noiseless(self, value: float, stored: str) -> float:
        """``value`` (stored in ``stored``) in the display unit, 0 below the label's
        resolution (rounding noise: ``e_x = 2.7·10⁻²⁰ m`` is 0), else to full precision."""
        shown_as = self.displayed(value, stored)
        return 0.0 if abs(shown_as) < self.resolution else shown_as


def round_to(value: float, digits: int, resolution: float = 0.0) -> float:
    """``value`` to ``digits`` significant digits; 0 if ``|value| < resolution``."""
    if not math.isfinite(value) or value == 0 or abs(value) < resolution:
        return 0.0 if math.isfinite(value) else value
    return float(f"{value:.{digits}g}")


_MEASURED, _THEORY, _COMPARISON = Part.MEASURED, Part.THEORY, Part.COMPARISON
_NOISE_UM = 1e-3  # µm: below a nanometre is the arithmetic's noise, not a displacement
_NOISE_PI = 1e-4  # dimensionless pressures and eccentricity ratios

#: How λc of an ISO roughness result was chosen, in words (the values of ``lambda_c_source``).
ISO_LAMBDA_C_SOURCE = {
    "given": N_("given in the configuration"),
    "ra": N_("by Ra, table of ISO 21920-3"),
    "rz": N_("by Rz, table of ISO 21920-3"),
    "rsm": N_("by RSm, table of ISO 21920-3"),
    "instrument": N_("the instrument's, as its file states"),
}

#: How the filter's end effects were handled, in words (the values of ``ends``).
ISO_ENDS = {
    "discarded": N_("λc/2 discarded at each end"),
    "corrected": N_("kept, corrected by renormalised weights (ISO 16610-28)"),
    "instrument": N_(
        "none: the instrument's roughness profile, not filtered again, evaluated whole, the "
        "parameters averaged over its sampling lengths (ISO 4287, ISO 4288)"
    ),
}

#: The ISO analysis' remarks (rigserver.core.iso_roughness.REMARKS) as notes of the results.
ISO_REMARKS = {
    "resampled": N_(
        "ISO roughness: the trace is not uniformly sampled; it was interpolated onto its "
        "median step"
    ),
    "no_rsm": N_("ISO roughness: λc not chosen by the RSm table, the profile has no RSm"),
    "capped": N_(
        "ISO roughness: the table's λc is longer than the trace; the longest λc it holds is used"
    ),
    "unsettled": N_(
        "ISO roughness: the choice of λc by the table does not settle; the last one is kept"
    ),
    "short": N_(
        "ISO roughness: the trace is shorter than 2λc, so its ends are kept (corrected by "
        "renormalised weights, ISO 16610-28) instead of discarded"
    ),
    "few_sections": N_(
        "ISO roughness: fewer sections of λc than the standard's five (a trace of 6λc gives five)"
    ),
    "coarse_step": N_("ISO roughness: the sampling step is longer than λs/5 (ISO 3274)"),
    "parts": N_(
        "ISO roughness: the trace has gaps (its resampling onto its median step would hold more "
        "than four times its points); it was analysed in its parts between them, each on its "
        "own grid, and the parameters taken over their evaluation lengths together"
    ),
}


def _iso(prefix: str) -> dict[str, Label]:
    """The labels of an ISO 21920-2 roughness result (:class:`schemas.results.IsoRoughnessResult`)
    under ``prefix`` (``"iso."``, ``"disc_wear.iso."``)."""
    iso = "ISO 21920-2"
    found = {
        "lambda_c": Label(N_("cut-off λc of the roughness filter"), "λ_c", "ISO 16610-21", "mm"),
        "lambda_s": Label(N_("cut-off λs of the short-wave filter"), "λ_s", "ISO 16610-21", "um"),
        "lambda_c_source": Label(N_("how λc was chosen")),
        "ends": Label(N_("end effects of the filter")),
        "sections": Label(
            N_("sections in the evaluation length"), "n_{sc}", "ISO 21920-3", digits=9, count=True
        ),
        "evaluation_length": Label(N_("evaluation length"), "l_e", "ISO 21920-3", "mm"),
        "parts": Label(
            N_("parts of the trace between its gaps analysed"), "N_p", digits=9, count=True
        ),
        "ra": Label(
            N_("arithmetic mean height of the roughness profile"), "R_a^{ISO}", iso, "um", 3
        ),
        "rq": Label(
            N_("root-mean-square height of the roughness profile"), "R_q^{ISO}", iso, "um", 3
        ),
        "rsk": Label(N_("skewness of the roughness profile"), "R_sk^{ISO}", iso, digits=3),
        "rku": Label(N_("kurtosis of the roughness profile"), "R_ku^{ISO}", iso, digits=3),
        "rp": Label(N_("maximum peak height, mean over the sections"), "R_p^{ISO}", iso, "um", 3),
        "rv": Label(N_("maximum pit depth, mean over the sections"), "R_v^{ISO}", iso, "um", 3),
        "rz": Label(N_("maximum height, mean over the sections"), "R_z^{ISO}", iso, "um", 3),
        "rt": Label(N_("total height of the roughness profile"), "R_t^{ISO}", iso, "um", 3),
        "rsm": Label(N_("mean width of the profile elements"), "R_{Sm}^{ISO}", iso, "mm", 3),
        "rdq": Label(N_("root-mean-square slope"), "R_{Δq}^{ISO}", iso, digits=3),
        "rk": Label(N_("core height"), "R_k", "ISO 13565-2", "um", 3),
        "rpk": Label(N_("reduced peak height"), "R_{pk}", "ISO 13565-2", "um", 3),
        "rvk": Label(N_("reduced valley depth"), "R_{vk}", "ISO 13565-2", "um", 3),
        "mr1": Label(N_("material ratio at the top of the core"), "M_{r1}", "ISO 13565-2", "%", 3),
        "mr2": Label(
            N_("material ratio at the bottom of the core"), "M_{r2}", "ISO 13565-2", "%", 3
        ),
    }
    return {prefix + name: label for name, label in found.items()}


SMTS2: dict[str, Label] = {
    "rows": Label(N_("rows analysed"), digits=9, count=True),
    "duration": Label(N_("duration of the record"), "τ", unit="s"),
    "revolutions": Label(N_("disc revolutions"), "M_rev", unit="rev"),
    "sliding_distance": Label(N_("sliding distance"), "L", "2.12", "m"),
    "mean_load": Label(N_("mean load, steady part"), "N", unit="N"),
    "friction_steady": Label(N_("friction coefficient, steady part"), "f", "2.8"),
    "friction_steady_uncertainty": Label(
        N_("standard uncertainty of the friction coefficient"), "u(f)", "GUM"
    ),
    "friction_steady_expanded": Label(
        N_("expanded uncertainty of the friction coefficient (k = 2)"), "U(f)", "GUM"
    ),
    "friction_steady_std": Label(N_("standard deviation of the friction coefficient"), "σ_f"),
    "steady_from_time": Label(N_("steady part from"), "t_s", unit="s"),
    "experimental.mass_loss": Label(N_("mass loss of the pin"), "Δm", "2.9", "mg"),
    "experimental.volume": Label(N_("worn volume"), "V", "2.10", "mm^3"),
    "experimental.wear_depth": Label(N_("linear wear"), "h", "2.11", "um"),
    "experimental.sliding_distance": Label(N_("sliding distance"), "L", "2.12", "m"),
    "experimental.intensity": Label(N_("experimental wear intensity"), "I_{h,exp}", "2.13"),
    "experimental.intensity_uncertainty": Label(
        N_("standard uncertainty of the wear intensity"), "u(I_{h,exp})", "GUM"
    ),
    "experimental.intensity_expanded": Label(
        N_("expanded uncertainty of the wear intensity (k = 2)"), "U(I_{h,exp})", "GUM"
    ),
    "experimental.specific_wear_rate": Label(
        N_("specific wear rate of the pin, V/(F·L)"), "k", "ASTM G99", "mm^3/(N*m)"
    ),
    "experimental.specific_wear_rate_uncertainty": Label(
        N_("standard uncertainty of the specific wear rate"), "u(k)", "GUM", "mm^3/(N*m)"
    ),
    "experimental.specific_wear_rate_expanded": Label(
        N_("expanded uncertainty of the specific wear rate (k = 2)"), "U(k)", "GUM", "mm^3/(N*m)"
    ),
    "disc_wear.profile_run": Label(N_("profilometer run across the disc's track")),
    "disc_wear.track_area": Label(
        N_("cross-section area of the wear track"), "A", "ASTM G99", "mm^2"
    ),
    "disc_wear.volume": Label(N_("worn volume of the disc"), "V_2", "ASTM G99", "mm^3"),
    "disc_wear.specific_wear_rate": Label(
        N_("specific wear rate of the disc"), "k_2", "ASTM G99", "mm^3/(N*m)"
    ),
    **_iso("disc_wear.iso."),
    "theoretical.contact": Label(N_("contact mode"), "", "2.7", part=_THEORY),
    "theoretical.fatigue_t": Label(N_("fatigue parameter"), "t", "2.1", part=_THEORY),
    "theoretical.contour_pressure": Label(
        N_("contour pressure"), "p_c", "2.3", "MPa", part=_THEORY
    ),
    "theoretical.nominal_area": Label(N_("nominal area"), "A_a", "2.5", "mm^2", part=_THEORY),
    "theoretical.contour_area": Label(N_("contour area"), "A_c", "2.4", "mm^2", part=_THEORY),
    "theoretical.eta_c": Label(N_("ratio of the contour to the nominal area"), "η_c", part=_THEORY),
    "theoretical.complex_parameter": Label(
        N_("complex roughness parameter of the disc"), "Δ", "2.6, E2", part=_THEORY
    ),
    "theoretical.rmax_over_r": Label(
        N_("ratio of the peak height to the radius"), "R_max/R", part=_THEORY
    ),
    "theoretical.C": Label(N_("coefficient C"), "C", "2.1", part=_THEORY),
    "theoretical.beta": Label(N_("exponent β = 1/(1 + 2ν)"), "β", "2.1", part=_THEORY),
    "theoretical.k_nu": Label(N_("coefficient k_ν"), "k_ν", "2.1", part=_THEORY),
    "theoretical.k_f": Label(N_("coefficient of the contact mode"), "k_f", "2.1", part=_THEORY),
    "theoretical.intensity": Label(
        N_("theoretical wear intensity"), "I_{h,th}", "2.1", part=_THEORY
    ),
    "validity.approach": Label(N_("relative approach at the contour pressure"), "ε", part=_THEORY),
    "validity.real_area_ratio": Label(
        N_("real contact area over the contour area"), "η_r", part=_THEORY
    ),
    "validity.real_contact_pressure": Label(
        N_("real-contact pressure at the asperities"), "p_r", unit="MPa", part=_THEORY
    ),
    "validity.hardness": Label(N_("hardness of the pin"), "HB", unit="MPa", part=_THEORY),
    "validity.asperity_stress": Label(N_("stress at an asperity"), "σ", unit="MPa", part=_THEORY),
    "validity.fatigue_strength": Label(
        N_("fatigue strength of the pin"), "σ_0", unit="MPa", part=_THEORY
    ),
    "validity.cycles_to_failure": Label(N_("cycles to failure per asperity"), "n", part=_THEORY),
    "validity.plastic_k_f": Label(
        N_("coefficient of the plastic contact"), "k_f^n", "2.1", part=_THEORY
    ),
    "sensitivity[].fatigue_t": Label(N_("fatigue parameter"), "t", "2.1", part=_THEORY),
    "sensitivity[].strength_ratio": Label(
        N_("ratio of the fatigue strength to the tensile strength"), "σ_0/σ_B", part=_THEORY
    ),
    "sensitivity[].intensity": Label(
        N_("theoretical wear intensity"), "I_{h,th}", "2.1", part=_THEORY
    ),
    "sensitivity[].cycles_to_failure": Label(
        N_("cycles to failure per asperity"), "n", part=_THEORY
    ),
    "adequacy.relative_error_percent": Label(
        N_("relative difference"), "ΔI_h", "2.14", "%", 3, part=_COMPARISON
    ),
    "adequacy.lower": Label(N_("lower bound 0.4·I_{h,th}"), "", "2.15", part=_COMPARISON),
    "adequacy.upper": Label(N_("upper bound 2.6·I_{h,th}"), "", "2.15", part=_COMPARISON),
    "adequacy.adequate": Label(N_("model adequate"), "", "2.15", part=_COMPARISON),
    "validity.within_range": Label(N_("theory within its range"), part=_COMPARISON),
    "validity.reasons": Label(N_("why the theory is outside its range"), part=_COMPARISON),
    "verdict": Label(N_("verdict on the wear theory"), part=_COMPARISON),
}

SLIDE_BEARING: dict[str, Label] = {
    "rows": Label(N_("rows of table 3.1"), digits=9, count=True),
    "load": Label(N_("load from the loader scale"), "N", unit="N"),
    "temperature": Label(N_("mean oil temperature"), "t", "3.21", "degC", 3),
    "viscosity": Label(N_("oil viscosity"), "μ_t", "3.21", "Pa*s"),
    "mu_bar": Label(N_("dimensionless viscosity"), "μ̄", "3.22"),
    "chi_mean": Label(N_("mean eccentricity ratio"), "χ_mean", "3.23", resolution=_NOISE_PI),
    "chi_mean_uncertainty": Label(
        N_("standard uncertainty of the mean eccentricity ratio"), "u(χ_mean)", "GUM"
    ),
    "chi_mean_expanded": Label(
        N_("expanded uncertainty of the mean eccentricity ratio (k = 2)"), "U(χ_mean)", "GUM"
    ),
    "attitude_angle": Label(
        N_("attitude angle, from the load line to the line of centres"), "ψ", unit="deg"
    ),
    "rupture_angle": Label(
        N_("rupture angle of the finite film past the thinnest film"),
        "φ_r",
        unit="deg",
        part=_THEORY,
    ),
    "half_width": Label(N_("relative half-width"), "a", "3.24, E3"),
    "phi_max": Label(N_("angle of the largest pressure"), "φ_pmax", unit="deg"),
    "pressure_max": Label(N_("largest pressure"), "p_max", unit="at"),
    "table[].limb_angle": Label(N_("limb angle"), "φ_limb", unit="deg"),
    "table[].phi_model": Label(N_("angle in the model frame"), "φ", "3.20", "deg"),
    "table[].pressure": Label(N_("pressure at z = 0"), "p", unit="at", resolution=1e-4),
    "table[].e_x": Label(N_("displacement of the journal along x"), "e_x", "3.16", "um", 4, 1e-3),
    "table[].e_y": Label(N_("displacement of the journal along y"), "e_y", "3.16", "um", 4, 1e-3),
    "table[].e": Label(N_("eccentricity"), "e", "3.16", "um", 4, _NOISE_UM),
    "table[].chi": Label(N_("eccentricity ratio"), "χ", "3.17", resolution=_NOISE_PI),
    "table[].pi_measured": Label(
        N_("measured dimensionless pressure"), "Π_e", "3.18", resolution=_NOISE_PI
    ),
    "table[].pi_short": Label(
        N_("short bearing"), "Π_0", "3.10", resolution=_NOISE_PI, part=_THEORY
    ),
    "table[].pi_long": Label(N_("long bearing"), "Π_∞", "3.15", resolution=_NOISE_PI, part=_THEORY),
    "table[].pi_finite": Label(
        N_("finite bearing"), "Π", "3.1", resolution=_NOISE_PI, part=_THEORY
    ),
    "table[].error_short": Label(
        N_("difference from the short bearing"), "ΔΠ_0", "3.26", "%", 3, 0.01, _COMPARISON
    ),
    "table[].error_long": Label(
        N_("difference from the long bearing"), "ΔΠ_∞", "3.27", "%", 3, 0.01, _COMPARISON
    ),
    "axial[].z": Label(N_("axial coordinate"), "z", "", resolution=_NOISE_PI),
    "axial[].pressure": Label(N_("pressure"), "p", unit="at", resolution=1e-4),
    "axial[].pi_measured": Label(
        N_("measured dimensionless pressure"), "Π_z", "3.18", resolution=_NOISE_PI
    ),
    "axial[].pi_short": Label(
        N_("short bearing"), "Π_m", "3.10", resolution=_NOISE_PI, part=_THEORY
    ),
    "axial[].pi_finite": Label(
        N_("finite bearing"), "Π", "3.1", resolution=_NOISE_PI, part=_THEORY
    ),
    "axial[].error": Label(
        N_("difference from the short bearing"), "ΔΠ", "3.25", "%", 3, 0.01, _COMPARISON
    ),
    "table[].attitude": Label(N_("attitude angle"), "ψ", unit="deg"),
}

MTOS: dict[str, Label] = {
    "rows": Label(N_("load steps"), digits=9, count=True),
    "h_crit": Label(N_("critical film thickness, sum of the five terms"), "h_{min,cr}", "", "um"),
    "h_min_smallest": Label(N_("smallest film thickness of the run"), "h_min", "", "um"),
    "friction_fluid": Label(N_("mean measured friction coefficient, fluid film"), "f̄_e", "4.16"),
    "half_width": Label(N_("relative half-width"), "a", "E3"),
    "steps[].load": Label(N_("load"), "N", unit="N"),
    "steps[].regime": Label(N_("lubrication regime")),
    "steps[].e_x": Label(N_("displacement of the journal along x"), "e_x", "4.11", "um", 4, 1e-3),
    "steps[].e_y": Label(N_("displacement of the journal along y"), "e_y", "4.11", "um", 4, 1e-3),
    "steps[].e": Label(N_("eccentricity"), "e", "4.11", "um", 4, _NOISE_UM),
    "steps[].chi": Label(N_("eccentricity ratio"), "χ", "4.11", resolution=_NOISE_PI),
    "steps[].chi_uncertainty": Label(
        N_("standard uncertainty of the eccentricity ratio"), "u(χ)", "GUM"
    ),
    "steps[].chi_expanded": Label(
        N_("expanded uncertainty of the eccentricity ratio (k = 2)"), "U(χ)", "GUM"
    ),
    "steps[].angle": Label(N_("attitude angle"), "δ, γ", "4.12", "deg"),
    "steps[].spring_force": Label(N_("spring force"), "F", "4.13", "N"),
    "steps[].friction_moment": Label(N_("friction moment"), "M_fr", "4.14", "N*m"),
    "steps[].friction_force": Label(N_("friction force"), "F_fr", "4.15", "N"),
    "steps[].friction_measured": Label(N_("measured friction coefficient"), "f_e", "4.16"),
    "steps[].viscosity": Label(N_("oil viscosity"), "μ_t", "4.18", "Pa*s"),
    "steps[].bearing_characteristic": Label(N_("bearing characteristic"), "S_1", "4.21, E9"),
    "steps[].temperature_rise": Label(N_("temperature rise of the oil"), "Δt", "4.19", "degC", 3),
    "steps[].viscosity_at": Label(N_("oil viscosity at the thermocouple"), "μ_i", "4.17", "Pa*s"),
    "steps[].bearing_characteristic_inverse": Label(
        N_("inverse bearing characteristic"), "S_1^{-1}", "4.21, E9"
    ),
    "steps[].h_min": Label(N_("film thickness"), "h_min", "", "um", 4, _NOISE_UM),
    "steps[].film": Label(N_("film (against the critical thickness)")),
    "steps[].viscosity_ratio": Label(
        N_("relative viscosity, μ0 at 50 °C"), "μ_t/μ_0", "4.4", part=_THEORY
    ),
    "steps[].a1_00": Label(N_("short-bearing integral A1^00"), "A_1^{00}", "4.5", part=_THEORY),
    "steps[].a2_00": Label(N_("short-bearing integral A2^00"), "A_2^{00}", "4.5", part=_THEORY),
    "steps[].a3_00": Label(N_("short-bearing integral A3^00"), "A_3^{00}", "4.5", part=_THEORY),
    "steps[].a3_02": Label(N_("short-bearing integral A3^02"), "A_3^{02}", "4.5", part=_THEORY),
    "steps[].a3_20": Label(N_("short-bearing integral A3^20"), "A_3^{20}", "4.5", part=_THEORY),
    "steps[].a3_11": Label(N_("short-bearing integral A3^11"), "A_3^{11}", "4.5", part=_THEORY),
    "steps[].v_factor": Label(N_("dimensionless tangential film force"), "V", "4.4", part=_THEORY),
    "steps[].tangential_force": Label(N_("tangential film force"), "P_τ", "4.2", "N", part=_THEORY),
    "steps[].friction_theory": Label(
        N_("friction coefficient, fluid film theory"), "f_T", "4.10", part=_THEORY
    ),
    "steps[].friction_finite": Label(
        N_("friction coefficient of the finite bearing"), "f", "3.1", part=_THEORY
    ),
    "steps[].load_finite": Label(
        N_("load the finite bearing carries"), "W", "3.1", "N", part=_THEORY
    ),
    "steps[].friction_error": Label(
        N_("difference from the theory"), "Δf", "", "%", 3, 0.01, _COMPARISON
    ),
    "steps[].friction_measured_uncertainty": Label(
        N_("standard uncertainty of the friction coefficient"), "u(f_e)", "GUM"
    ),
    "steps[].friction_measured_expanded": Label(
        N_("expanded uncertainty of the friction coefficient (k = 2)"), "U(f_e)", "GUM"
    ),
    "steps[].film_parameter": Label(
        N_("film parameter h_min/√(Rq_journal² + Rq_bush²)"), "Λ", digits=3
    ),
    "steps[].film_lambda": Label(N_("regime by the film parameter")),
    "journal_rq": Label(N_("root-mean-square roughness of the journal"), "R_{q,j}", unit="um"),
    "bush_rq": Label(N_("root-mean-square roughness of the bush"), "R_{q,b}", unit="um"),
    "roughness_source": Label(N_("where the roughness comes from")),
    "regime_disagreements": Label(
        N_("steps whose regime differs from the experiment's"), part=_COMPARISON
    ),
}


def _fit(method: str) -> dict[str, Label]:
    """The bearing-curve fit by three pairs of levels (the manual's ν, b) or by least squares
    (ν_LSQ, b_LSQ): one symbol per fit."""
    lsq = method == "lsq"
    mark = "_{LSQ}" if lsq else ""
    return {
        "method": Label(N_("fitting method"), "", "", part=_THEORY),
        "nu": Label(
            N_("exponent of the bearing curve, least squares")
            if lsq
            else N_("exponent of the bearing curve, three pairs of levels"),
            "ν" + mark,
            "1.8",
            part=_THEORY,
        ),
        "b": Label(
            N_("coefficient of the bearing curve, least squares")
            if lsq
            else N_("coefficient of the bearing curve, three pairs of levels"),
            "b" + mark,
            "1.8",
            part=_THEORY,
        ),
        "nu_partial": Label(N_("exponent by a pair of levels"), "ν_i", "1.16", part=_THEORY),
        "b_partial": Label(N_("coefficient by a level"), "b_i", "1.18", part=_THEORY),
    }


PROFILOMETER: dict[str, Label] = {
    "rows": Label(N_("points of the trace"), digits=9, count=True),
    "base_length": Label(N_("base length"), "l", "", "mm"),
    "ra": Label(N_("arithmetic mean deviation"), "R_a", "1.3", "um", 3),
    "ra_uncertainty": Label(
        N_("standard uncertainty of the arithmetic mean deviation"), "u(R_a)", "GUM", "um", 3
    ),
    "ra_expanded": Label(
        N_("expanded uncertainty of the arithmetic mean deviation (k = 2)"),
        "U(R_a)",
        "GUM",
        "um",
        3,
    ),
    "ra_error": Label(N_("instrument error of Ra"), "δR_a", "1.14", "um", 2),
    "rq": Label(N_("root-mean-square deviation"), "R_q", "", "um", 3),
    "rz": Label(N_("ten-point height"), "R_z", "1.4", "um", 3),
    "rz_uncertainty": Label(
        N_("standard uncertainty of the ten-point height"), "u(R_z)", "GUM", "um", 3
    ),
    "rz_expanded": Label(
        N_("expanded uncertainty of the ten-point height (k = 2)"), "U(R_z)", "GUM", "um", 3
    ),
    "rz_error": Label(N_("instrument error of Rz"), "δR_z", "1.14", "um", 2),
    "rmax": Label(N_("peak line to valley line"), "R_max", "", "um", 3),
    "rmax_error": Label(N_("instrument error of Rmax"), "δR_max", "1.14", "um", 2),
    "sm": Label(N_("mean spacing of profile elements"), "S_m", "", "mm", 3),
    "sm_error": Label(N_("instrument error of Sm"), "δS_m", "1.14", "mm", 2),
    "asperity_radius": Label(N_("mean asperity radius"), "R", "1.1, E5", "um", 3),
    "levels": Label(N_("depth of the level below the peak line"), "p_i", "", "um", 3),
    "eps": Label(N_("relative depth"), "ε", "1.7", digits=3),
    "tp": Label(N_("relative bearing length"), "t_p", "1.6", digits=3),
    "bearing_lengths": Label(N_("bearing length of the profile"), "η_p", "1.6", "um", 3),
    "outside_subrange": Label(N_("parameters outside the ranges of the subrange")),
    "rmax_difference": Label(
        N_("profilometer's Rmax against the profilogram's"), "δ", "1.20", "%", 3, 0, _COMPARISON
    ),
    "rz_difference": Label(
        N_("profilometer's Rz against the profilogram's"), "δ_{Rz}", "1.20", "%", 3, 0, _COMPARISON
    ),
    "ra_difference": Label(
        N_("profilometer's Ra against the profilogram's"), "δ_{Ra}", "1.20", "%", 3, 0, _COMPARISON
    ),
    "rz_peaks": Label(N_("the five highest peaks behind Rz"), "y_{p,i}", "1.4", "um", 4),
    "rz_valleys": Label(N_("the five deepest valleys behind Rz"), "y_{v,i}", "1.4", "um", 4),
    **{
        f"fit_{method}.{name}": label
        for method in ("manual", "lsq")
        for name, label in _fit(method).items()
    },
    "fit_manual.residuals": Label(
        N_("difference from the fit by three pairs of levels"), "Δt_p", "1.8", digits=3
    ),
    "fit_lsq.residuals": Label(
        N_("difference from the least-squares fit"), "Δt_{p,LSQ}", "1.8", digits=3
    ),
    "complex_parameter": Label(N_("complex roughness parameter"), "Δ", "1.9", part=_THEORY),
    "ra_from_complex": Label(
        N_("Ra from the complex parameter"), "R_{a,Δ}", "1.10", "um", 3, 0, _THEORY
    ),
    "complex_parameter_equilibrium": Label(
        N_("complex parameter of the equilibrium roughness"), "Δ_T", "1.11", part=_COMPARISON
    ),
    **_iso("iso."),
}


#: The wear estimates' subscripts: the specimen (1 the ball or pin, 2 the disc or flat, as
#: the manual numbers the pin and the disc) and the method (A the track's area, d the scar,
#: m the mass).
WEAR_SUBSCRIPTS = {"disc_track": "2,A", "disc_mass": "2,m", "pin_scar": "1,d", "pin_mass": "1,m"}


def _wear_labels(path: str, what: str, rate: str) -> dict[str, Label]:
    """A wear estimate's volume and specific wear rate, with their uncertainties."""
    k: UnitSymbol = "mm^3/(N*m)"
    sub = WEAR_SUBSCRIPTS[path]
    return {
        f"{path}.volume": Label(what, f"V_{{{sub}}}", "", "mm^3"),
        f"{path}.volume_uncertainty": Label(
            N_("standard uncertainty of the volume"), f"u(V_{{{sub}}})", "GUM", "mm^3"
        ),
        f"{path}.specific_wear_rate": Label(rate, f"k_{{{sub}}}", "", k),
        f"{path}.specific_wear_rate_uncertainty": Label(
            N_("standard uncertainty of the specific wear rate"), f"u(k_{{{sub}}})", "GUM", k
        ),
        f"{path}.specific_wear_rate_expanded": Label(
            N_("expanded uncertainty of the specific wear rate (k = 2)"),
            f"U(k_{{{sub}}})",
            "GUM",
            k,
        ),
    }


TRIBOMETER: dict[str, Label] = {
    "rows": Label(N_("rows analysed"), digits=9, count=True),
    "duration": Label(N_("duration of the record"), "t", unit="s"),
    "sliding_distance": Label(N_("sliding distance"), "L", unit="m"),
    "laps": Label(N_("laps (cycles) run"), "n_L", digits=6, count=True),
    "mean_load": Label(N_("mean normal load"), "F", unit="N"),
    "friction_mean": Label(N_("friction coefficient, whole record"), "μ̄"),
    "friction_static": Label(N_("static (peak) friction coefficient at the start"), "μ_s"),
    "running_in_distance": Label(N_("running-in distance (settled within ±5 %)"), "L_r", unit="m"),
    "running_in_laps": Label(N_("laps (cycles) of the running-in"), "n_r", digits=6, count=True),
    "change_points": Label(N_("changes in the mean found"), "", digits=3, count=True),
    "friction_steady": Label(N_("friction coefficient, steady part"), "μ"),
    "friction_steady_std": Label(N_("standard deviation of the friction coefficient"), "σ_μ"),
    "friction_steady_uncertainty": Label(
        N_("standard uncertainty of the friction coefficient"), "u(μ)", "GUM"
    ),
    "friction_steady_expanded": Label(
        N_("expanded uncertainty of the friction coefficient (k = 2)"), "U(μ)", "GUM"
    ),
    "temperature_mean": Label(N_("mean temperature"), "T", unit="degC", digits=3),
    "steps[].step": Label(N_("step"), "i", digits=6, count=True),
    "steps[].sliding_speed": Label(N_("sliding speed"), "v", unit="m/s"),
    "steps[].track_radius": Label(N_("track radius"), "R", unit="mm"),
    "steps[].normal_load": Label(N_("normal load"), "F", unit="N"),
    "steps[].duration": Label(N_("duration"), "t", unit="s"),
    "steps[].distance": Label(N_("sliding distance"), "L", unit="m"),
    "steps[].friction_mean": Label(N_("friction coefficient, whole step"), "μ̄"),
    "steps[].friction_steady": Label(N_("friction coefficient, steady part"), "μ"),
    "wear_depth_change": Label(N_("wear depth by the displacement sensor"), "h", unit="um"),
    "hertz.modulus": Label(N_("contact modulus"), "E*", "", "GPa", part=_THEORY),
    "hertz.contact_radius": Label(N_("radius of the contact circle"), "a", "", "um", part=_THEORY),
    "hertz.max_pressure": Label(
        N_("initial maximum contact pressure"), "p_0", "", "MPa", part=_THEORY
    ),
    "hertz.mean_pressure": Label(
        N_("initial mean contact pressure"), "p_m", "", "MPa", part=_THEORY
    ),
    "nominal_pressure": Label(
        N_("nominal pressure of the flat pin"), "p", unit="MPa", part=_THEORY
    ),
    "disc_track.traces": Label(N_("profiles across the track"), "n_p", digits=3, count=True),
    "disc_track.track_area": Label(N_("cross-section area of the wear track"), "A", "", "mm^2"),
    "disc_track.track_area_std": Label(
        N_("standard deviation of the track's area"), "s(A)", "", "mm^2"
    ),
    **_wear_labels(
        "disc_track",
        N_("worn volume of the disc, from the track"),
        N_("specific wear rate of the disc, from the track"),
    ),
    **_iso("disc_track.iso."),
    "disc_mass.mass_loss": Label(N_("mass loss of the disc"), "Δm", unit="mg"),
    "disc_mass.density": Label(N_("density of the disc"), "ρ", unit="kg/m^3"),
    **_wear_labels(
        "disc_mass",
        N_("worn volume of the disc, from its mass loss"),
        N_("specific wear rate of the disc, from its mass loss"),
    ),
    "pin_scar.scar_diameter": Label(N_("wear scar diameter of the ball"), "d", unit="um"),
    "pin_scar.height_loss": Label(N_("height loss of the pin"), "Δh", unit="um"),
    **_wear_labels(
        "pin_scar",
        N_("worn volume of the ball or pin, from its scar"),
        N_("specific wear rate of the ball or pin, from its scar"),
    ),
    "disc_mass_below": Label(
        N_("mass change of the disc: below the balance's resolution"), "|Δm| <", unit="mg"
    ),
    "pin_mass_below": Label(
        N_("mass change of the ball or pin: below the balance's resolution"), "|Δm| <", unit="mg"
    ),
    "pin_mass.mass_loss": Label(N_("mass loss of the ball or pin"), "Δm", unit="mg"),
    "pin_mass.density": Label(N_("density of the ball or pin"), "ρ", unit="kg/m^3"),
    **_wear_labels(
        "pin_mass",
        N_("worn volume of the ball or pin, from its mass loss"),
        N_("specific wear rate of the ball or pin, from its mass loss"),
    ),
}

PIN_ON_DISC: dict[str, Label] = {
    **TRIBOMETER,
    "lap_amplitude": Label(N_("once-per-lap amplitude of the friction coefficient"), "Δμ_1"),
}

RECIPROCATING: dict[str, Label] = {
    **TRIBOMETER,
    "friction_forward": Label(N_("friction coefficient, forward strokes"), "μ_f"),
    "friction_backward": Label(N_("friction coefficient, backward strokes"), "μ_b"),
    "strokes[].cycle": Label(N_("cycle"), "n"),
    "strokes[].forward": Label(N_("forward strokes"), "μ_f"),
    "strokes[].backward": Label(N_("backward strokes"), "μ_b"),
}


def row_labels(labels: Mapping[str, Label], prefix: str) -> dict[str, Label]:
    """The labels of the rows of a per-row table by field name: ``row_labels(MTOS,
    "steps[].")["chi"]``."""
    return {k.removeprefix(prefix): v for k, v in labels.items() if k.startswith(prefix)}


@dataclass(frozen=True, slots=True)
class RowTable:
    """A per-row table of the results (a CSV of its own): its file name, its caption and
    its columns, paths of lists of equal length (``"steps[].chi"``, ``"levels"``)."""

    name: str
    caption: str
    columns: tuple[str, ...]


def _columns(labels: Mapping[str, Label], prefix: str) -> tuple[str, ...]:
    return tuple(path for path in labels if path.startswith(prefix))


SLIDE_BEARING_TABLES = (
    RowTable(
        "angles",
        N_("Tables 3.1 and 3.3: pressure along the angle at z = 0"),
        _columns(SLIDE_BEARING, "table[]."),
    ),
    RowTable(
        "axial_profile",
        N_("Table 3.2: pressure along the axis"),
        _columns(SLIDE_BEARING, "axial[]."),
    ),
)
"""The per-row tables of the slide bearing's results (a stand's declaration names its own)."""

MTOS_TABLES = (RowTable("steps", N_("Tables 4.4-4.6: the load steps"), _columns(MTOS, "steps[].")),)

PROFILOMETER_TABLES = (
    RowTable(
        "bearing_curve",
        N_("Tables 1.6 and 1.8: the bearing curve"),
        ("levels", "eps", "tp", "fit_manual.residuals", "fit_lsq.residuals"),
    ),
    RowTable(
        "partial_fits",
        N_("Table 1.7: coefficients by pairs of levels"),
        ("fit_manual.nu_partial", "fit_manual.b_partial"),
    ),
)

PIN_ON_DISC_TABLES = (
    RowTable("steps", N_("The recipe's steps"), _columns(PIN_ON_DISC, "steps[].")),
)

RECIPROCATING_TABLES = (
    RowTable("steps", N_("The recipe's steps"), _columns(RECIPROCATING, "steps[].")),
    RowTable(
        "strokes",
        N_("Forward and backward strokes, by blocks of cycles"),
        _columns(RECIPROCATING, "strokes[]."),
    ),
)

#: Results that are plot series or the analysis' own words, not quantities.
NOT_QUANTITIES = frozenset({"stand", "friction", "pending", "notes", "friction_map", "loops"})

_SUB = str.maketrans("0123456789aehijklmnoprstuvx+-", "₀₁₂₃₄₅₆₇₈₉ₐₑₕᵢⱼₖₗₘₙₒₚᵣₛₜᵤᵥₓ₊₋")
_SUP = str.maketrans("0123456789+-n", "⁰¹²³⁴⁵⁶⁷⁸⁹⁺⁻ⁿ")
_SCRIPT = re.compile(r"([_^])(\{[^}]*\}|[\w∞]+)")


def plain_symbol(symbol: str) -> str:
    """The symbol in plain Unicode for CSV and consoles: ``"e_x"`` -> ``"eₓ"``,
    ``"S_1^{-1}"`` -> ``"S₁⁻¹"``; a script Unicode cannot write stays as ``_min``."""

    def script(match: re.Match[str]) -> str:
        text = match.group(2).strip("{}")
        table = _SUB if match.group(1) == "_" else _SUP
        turned = text.translate(table)
        if any(c == t for c, t in zip(text, turned, strict=True) if c not in ",·"):
            return match.group(1) + text
        return turned

    return _SCRIPT.sub(script, symbol)


PARTICULARS: dict[str, Label] = {
    "mode": Label(N_("mode")),
    "load_N": Label(N_("load"), "N", unit="N"),
    "speed_rpm": Label(N_("disc speed"), "n", unit="rpm"),
    "revolutions": Label(N_("disc revolutions"), "M_rev", unit="rev"),
    "loads_fluid": Label(N_("loads, fluid film"), "N", unit="N"),
    "loads_mixed": Label(N_("loads, mixed lubrication"), "N", unit="N"),
    "loads_boundary": Label(N_("loads, boundary lubrication"), "N", unit="N"),
    "bearing_model": Label(N_("bearing model of the simulator")),
    "simulated": Label(N_("simulated")),
    "ra_um": Label(N_("roughness of the surface"), "R_a", unit="um"),
    "base_length_mm": Label(N_("base length"), "l", unit="mm"),
    "loader_scale_mm": Label(N_("loader scale reading"), unit="mm"),
    "limb_step_deg": Label(N_("step of the limb"), "Δφ", unit="deg"),
    "pin": Label(N_("pin")),
    "disc": Label(N_("disc")),
    "journal": Label(N_("journal")),
    "bush": Label(N_("bush")),
    "bearing": Label(N_("bearing")),
    "surface": Label(N_("surface")),
    "ball": Label(N_("ball")),
    "laps": Label(N_("laps")),
    "plan": Label(N_("test plan")),
}
"""The usual keys of a run's test plan and specimen (free fields: a key not named here is
shown as it is, as user data), each value in the unit of its key."""

_MM, _UM, _MPA = Label("", unit="mm"), Label("", unit="um"), Label("", unit="MPa")
CONFIGURATION: dict[str, Label] = {
    "disc_radius": _MM,
    "disc_width": _MM,
    "pin_diameter": _MM,
    "youngs_modulus": Label("", unit="GPa"),
    "hardness": _MPA,
    "yield_strength": _MPA,
    "tensile_strength": _MPA,
    "contour_pressure": _MPA,
    "tau0": _MPA,
    "accuracy.balance_resolution": Label("", unit="mg"),
    "accuracy.length": _MM,
    "clearance": _UM,
    "accuracy.clearance": _UM,
    "bearing_radius": _MM,
    "width": _MM,
    "diameter": _MM,
    "displacement_per_division": _UM,
    "lever_moment_arm": _MM,
    "friction_arm": _MM,
    "accuracy.arms": _MM,
    "journal_roughness": _UM,
    "bush_roughness": _UM,
    "misalignment": _UM,
    "deflection": _UM,
    "shape_error": _UM,
    "journal_rq": _UM,
    "bush_rq": _UM,
    "stylus_radius": _UM,
    "step": _UM,
    "tip_diameter": _MM,
    "track_radius": _MM,
    "stroke_length": _MM,
    "accuracy.scar": _UM,
    "accuracy.height": _UM,
    "lambda_c": _MM,
    "lambda_s": _UM,
    **{
        f"accuracy.{name}": Label("", unit="%")
        for name in (
            "moment",
            "load",
            "dynamometer",
            "spring_rate",
            "friction_force",
            "profile_height",
        )
    },
}
"""The display unit of a stand's configuration fields, by field name (``accuracy.<name>``
for the instruments' accuracies), as the results print them: mm for the geometry, µm for
clearances and roughness, MPa for strengths and pressures, GPa for moduli, mg for the
balance, λc in mm and λs in µm (as the ISO results), relative limits of error in % (the
manual's ±5 %); a field not named here is printed in its declared unit."""

WORDS: tuple[str, ...] = (
    N_("fluid"),
    N_("mixed"),
    N_("boundary"),
    N_("elastic"),
    N_("plastic"),
    N_("manual"),
    N_("lsq"),
    N_("yes"),
    N_("no"),
    N_("wear"),
    N_("adhesive"),
    N_("oxidative"),
    N_("ABRIS-PM7"),
    N_("finite"),
    N_("ball"),
    N_("flat_pin"),
    N_("none"),
    N_("profilograph-profilometer"),
    N_("profilograph"),
    N_("primary"),
    N_("roughness"),
    *ISO_LAMBDA_C_SOURCE.values(),
    *ISO_ENDS.values(),
)
"""The words results, test plans and configurations hold as values (regimes, contact
modes, methods, the instrument)."""

VALUE_WORDS: dict[str, str] = {
    "flat_pin": N_("flat-ended pin"),
    "lsq": N_("least squares in log-log"),
    "manual": N_("three pairs of levels (1.16)-(1.19)"),
}
"""Code words a result holds as its value, as a page prints them (in every language)."""

CHANNEL_SYMBOLS: dict[str, str] = {
    "time": "t",
    "speed": "n",
    "revolutions": "M_rev",
    **{f"p{k}": f"p_{k}" for k in range(1, 6)},
    **{f"t{k}": f"t_{k}" for k in range(1, 6)},
    "x_zero": "X_set",
    "y_zero": "Y_set",
    "pin_mass_before": "m_1",
    "pin_mass_after": "m_2",
    "disc_ra": "R_a",
    "rz_instrument": "R_{z1}",
    "rmax_instrument": "R_{max1}",
}
"""The manual's symbols of the channels whose declared name does not begin with one (the
others begin with theirs: ``"φ_k, limb angle at the end of the load zone"``)."""


def channel_symbol(name: str, long_name: str) -> str:
    """The manual's symbol of a channel (its column head in the manual's tables): declared
    here, else the head of its long name before the comma (``"Δl, friction indicator
    reading"`` -> ``"Δl"``), else none."""
    if name in CHANNEL_SYMBOLS:
        return CHANNEL_SYMBOLS[name]
    head, comma, _ = long_name.partition(", ")
    return head if comma and " " not in head else ""
