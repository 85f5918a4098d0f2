"""A run's single results as a table, as the pages list them: the wire form of
``GET /runs/{id}/results/table`` (a notebook's frame of results)."""

from __future__ import annotations

from pydantic import BaseModel, Field


class Quantity(BaseModel):
    """One result: the manual's words and symbol in the asked language, the value and its
    standard uncertainty in the display unit (full precision), the unit as printed."""

    path: str = Field(description="the result's place in the results payload")
    quantity: str = Field(description="the manual's words, with the equation number")
    symbol: str = Field(description="the manual's symbol, plain text")
    value: float | str | bool | None = Field(description="in the display unit")
    uncertainty: float | None = Field(
        description="standard uncertainty (GUM) in the display unit, where computed"
    )
    unit: str = Field(description="the display unit as printed; empty when dimensionless")
    part: str = Field(description="measured, theory or comparison")
