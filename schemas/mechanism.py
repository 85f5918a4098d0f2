"""The lever-mechanism calculator: the article's arm, a programmed move, the dynamic errors."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from schemas.quantity import quantity
from schemas.wire import Number


class ArmParameters(BaseModel):
    """Overrides of the arm's parameters; a field left out keeps the model library's default."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, strict=True)

    m1: float | None = quantity(None, "kg", "shoulder mass", gt=0)
    m2: float | None = quantity(None, "kg", "forearm mass", gt=0)
    m3: float | None = quantity(None, "kg", "gripper mass with payload", gt=0)
    l1: float | None = quantity(None, "m", "shoulder length", gt=0)
    l2: float | None = quantity(None, "m", "forearm length", gt=0)
    alpha1: float | None = quantity(None, "m/N", "α1, linear compliance of drive IV (17)", ge=0)
    alpha2: float | None = quantity(None, "m/N", "α2, linear compliance of drive V (17)", ge=0)
    lam1: float | None = quantity(
        None, "m/N^(2/3)", "λ1, contact compliance of drive IV (17)", ge=0
    )
    lam2: float | None = quantity(None, "m/N^(2/3)", "λ2, contact compliance of drive V (17)", ge=0)
    c33: float | None = quantity(None, "N*m/rad", "c33, gripper joint stiffness", ge=0)
    b11: float | None = quantity(None, "N*m*s/rad", "b11, shoulder joint damping", ge=0)
    b22: float | None = quantity(None, "N*m*s/rad", "b22, forearm joint damping", ge=0)
    b33: float | None = quantity(None, "N*m*s/rad", "b33, gripper joint damping", ge=0)


class Move(BaseModel):
    """A synchronous point-to-point move of the three joints, at rest before and after."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, strict=True)

    # a JSON array (not strict), of numbers (strict)
    q_start: tuple[Number, Number, Number] = quantity(
        (0.3, 0.6, 0.0), "rad", "joint angles at start", strict=False
    )
    q_end: tuple[Number, Number, Number] = quantity(
        (0.8, 1.0, 0.5), "rad", "joint angles at end", strict=False
    )
    duration: float = quantity(1.5, "s", "time of the move", gt=0, le=10)
    profile: Literal["trapezoidal", "quintic"] = "trapezoidal"


class DynamicErrorsRequest(BaseModel):
    model_config = ConfigDict(
        extra="forbid",
        allow_inf_nan=False,
        strict=True,  # a flag or a text is no number
        json_schema_extra={"examples": [{"move": {"duration": 1.5}, "samples": 200}]},
    )

    arm: ArmParameters = Field(default_factory=ArmParameters)
    move: Move = Field(default_factory=Move)
    settle: float = quantity(0.2, "s", "time after the move also simulated", ge=0, le=5)
    samples: int = Field(default=300, ge=2, le=2000, description="output times")
    method: Literal["LSODA", "Radau", "BDF", "RK45", "DOP853"] = "LSODA"


class DynamicErrorsResponse(BaseModel):
    t: list[float] = quantity(..., "s", "output times")
    q: list[list[float]] = quantity(..., "rad", "programmed joint angles, 3 x len(t)")
    xi: list[list[float]] = quantity(..., "rad", "dynamic errors ξ_k(t), 3 x len(t)")
    xi_dot: list[list[float]] = quantity(..., "rad/s", "ξ'_k(t)")
    max_abs: list[float] = quantity(..., "rad", "largest |ξ_k| of each joint")
    success: bool
    message: str
    evaluations: int = Field(description="right-hand side evaluations of the solver")
