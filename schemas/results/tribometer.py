"""The commercial tribometers' results: pin- or ball-on-disc, reciprocating."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from schemas.quantity import quantity
from schemas.results.common import IsoRoughnessResult, Series


class WearEstimate(BaseModel):
    """One specimen's worn volume by one method and its specific wear rate k = V/(F·L)."""

    volume: float = quantity(..., "m^3", "V, the worn volume")
    volume_uncertainty: float | None = quantity(None, "m^3", "u(V), standard uncertainty")
    specific_wear_rate: float = quantity(..., "m^2/N", "k = V/(F·L), m³/(N·m)")
    specific_wear_rate_uncertainty: float | None = quantity(
        None, "m^2/N", "u(k), standard uncertainty (GUM)"
    )
    specific_wear_rate_expanded: float | None = quantity(
        None, "m^2/N", "U(k) = 2u, expanded (k = 2)"
    )


class TrackWear(WearEstimate):
    """The disc's (flat's) wear from profiles across its track (ASTM G99 9.2.2, G133)."""

    traces: int = Field(description="profiles across the track averaged")
    track_area: float = quantity(..., "m^2", "A, mean cross-section area of the track")
    track_area_std: float | None = quantity(None, "m^2", "s(A) over the traces")
    iso: IsoRoughnessResult | None = Field(
        default=None, description="ISO roughness of the first trace (the track's form filtered out)"
    )


class ScarWear(WearEstimate):
    """The ball's wear from its scar (a spherical cap), or a flat pin's from its height loss."""

    scar_diameter: float | None = quantity(None, "m", "d, the ball's wear scar diameter")
    height_loss: float | None = quantity(None, "m", "Δh, the flat pin's height loss")


class MassWear(WearEstimate):
    """A specimen's wear from its weighings: V = Δm/ρ."""

    mass_loss: float = quantity(..., "kg", "Δm = m_before - m_after")
    density: float = quantity(..., "kg/m^3", "ρ used")


class HertzResult(BaseModel):
    """The initial contact of the ball on the flat (Hertz)."""

    modulus: float = quantity(..., "Pa", "E*, contact modulus of the two materials")
    contact_radius: float = quantity(..., "m", "a = (3FR/(4E*))^(1/3)")
    max_pressure: float = quantity(..., "Pa", "p0 = (6FE*²/(π³R²))^(1/3)")
    mean_pressure: float = quantity(..., "Pa", "p_m = F/(πa²)")


class LapMapResult(BaseModel):
    """μ against the lap and the angular position on the disc (cell means)."""

    lap: list[float] = quantity(..., "1", "the middle lap of each row")
    angle: list[float] = quantity(..., "deg", "the middle of each angular bin")
    values: list[list[float | None]] = quantity(..., "1", "mean μ per cell; null: no reading")


class StrokeBlock(BaseModel):
    """Forward and backward strokes, averaged over a block of cycles."""

    cycle: float = quantity(..., "1", "middle cycle of the block")
    forward: float | None = quantity(None, "1", "mean μ of the forward strokes")
    backward: float | None = quantity(None, "1", "mean |μ| of the backward strokes")


class FrictionLoop(BaseModel):
    """One cycle's friction against the position: a friction loop."""

    cycle: int = Field(description="the cycle drawn")
    position: list[float] = quantity(..., "m", "x along the stroke")
    friction: list[float] = quantity(..., "1", "μ, signed by the direction of sliding")


class TribometerStep(BaseModel):
    """One step of a test's recipe (a speed or load sweep), in the record's order."""

    step: int = quantity(..., "1", "the step's number, as the record gives it")
    sliding_speed: float | None = quantity(
        None, "m/s", "v, mean sliding speed: recorded, or 2πRn/60 from the rotational speed"
    )
    track_radius: float | None = quantity(None, "m", "R, mean track radius of the step")
    normal_load: float = quantity(..., "N", "F, mean normal load of the step")
    duration: float = quantity(..., "s", "time from the step's first to its last reading")
    distance: float = quantity(..., "m", "sliding distance of the step")
    friction_mean: float = quantity(..., "1", "μ, mean over the step")
    friction_steady: float | None = quantity(
        None, "1", "μ, mean over the step's steady part; null when it did not settle"
    )


class TribometerResults(BaseModel):
    """What both tribometers report (ASTM G99, G133, ISO 20808)."""

    rows: int = Field(description="rows of the friction record analysed")
    duration: float = quantity(..., "s", "time from the first to the last reading")
    sliding_distance: float = quantity(..., "m", "L, sliding distance of the record")
    laps: float = quantity(..., "1", "laps (cycles) run")
    mean_load: float = quantity(..., "N", "F, mean normal load")
    friction_mean: float = quantity(..., "1", "μ, mean over the whole record")
    friction_static: float = quantity(..., "1", "μ_s, the peak μ at the start (static)")
    running_in_distance: float | None = quantity(
        ...,
        "m",
        "sliding distance of the running-in: where μ's lap means settle within ±5 % of the "
        "steady mean; null when the friction did not settle",
    )
    running_in_laps: float | None = quantity(..., "1", "laps (cycles) of the running-in")
    change_points: int = Field(description="changes in the mean found by PELT")
    friction_steady: float | None = quantity(
        ..., "1", "μ, mean over the steady part; null when the friction did not settle"
    )
    friction_steady_std: float | None = quantity(..., "1", "standard deviation of μ there")
    friction_steady_uncertainty: float | None = quantity(
        None, "1", "u(μ): batch means of the steady part and the sensors' limits (GUM)"
    )
    friction_steady_expanded: float | None = quantity(None, "1", "U(μ) = 2u, expanded (k = 2)")
    temperature_mean: float | None = quantity(None, "degC", "mean temperature of the record")
    wear_depth_change: float | None = quantity(
        None, "m", "last minus first reading of the displacement sensor"
    )
    hertz: HertzResult | None = None
    nominal_pressure: float | None = quantity(None, "Pa", "F/(πD²/4) of a flat pin")
    disc_track: TrackWear | None = None
    disc_mass: MassWear | None = None
    pin_scar: ScarWear | None = None
    pin_mass: MassWear | None = None
    disc_mass_below: float | None = quantity(
        None,
        "kg",
        "the balance's resolution, when the disc's mass changed by no more: no wear by mass",
    )
    pin_mass_below: float | None = quantity(
        None,
        "kg",
        "the balance's resolution, when the pin's mass changed by no more: no wear by mass",
    )
    friction: Series = Field(description="μ against the sliding distance, block means")
    steps: list[TribometerStep] = Field(
        default_factory=list, description="the recipe's steps in order (a record with `step`)"
    )
    pending: list[str] = Field(default_factory=list)
    notes: list[str] = Field(default_factory=list)


class PinOnDiscResults(TribometerResults):
    stand: Literal["pin_on_disc"] = "pin_on_disc"
    lap_amplitude: float | None = quantity(
        None, "1", "amplitude of μ's once-per-lap part in the steady state"
    )
    friction_map: LapMapResult | None = None


class ReciprocatingResults(TribometerResults):
    stand: Literal["reciprocating"] = "reciprocating"
    friction_forward: float | None = quantity(None, "1", "mean μ of the steady forward strokes")
    friction_backward: float | None = quantity(None, "1", "mean |μ| of the steady backward strokes")
    strokes: list[StrokeBlock] = Field(default_factory=list)
    loops: list[FrictionLoop] = Field(default_factory=list)
