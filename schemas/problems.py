"""Errors on the wire: RFC 9457 problem details with the field, the value and the limit."""

from __future__ import annotations

from pydantic import BaseModel, Field

from schemas.channels import Violation

PROBLEM_MEDIA_TYPE = "application/problem+json"


class Problem(BaseModel):
    type: str = Field(default="about:blank", examples=["/problems/reading-out-of-limits"])
    title: str = Field(examples=["Readings outside the stand's limits"])
    status: int = Field(examples=[422])
    detail: str = Field(
        examples=["friction_moment[12] = 15.7 N*m is outside the limit: 0 <= value <= 15 N*m"]
    )
    instance: str | None = None
    errors: list[Violation] = Field(default_factory=list)
