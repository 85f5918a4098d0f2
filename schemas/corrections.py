"""Corrections of stored readings: a mistyped cell corrected, or a row struck out, each with
its reason, who and when; the value as typed is never overwritten (what
``PATCH``/``DELETE /runs/{id}/readings/{group}/{index}`` take and ``GET
/runs/{id}/corrections`` answers)."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated

from pydantic import AfterValidator, BaseModel, ConfigDict, Field
from pydantic_core import PydanticCustomError

from schemas.wire import Number, Text

#: Characters of a correction's reason.
REASON_LIMIT = 500
#: Channels one correction may change (a row of the widest group, the MTOS steps, has 10).
VALUES_LIMIT = 64


def _reason(text: str) -> str:
    """The reason without the spaces around it: 1 to :data:`REASON_LIMIT` characters."""
    stripped = text.strip()
    if not stripped:
        raise PydanticCustomError("reason_empty", "say why the reading is corrected")
    if len(stripped) > REASON_LIMIT:
        raise PydanticCustomError(
            "reason_long",
            "at most {limit} characters, not {length}",
            {"limit": REASON_LIMIT, "length": len(stripped)},
        )
    return stripped


Reason = Annotated[Text, AfterValidator(_reason)]


class CorrectionWrite(BaseModel):
    """New values for cells of one stored row, and why."""

    model_config = ConfigDict(
        extra="forbid",
        strict=True,  # a number sent as text or as true is refused
        json_schema_extra={
            "examples": [
                {"values": {"friction_moment": 3.05}, "reason": "misread: 30.5 typed for 3.05"}
            ]
        },
    )

    values: dict[Text, Number] = Field(
        min_length=1,
        max_length=VALUES_LIMIT,
        description="channel -> the value the cell should hold, in the channel's unit",
    )
    reason: Reason = Field(description="why, as the report prints it")


class StrikeWrite(BaseModel):
    """Why a stored row is struck out (left out of the corrected readings and results)."""

    model_config = ConfigDict(
        extra="forbid",
        strict=True,
        json_schema_extra={"examples": [{"reason": "row typed twice"}]},
    )

    reason: Reason = Field(description="why, as the report prints it")


class Correction(BaseModel):
    """One stored correction: a cell's value changed (``channel``, ``was``, ``now``) or a
    row struck out (``channel`` null). ``was`` is the value the cell read before this
    correction (the value as typed for the first one)."""

    model_config = ConfigDict(frozen=True)

    n: int = Field(description="its place among the run's corrections, from 1")
    group: str
    row: int = Field(description="the row's index in its group, from 0, as stored")
    channel: str | None = Field(description="the cell's channel; null: the row struck out")
    was: float | None = Field(default=None, description="the value before, in the unit")
    now: float | None = Field(default=None, description="the value after, in the unit")
    unit: str = Field(default="", description="the channel's unit")
    reason: str
    by: str = Field(description="the API key's name that made it")
    at: datetime = Field(description="when it was stored (UTC)")

    @property
    def strikes(self) -> bool:
        return self.channel is None


class CorrectedRow(BaseModel):
    """A stored row as it now reads, with its corrections (PATCH/DELETE's answer)."""

    run_id: str
    group: str
    index: int
    struck: bool = Field(description="true if the row is struck out")
    values: dict[str, float | None] = Field(
        description="channel -> the value as corrected (null: none posted)"
    )
    original: dict[str, float | None] = Field(description="channel -> the value as typed")
    corrections: list[Correction] = Field(description="the corrections of this row, in order")


class CorrectionList(BaseModel):
    """Every correction of a run, in the order stored."""

    run_id: str
    corrections: list[Correction]
