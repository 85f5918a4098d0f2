"""What the stands' results share: a long record reduced for display, the ISO roughness
parameters of a profile."""

from __future__ import annotations

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
