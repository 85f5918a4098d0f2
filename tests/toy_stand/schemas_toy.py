"""The toy stand's declaration (copied as ``schemas/toy.py``): a spring stretched on a
tensile tester, its force F read against its extension x."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from schemas.channels import Channel, ChannelGroup, Limit, Order
from schemas.configuration import Configuration
from schemas.labels import Label
from schemas.quantity import quantity


class ToyConfig(Configuration):
    """The tester: the spring's free length (the manual's defaults, here a toy's)."""

    free_length: float = quantity(0.05, "m", "L_0, free length of the spring", gt=0)


GROUPS = (
    ChannelGroup(
        name="stretch",
        long_name="the spring stretched",
        aligned=True,
        signals=("force",),
        axis="extension",
        channels=(
            Channel(
                name="time",
                unit="s",
                long_name="time since the start of the run",
                limit=Limit(low=0),
                order=Order.INCREASING,
            ),
            Channel(name="extension", unit="mm", long_name="x, extension", limit=Limit(low=0)),
            Channel(name="force", unit="N", long_name="F, force", limit=Limit(low=-1e4, high=1e4)),
        ),
    ),
)


class ToyResults(BaseModel):
    stand: Literal["toy"] = "toy"
    rows: int
    stiffness: float | None = quantity(None, "N/m", "k, slope of F against x (least squares)")
    preload: float | None = quantity(None, "N", "F_0, force at zero extension")
    pending: list[str] = Field(default_factory=list)
    notes: list[str] = Field(default_factory=list)


LABELS = {
    "rows": Label("rows of the stretch", digits=9, count=True),
    "stiffness": Label("stiffness of the spring", "k", unit="N/mm", digits=5),
    "preload": Label("preload", "F_0", unit="N", digits=4),
}
