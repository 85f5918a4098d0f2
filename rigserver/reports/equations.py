"""The manual's formulas by their equation numbers, for the report's list of the formulas it
uses (docs/models.md; corrected forms where the print is wrong, marked with the correction).

Each text is written in the reports' symbol syntax (``R_a``, ``A_3^{20}``): the symbols are
put in the report's language one by one (:meth:`Messages.symbol`), ``{um}`` is the unit µm
in it; the rest is mathematics, no words.
"""

from __future__ import annotations

import re

EQUATIONS: dict[str, str] = {
    # lab work 1
    "1.1": "R = √(π/2)/ρ_2, ρ_2 = 2π²·ρ·ξ·λ (E5)",
    "1.3": "R_a = (1/l)·∫|y| dx",
    "1.4": "R_z = (Σ_{i=1…5} |y_{p,i}| + Σ_{i=1…5} |y_{v,i}|)/5",
    "1.6": "t_p = η_p/l",
    "1.7": "ε = p/R_max",
    "1.8": "t_p = b·ε^ν",
    "1.9": "Δ = R_max/(R·b^{1/ν})",
    "1.10": "R_a = 4.3·Δ^{1/2}, {um}",
    "1.11": "Δ_T = (k_1·θ)^{(2ν-1)/(2ν)}·p_c^{-1/ν}·(τ_0/(k_2·α_{ef}))^{(2ν+1)/(2ν)}",
    "1.14": "ΔR_a = 0.02·R_{a,max} + 0.04·R_a, ΔR_z = 0.03·R_{z,max} + 0.05·R_z",
    "1.16": "ν_{ij} = lg(η_{pi}/η_{pj})/lg(p_i/p_j)",
    "1.18": "lg b_i = lg t_{pi} - ν·lg ε_i",
    "1.20": "δ = (R_{max1} - R_{max2})/R_{max1}·100 %, δ_{Rz} = (R_{z1} - R_{z2})/R_{z2}·100 %",
    # lab work 2
    "2.2": "C = 0.118/(1 + t/2) (E1)",
    "2.3": "p_c = N/A_c",
    "2.6": "Δ = 5.4·10⁻²·R_a² (E2)",
    "2.8": "f = M_fr/(N·r_2)",
    "2.9": "Δm = m_1 - m_2",
    "2.10": "V = Δm/ρ",
    "2.11": "h = V/(π·r_1²)",
    "2.12": "L = 2π·r_2·M_rev",
    "2.13": "I_{h,exp} = h/L",
    "2.14": "ΔI_h = (I_{h,exp} - I_{h,th})/I_{h,exp}·100 %",
    "2.15": "0.4·I_{h,th} ≤ I_{h,exp} ≤ 2.6·I_{h,th}",
    "2.16": "Δf = (f_a - f_ok)/f_a·100 %",
    # lab work 3
    "3.10": "Π_0 = 3μ̄a²·(Gχ sin φ - E cos φ)/(1 - χ cos φ)³·((z/a)² - 1)",
    "3.15": "Π_∞ = 6χμ̄(2 - χ cos φ)/((2 + χ²)(1 - χ cos φ)²)·(-G sin φ)",
    "3.17": "χ = e/h_0, e = √(e_x^2 + e_y^2)",
    "3.21": "μ = A·exp(α·t)",
    "3.22": "μ̄ = μ_t/μ_0",
    # lab work 4
    "4.2": "P_τ = P*·V, P* = 2BRμ_0ω_0/ψ²",
    "4.4": "V = -χ·a²·μ̄·A_3^{20}·G, G = ω/ω_0",
    "4.5": "A_1^{00} = π/√(1 - χ²), A_2^{00} = A_1^{00}/(1 - χ²), A_3^{20} = π/(2(1 - χ²)^{3/2})",
    "4.10": "f_T = M_fr/(N·R_1)",
    "4.11": "e = √(e_x^2 + e_y^2), χ = e/h_0",
    "4.13": "F = k·Δl",
    "4.14": "M_fr = F·l_1",
    "4.15": "F_fr = M_fr/l_2",
    "4.16": "f_e = F_fr/N",
    "4.17": "μ_i = A·exp(α·t_i)",
    "4.18": "μ_t = (μ_3 + μ_4 + μ_5)/3",
    "4.19": "Δt_i = t_i - t_1 (E4)",
    "4.21": "S_1 = μ_t·ω/p̄, p̄ = N/(BD) (E9)",
}

#: An equation number as the reports cite it: "(1.3)", "(4.21, E9)", "(4.1)-(4.10)".
_CITED = re.compile(r"(?<![\d.,])([1-4])\.(\d{1,2})(?![\d])")
#: What a pair of parentheses holds: a citation is in them, never a value of a table.
_PARENS = re.compile(r"\(([^()]*)\)")
#: A symbol with a subscript or superscript, translated as a whole (f_e -> f_э).
_SYMBOL = re.compile(r"[^\W\d_]+_(?:\{[^}]*\}|\w+)(?:\^\{[^}]*\})?")


def cited(text: str) -> list[str]:
    """The equation numbers of :data:`EQUATIONS` that ``text`` cites, once each, in the
    manual's order."""
    found = [f"{a}.{b}" for group in _PARENS.findall(text) for a, b in _CITED.findall(group)]
    known = [n for n in dict.fromkeys(found) if n in EQUATIONS]
    return sorted(known, key=lambda n: tuple(int(part) for part in n.split(".")))


def symbols_of(formula: str) -> list[str]:
    """The symbols with scripts in ``formula`` (to be put in the report's language)."""
    return _SYMBOL.findall(formula)
