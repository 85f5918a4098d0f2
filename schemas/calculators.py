"""Inputs and answers of the calculators under ``/models``: the model library on its own."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict

from schemas.quantity import quantity


def _defaults_as_example(schema: dict[str, Any], model: type[BaseModel]) -> None:
    """The inputs' defaults (the manual's data where the class names an item) as the
    OpenAPI example."""
    schema["examples"] = [model().model_dump(mode="json")]


class _Input(BaseModel):
    model_config = ConfigDict(
        extra="forbid",
        allow_inf_nan=False,
        strict=True,  # a flag or a text is no number
        json_schema_extra=_defaults_as_example,
    )


class WearTheoryInput(_Input):
    """Kragelsky's fatigue wear of a pin on a disc (2.1)-(2.7); defaults: lab 2, item 18."""

    load: float = quantity(300.0, "N", "N, normal load", gt=0)
    pin_radius: float = quantity(0.005, "m", "r1", gt=0)
    disc_radius: float = quantity(0.0225, "m", "r2", gt=0)
    friction_coefficient: float = quantity(0.4, "1", "f", gt=0)
    ra_disc: float = quantity(0.78e-6, "m", "Ra of the disc", gt=0)
    youngs_modulus: float = quantity(2.13e11, "Pa", "E1 of the pin", gt=0)
    poisson: float = quantity(0.3, "1", "μ1 of the pin", ge=0, le=0.5)
    hardness: float = quantity(1.24e9, "Pa", "HB1 of the pin", gt=0)
    yield_strength: float = quantity(2.25e8, "Pa", "σ_T", gt=0)
    tensile_strength: float = quantity(4.2e8, "Pa", "σ_B", gt=0)
    elongation: float = quantity(0.23, "1", "e_B = δ/100", gt=0, le=1)
    fatigue_t: float = quantity(3.0, "1", "t", gt=0)
    nu: float = quantity(2.0, "1", "ν", gt=0)
    b: float = quantity(2.0, "1", "b_ν", gt=0)


class BearingFrictionInput(_Input):
    """Short-bearing friction of a journal bearing (4.1)-(4.10)."""

    chi: float = quantity(0.5, "1", "χ = e/h0", ge=0, lt=1)
    omega: float = quantity(157.0, "rad/s", "ω, journal speed", gt=0)
    viscosity: float = quantity(0.03, "Pa*s", "μ of the film", gt=0)
    bearing_radius: float = quantity(0.025, "m", "R", gt=0)
    width: float = quantity(0.04, "m", "B", gt=0)
    clearance: float = quantity(100e-6, "m", "h0, radial clearance", gt=0)
    load: float = quantity(1000.0, "N", "N, applied load", gt=0)


class BearingFrictionResult(BaseModel):
    friction_moment: float = quantity(..., "N*m", "M_tr (4.1)")
    friction_coefficient: float = quantity(..., "1", "f_T = M_tr/(N·R1) (4.10)")
    film_force: float = quantity(..., "N", "resultant of the short-bearing film force")
    attitude_angle: float = quantity(..., "deg", "angle between load and line of centres")
    half_width: float = quantity(..., "1", "a = B/(2R) (E3)")


class EquilibriumRoughnessInput(_Input):
    """Equilibrium roughness of a run-in surface (1.11)-(1.13); defaults: lab 1, item 13."""

    nu: float = quantity(2.0, "1", "ν of the bearing curve", gt=0)
    poisson: float = quantity(0.27, "1", "μ", ge=0, le=0.5)
    youngs_modulus: float = quantity(2.1e11, "Pa", "E", gt=0)
    contour_pressure: float = quantity(18e6, "Pa", "p_c", gt=0)
    tau0: float = quantity(1.2e6, "Pa", "τ0", gt=0)
    alpha_r: float = quantity(0.02, "1", "α_r, hysteresis loss", gt=0)


class EquilibriumRoughnessResult(BaseModel):
    complex_parameter: float = quantity(..., "1", "Δ_T (1.11)")
    ra: float = quantity(..., "m", "Ra = 4.3·Δ^(1/2) μm (1.10)")
    k1: float = quantity(..., "1", "k1 (1.13)")
    k2: float = quantity(..., "1", "k2 (1.13)")
