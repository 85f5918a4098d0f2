"""Whether Kragelsky's fatigue-wear model (2.1) applies: its own applicability figures.

(2.1) assumes elastic contact at the asperities and many passes to fail one (n ≫ 1); the
plastic branch needs k_f^n (σ_T > 2f·HB). (2.7) compares the contour pressure p_c with HB and
cannot see the asperities, so this module estimates the real-contact pressure from the same
rough-surface model that (2.1) is built on (spherical asperities of radius R, heights by the
bearing curve t_p = b·ε^ν, Hertz contact each) and the cycles to failure from the same
fatigue law. The derivation is in ``docs/validity.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rigserver.core._checks import positive
from rigserver.core.errors import ModelInputError
from rigserver.core.wear import (
    TheoreticalWear,
    elastic_fatigue_factor,
    plastic_fatigue_factor,
)

__all__ = ["MIN_CYCLES", "WearTheoryValidity", "wear_theory_validity"]

#: n ≫ 1 read as: an asperity survives at least this many passes.
MIN_CYCLES = 10.0


@dataclass(frozen=True, slots=True)
class WearTheoryValidity:
    """The applicability figures of (2.1) for one run.

    Attributes
    ----------
    approach : float
        ε = a/Rmax, relative approach of the surfaces at the contour pressure.
    real_area_ratio : float
        η_r = A_r/A_c = b·ε^ν/2 (Hertz area: half the geometric cut of each asperity).
    real_contact_pressure : float
        p_r = p_c/η_r, Pa: the mean pressure on the asperities in elastic contact.
    hardness : float
        HB of the wearing body, Pa.
    asperity_stress : float
        σ = k_f^y·p_r, Pa: the largest stress at an asperity in elastic sliding.
    fatigue_strength : float
        σ0 of n = (σ0/σ)^t, Pa (σ_B in (2.1)).
    cycles_to_failure : float
        n = (σ0/σ)^t, passes an asperity survives.
    plastic_k_f : float or None
        k_f^n, None when σ_T <= 2f·HB.
    within_range : bool
        True when the branch (2.7) picks applies: elastic with p_r <= HB and n >= MIN_CYCLES,
        or plastic with k_f^n defined.
    reasons : tuple of str
        Why not (empty when within range), as codes: ``"plastic_asperities"`` (elastic by
        (2.7), but p_r > HB), ``"few_cycles"`` (n < MIN_CYCLES), ``"no_plastic_k_f"``
        (k_f^n undefined, σ_T <= 2f·HB, where the plastic branch would be needed); the
        figures behind each are the other attributes.
    """

    approach: float
    real_area_ratio: float
    real_contact_pressure: float
    hardness: float
    asperity_stress: float
    fatigue_strength: float
    cycles_to_failure: float
    plastic_k_f: float | None
    within_range: bool
    reasons: tuple[str, ...]


def wear_theory_validity(
    *,
    theory: TheoreticalWear,
    friction_coefficient: float,
    poisson: float,
    hardness: float,
    yield_strength: float,
    fatigue_strength: float,
    fatigue_t: float,
    b: float,
    nu: float,
) -> WearTheoryValidity:
    """The applicability figures of (2.1): real-contact pressure, cycles to failure, k_f^n.

    .. math::

        p_c = \\frac{b\\,k_ν}{θ}\\sqrt{R_{max}/R}\\;ε^{ν+1/2}, \\qquad
        η_r = \\frac{b\\,ε^ν}{2}, \\qquad p_r = \\frac{p_c}{η_r}
              = \\frac{2 k_ν}{θ}\\sqrt{R_{max}/R}\\;ε^{1/2},

        n = \\left(\\frac{σ_0}{k_f^y p_r}\\right)^t

    Parameters
    ----------
    theory : TheoreticalWear
        (2.1) evaluated for the run: p_c, θ, k_ν, Rmax/R and the contact mode by (2.7).
    friction_coefficient : float
        f, dimensionless.
    poisson : float
        μ1 of the pin.
    hardness, yield_strength : float
        HB1 and σ_T of the pin, Pa.
    fatigue_strength : float
        σ0 of the fatigue curve, Pa (σ_B in (2.1)).
    fatigue_t : float
        t of the fatigue curve (> 0).
    b, nu : float
        Bearing-curve parameters b_ν, ν of the disc (ν > 1 for the height density of the
        derivation to be non-negative; 2 after running-in).

    Returns
    -------
    WearTheoryValidity

    Notes
    -----
    The contour pressure is carried by spherical asperities of radius R whose summit heights
    follow the bearing curve; k_ν = Γ(ν+1)/(2√π Γ(ν+1.5)) of (2.1) is exactly the constant
    the sum of Hertz loads gives, so p_r uses nothing that (2.1) does not. Only the pin's θ
    enters, as in (2.1). The estimate is for elastic asperities; when it exceeds HB, they
    yield and the elastic branch does not apply.

    References
    ----------
    .. [1] I. V. Kragelsky, M. N. Dobychin, V. S. Kombalov, Friction and Wear: Calculation
       Methods, Pergamon, 1982, ch. 3 (contact of rough surfaces) and ch. 7 (fatigue wear).
    .. [2] Lab manual, lab work 2, (2.1)-(2.7).
    """
    hb = float(positive("hardness", hardness))
    sigma_0 = float(positive("fatigue_strength", fatigue_strength))
    t = float(positive("fatigue_t", fatigue_t))
    b_nu = float(positive("b", b))
    nu_ = float(positive("nu", nu))
    if theory.rmax_over_r <= 0.0:
        raise ModelInputError(
            "Rmax/R is 0 (a disc without roughness, Ra = 0): the approach of the asperities "
            "is undefined"
        )
    root = math.sqrt(theory.rmax_over_r)
    approach = (theory.contour_pressure * theory.theta / (b_nu * theory.k_nu * root)) ** (
        1.0 / (nu_ + 0.5)
    )
    area_ratio = b_nu * approach**nu_ / 2.0
    p_r = theory.contour_pressure / area_ratio
    stress = (
        elastic_fatigue_factor(friction_coefficient=friction_coefficient, poisson=poisson) * p_r
    )
    if stress <= 0.0:
        raise ModelInputError("σ = k_f^y·p_r is 0: n = (σ0/σ)^t is undefined")
    try:
        cycles = (sigma_0 / stress) ** t
    except OverflowError:
        raise ModelInputError(
            f"n = (σ0/σ)^t exceeds the largest number (σ0/σ = {sigma_0 / stress:.3g}, t = {t:g})"
        ) from None
    k_f_n = plastic_fatigue_factor(
        friction_coefficient=friction_coefficient, yield_strength=yield_strength, hardness=hb
    )
    reasons: list[str] = []
    if theory.contact == "elastic":
        if p_r > hb:
            reasons.append("plastic_asperities")
        if cycles < MIN_CYCLES:
            reasons.append("few_cycles")
    if k_f_n is None and (theory.contact == "plastic" or p_r > hb):
        reasons.append("no_plastic_k_f")
    return WearTheoryValidity(
        approach=approach,
        real_area_ratio=area_ratio,
        real_contact_pressure=p_r,
        hardness=hb,
        asperity_stress=stress,
        fatigue_strength=sigma_0,
        cycles_to_failure=cycles,
        plastic_k_f=k_f_n,
        within_range=not reasons,
        reasons=tuple(reasons),
    )
