"""The stand kinds: the lab's four stands, configured with the manual's values as defaults,
and two commercial tribometers (pin- or ball-on-disc, reciprocating); configuration and
channels, and each kind's declaration (:data:`DECLARATIONS`: its configuration, results,
channels, labels), the one place in the schemas that names the kinds.

Every number of a configuration carries its unit. Defaults are the lab manual's where it
gives one; where it does not (the MTOS spring calibration and lever arms, the displacement
sensors' scale), the default is a placeholder that the lab overrides in its stands file,
and the field's description says so.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from schemas import labels
from schemas.channels import Channel, ChannelGroup, Limit, Order, configured_groups
from schemas.configuration import Configuration
from schemas.labels import Label, RowTable
from schemas.messages import N_
from schemas.quantity import quantity
from schemas.results.mtos import MtosResults
from schemas.results.profilometer import ProfilometerResults
from schemas.results.slide_bearing import SlideBearingResults
from schemas.results.smts2 import Smts2Results
from schemas.results.tribometer import PinOnDiscResults, ReciprocatingResults
from schemas.units import UnitSymbol
from schemas.wire import Number, Text


class StandKind(StrEnum):
    SMTS2 = "smts2"
    SLIDE_BEARING = "slide_bearing"
    MTOS = "mtos"
    PROFILOMETER = "profilometer"
    PIN_ON_DISC = "pin_on_disc"
    RECIPROCATING = "reciprocating"


# --- SMTs-2 friction and wear machine, lab work 2 -------------------------------------


class PinMaterial(Configuration):
    """The upper specimen (pin); defaults: steel St3sp (VSt3ps), table 2.2 and item 18."""

    name: Text = "St3sp"
    youngs_modulus: float = quantity(2.13e11, "Pa", "E1, Young's modulus", gt=0)
    poisson: float = quantity(0.3, "1", "μ1, Poisson's ratio", ge=0, lt=0.5)
    hardness: float = quantity(1.24e9, "Pa", "HB1, Brinell hardness", gt=0)
    yield_strength: float = quantity(2.25e8, "Pa", "σ_T, yield strength", gt=0)
    tensile_strength: float = quantity(4.2e8, "Pa", "σ_B, tensile strength", gt=0)
    elongation: float = quantity(0.23, "1", "e_B = δ/100, elongation at break", gt=0, le=1)
    density: float = quantity(7800.0, "kg/m^3", "ρ, density (2.10)", gt=0)


class DiscMaterial(Configuration):
    """The lower specimen (disc); defaults: steel R9."""

    name: Text = "R9"
    youngs_modulus: float = quantity(2.2e11, "Pa", "E2, Young's modulus", gt=0)
    poisson: float = quantity(0.3, "1", "μ2, Poisson's ratio", ge=0, lt=0.5)
    hardness: float = quantity(6.4e9, "Pa", "HB2, Brinell hardness", gt=0)


class Smts2Accuracy(Configuration):
    """Limits of error of the SMTs-2's measurements (GUM type B: a rectangular distribution of
    half-width a has the standard uncertainty a/√3)."""

    moment: float = quantity(
        0.05,
        "1",
        "friction moment, relative limit of error of its measurement (±5 %, the SMTs-2's data)",
        ge=0,
    )
    load: float = quantity(0.05, "1", "load, relative tolerance of the stand (±5 %)", ge=0)
    balance_resolution: float = quantity(1e-7, "kg", "balance's resolution (0.1 mg)", ge=0)
    length: float = quantity(5e-5, "m", "r1, r2 as machined, limit of error (±0.05 mm)", ge=0)
    density: float = quantity(50.0, "kg/m^3", "ρ of the pin's steel, limit of error", ge=0)
    counter: float = quantity(100.0, "rev", "revolution counter's step (100 rev)", ge=0)


class Smts2Config(Configuration):
    disc_radius: float = quantity(0.0225, "m", "r2, disc radius", gt=0)
    disc_width: float = quantity(0.012, "m", "b2, disc width", gt=0)
    pin_diameter: float = quantity(0.010, "m", "d1 = 2·r1, pin diameter", gt=0)
    pin: PinMaterial = PinMaterial()
    disc: DiscMaterial = DiscMaterial()
    fatigue_t_elastic: float = quantity(3.0, "1", "t, fatigue parameter, elastic contact", gt=0)
    fatigue_t_plastic: float = quantity(1.3, "1", "t, fatigue parameter, plastic contact", gt=0)
    nu: float = quantity(2.0, "1", "ν, bearing-curve exponent after run-in", gt=0.5)
    b: float = quantity(2.0, "1", "b_ν, bearing-curve coefficient after run-in", gt=0)
    steady_fraction: float = quantity(
        0.5, "1", "share of the record, from its end, averaged for the steady friction", gt=0, le=1
    )
    accuracy: Smts2Accuracy = Smts2Accuracy()


class ViscosityLaw(Configuration):
    """The oil's viscosity law μ = A·exp(α·t), t in °C (3.21, 4.17)."""

    A: float = quantity(0.0773, "Pa*s", "A of the oil's viscosity μ = A·exp(α·t)", gt=0)
    alpha: float = quantity(-0.0485, "1/degC", "α of the oil's viscosity μ = A·exp(α·t)")


# --- Slide-bearing stand, lab work 3 --------------------------------------------------


class SlideBearingAccuracy(Configuration):
    """Limits of error of the slide-bearing stand's measurements (GUM type B, rectangular)."""

    manometer_class: float = quantity(
        1.5, "%", "manometers' accuracy class: limit of error in % of the range", ge=0
    )
    manometer_range: float = quantity(10.0, "1", "manometers' range, in the gauge unit", gt=0)
    displacement: float = quantity(1.0, "div", "X, Y gauges, limit of error", ge=0)
    clearance: float = quantity(5e-6, "m", "h0 as machined, limit of error", ge=0)


class SlideBearingConfig(Configuration):
    clearance: float = quantity(175e-6, "m", "h0, radial clearance (3.17)", gt=0)
    bearing_radius: float = quantity(25.175e-3, "m", "R2, bearing radius (3.19)", gt=0)
    width: float = quantity(
        29.7e-3, "m", "B, bearing width: edges at z = ±0.59 = B/(2R) (table 3.2, E3)", gt=0
    )
    mu0: float = quantity(0.0282, "Pa*s", "μ0 = μ20, characteristic viscosity (3.18)", gt=0)
    omega0: float = quantity(329.0, "rad/s", "ω0, journal angular speed (3.18)", gt=0)
    viscosity: ViscosityLaw = ViscosityLaw()
    gauge_unit: Literal["at", "atm"] = "at"
    manometer_z: tuple[Number, Number, Number, Number, Number] = quantity(
        (-0.394, -0.197, 0.0, 0.197, 0.394),
        "1",
        "z = Z/R of manometers 1..5 (table 3.2)",
        strict=False,  # a JSON array; its items are strict
    )
    loader_rate: float = quantity(16.2, "N/mm", "load per mm of the loader scale", gt=0)
    displacement_per_division: float = quantity(
        1e-6, "m", "scale of the X, Y displacement gauges per division (placeholder)", gt=0
    )
    accuracy: SlideBearingAccuracy = SlideBearingAccuracy()


# --- MTOS stand, lab work 4 -----------------------------------------------------------


class MtosAccuracy(Configuration):
    """Limits of error of the MTOS stand's measurements (GUM type B, rectangular)."""

    indicator: float = quantity(0.005, "mm", "indicator of the flat spring, limit of error", ge=0)
    dynamometer: float = quantity(0.01, "1", "dynamometer, relative limit of error", ge=0)
    spring_rate: float = quantity(
        0.01, "1", "the flat spring's calibration k, relative limit of error", ge=0
    )
    arms: float = quantity(5e-4, "m", "l1, l2 as measured, limit of error", ge=0)
    displacement: float = quantity(0.5, "um", "X, Y sensors, limit of error", ge=0)
    clearance: float = quantity(2e-6, "m", "h0 as machined, limit of error", ge=0)


class MtosConfig(Configuration):
    spring_rate: float = quantity(
        20.0, "N/mm", "k, flat-spring calibration F = k·Δl (4.13) (placeholder)", gt=0
    )
    lever_moment_arm: float = quantity(
        0.20, "m", "l1, arm of the spring force, M = F·l1 (4.14) (placeholder)", gt=0
    )
    friction_arm: float = quantity(
        0.025, "m", "l2, arm of the friction force, F_tr = M/l2 (4.15) (placeholder)", gt=0
    )
    diameter: float = quantity(0.050, "m", "D = 2R, bearing diameter (placeholder)", gt=0)
    width: float = quantity(0.040, "m", "B, bearing width (placeholder)", gt=0)
    clearance: float = quantity(100e-6, "m", "h0, radial clearance (placeholder)", gt=0)
    omega: float = quantity(157.0, "rad/s", "ω, journal angular speed (placeholder)", gt=0)
    viscosity: ViscosityLaw = ViscosityLaw()
    journal_roughness: float = quantity(
        1.6e-6, "m", "h_journal, mean asperity height of the journal, a term of h_min,cr", ge=0
    )
    bush_roughness: float = quantity(
        3.2e-6, "m", "h_bush, mean asperity height of the bush, a term of h_min,cr", ge=0
    )
    misalignment: float = quantity(0.0, "m", "h from misalignment, a term of h_min,cr", ge=0)
    deflection: float = quantity(0.0, "m", "h from shaft deflection, a term of h_min,cr", ge=0)
    shape_error: float = quantity(0.0, "m", "h from form errors, a term of h_min,cr", ge=0)
    # Rq ≈ Rz/4.35 by (1.2) (Rmax ≈ 5ρ ≈ 1.15 Rz) from the mean heights above; a profilometer
    # run named in the run's specimen (journal_profile_run, bush_profile_run) overrides them.
    journal_rq: float = quantity(0.37e-6, "m", "Rq of the journal, for the film parameter Λ", gt=0)
    bush_rq: float = quantity(0.74e-6, "m", "Rq of the bush, for the film parameter Λ", gt=0)
    accuracy: MtosAccuracy = MtosAccuracy()
    signed_sensors: bool = Field(
        default=False,
        description="true when X, Y read more as the journal lifts off the zero contact: "
        "(4.11) then takes the sign, not |X_set - X|, which folds positions near the bush "
        "(experiments 2-3)",
    )


# --- ABRIS-PM7 profilometer, lab work 1 -----------------------------------------------


class ProfilometerConfig(Configuration):
    """The profilograph-profilometer and its settings for the run; the magnifications are
    the nominal ones of the instrument's data in the manual's lab 1 (vertical 200 … 100 000,
    horizontal 20 … 500, each of those also ×2 and ×4)."""

    instrument: Text = "ABRIS-PM7"
    mode: Literal["profilograph-profilometer", "profilograph"] = Field(
        default="profilograph-profilometer",
        description=N_(
            "mode of measurement: profilograph-profilometer (the parameters, the filtered "
            "profile) or profilograph (the profilogram only, unfiltered)"
        ),
    )
    vertical_magnification: float = quantity(
        2000.0, "1", "vertical magnification of the profilogram", gt=0
    )
    horizontal_magnification: float = quantity(
        100.0, "1", "horizontal magnification of the profilogram", gt=0
    )
    stylus_radius: float = quantity(10e-6, "m", "radius of the stylus tip", gt=0)
    step: float = quantity(0.5e-6, "m", "sampling step along the trace", gt=0)
    poisson: float = quantity(0.27, "1", "μ of the specimen, for Δ_T (1.12)", ge=0, lt=0.5)
    youngs_modulus: float = quantity(2.1e11, "Pa", "E of the specimen, for Δ_T (1.12)", gt=0)
    contour_pressure: float = quantity(18e6, "Pa", "p_c, contour pressure for Δ_T (1.11)", gt=0)
    tau0: float = quantity(1.2e6, "Pa", "τ0, friction parameter for Δ_T (1.11)", gt=0)
    alpha_r: float = quantity(0.02, "1", "α_r, hysteresis loss for Δ_T (1.12)", gt=0)
    levels: int = quantity(
        10, "1", "strips between the peak line and the mean line (table 1.6, >= 10)", ge=6
    )
    lambda_c: float = quantity(
        0.0, "m", "λc of the ISO roughness filter (0: by the ISO 21920-3 table)", ge=0
    )
    lambda_s: float = quantity(
        0.0, "m", "λs of the ISO short-wave filter (0: by the ISO 21920-3 table)", ge=0
    )
    profile_kind: Literal["primary", "roughness"] = Field(
        default="primary",
        description=N_(
            "the profile posted: primary (filtered here, ISO 16610-21) or roughness (the "
            "instrument's own roughness profile, not filtered again; λc and λs are then the "
            "instrument's, as stated)"
        ),
    )
    sections: int = quantity(
        0,
        "1",
        "sampling lengths of a roughness profile's evaluation length (0: its length over "
        "λc, or five without λc)",
        ge=0,
        le=1000,
    )


# --- commercial tribometers: pin- or ball-on-disc (ASTM G99, ISO 20808), reciprocating
# (ASTM G133) ------------------------------------------------------------------------------


class SpecimenMaterial(Configuration):
    """A specimen's material; defaults: bearing steel 100Cr6 (AISI 52100), hardened."""

    name: Text = "100Cr6"
    youngs_modulus: float = quantity(2.10e11, "Pa", "E, Young's modulus", gt=0)
    poisson: float = quantity(0.30, "1", "ν, Poisson's ratio", ge=0, lt=0.5)
    hardness: float = quantity(7.5e9, "Pa", "H, Vickers hardness", gt=0)
    density: float = quantity(7810.0, "kg/m^3", "ρ, density", gt=0)


def _alumina() -> SpecimenMaterial:
    """An alumina (Al2O3) ball, the usual counter-body of ISO 20808."""
    return SpecimenMaterial(
        name="Al2O3", youngs_modulus=3.7e11, poisson=0.22, hardness=1.5e10, density=3950.0
    )


class PlannedTest(Configuration):
    """The test as planned: load, speed, distance and the environment."""

    load: float = quantity(5.0, "N", "F, normal load", gt=0)
    speed: float = quantity(0.1, "m/s", "v, sliding speed (mean, reciprocating)", gt=0)
    distance: float = quantity(100.0, "m", "L, sliding distance planned", gt=0)
    lubricant: Text = Field(default="none", description=N_("lubricant"))
    temperature: float = quantity(23.0, "degC", "ambient temperature", gt=-273.15)
    humidity: float = quantity(50.0, "%", "relative humidity", ge=0, le=100)


class TribometerAccuracy(Configuration):
    """Limits of error of a tribometer's measurements (GUM type B, rectangular)."""

    load: float = quantity(0.01, "1", "normal load, relative limit of error", ge=0)
    friction_force: float = quantity(0.01, "1", "friction force, relative limit of error", ge=0)
    length: float = quantity(1e-5, "m", "track radius or stroke length, limit of error", ge=0)
    scar: float = quantity(5e-6, "m", "wear scar diameter under the microscope, limit", ge=0)
    height: float = quantity(1e-6, "m", "pin's height loss, limit of error", ge=0)
    balance_resolution: float = quantity(1e-8, "kg", "balance's resolution (0.01 mg)", ge=0)
    density: float = quantity(20.0, "kg/m^3", "ρ of the specimens, limit of error", ge=0)
    profile_height: float = quantity(
        0.02, "1", "profilometer's heights across the track, relative limit", ge=0
    )


class TribometerConfig(Configuration):
    """What both tribometers share: the counter-body (pin or ball) and its geometry, the
    materials, the test plan, the accuracy."""

    tip: Literal["ball", "flat_pin"] = Field(
        default="ball",
        description=N_("the counter-body: a ball or a pin with a flat end"),
    )
    tip_diameter: float = quantity(
        6e-3, "m", "diameter of the ball, or of the pin's flat end", gt=0
    )
    pin: SpecimenMaterial = Field(default_factory=_alumina)
    disc: SpecimenMaterial = SpecimenMaterial()
    plan: PlannedTest = PlannedTest()
    accuracy: TribometerAccuracy = TribometerAccuracy()


class PinOnDiscConfig(TribometerConfig):
    track_radius: float = quantity(0.01, "m", "R, radius of the wear track on the disc", gt=0)


class ReciprocatingConfig(TribometerConfig):
    stroke_length: float = quantity(0.01, "m", "S, stroke length (one way, half a cycle)", gt=0)
    frequency: float = quantity(5.0, "Hz", "f, strokes' frequency (cycles per second)", gt=0)


StandConfig = (
    Smts2Config
    | SlideBearingConfig
    | MtosConfig
    | ProfilometerConfig
    | PinOnDiscConfig
    | ReciprocatingConfig
)

# --- channels -------------------------------------------------------------------------

MEASUREMENTS = "measurements"
"""The group of single measurements in every stand (latest value counts)."""


def _c(
    name: str,
    unit: UnitSymbol,
    long_name: str,
    limit: Limit | None = None,
    order: Order = Order.ANY,
    unit_from: str | None = None,
) -> Channel:
    return Channel(
        name=name,
        unit=unit,
        long_name=long_name,
        limit=limit or Limit(),
        order=order,
        unit_from=unit_from,
    )


_TIME = _c("time", "s", "time since the start of the run", Limit(low=0), Order.INCREASING)

SMTS2_GROUPS = (
    ChannelGroup(
        name="friction",
        long_name=N_("friction record (SMTs-2 recorder)"),
        aligned=True,
        signals=("friction_moment",),
        axis="time",
        channels=(
            _TIME,
            _c("load", "N", "N, normal load on the pin", Limit(low=190.0, high=5250.0)),
            _c(
                "speed",
                "rpm",
                "disc speed",
                Limit(nominal=(300.0, 500.0, 1000.0), tolerance=0.10),
            ),
            _c("friction_moment", "N*m", "M_tr, friction moment", Limit(low=0.0, high=15.0)),
            _c(
                "revolutions",
                "100 rev",
                "revolution counter (hundreds of revolutions)",
                Limit(low=0.0),
                Order.NON_DECREASING,
            ),
        ),
    ),
    ChannelGroup(
        name=MEASUREMENTS,
        long_name=N_("weighings and the disc's roughness"),
        aligned=False,
        channels=(
            _c(
                "pin_mass_before",
                "g",
                "m1, pin mass before the test (2.9)",
                Limit(low=0, high=1000),
            ),
            _c("pin_mass_after", "g", "m2, pin mass after the test (2.9)", Limit(low=0, high=1000)),
            _c(
                "disc_ra",
                "um",
                "Ra of the disc, from the profilometer (2.6)",
                Limit(low=0, high=100),
            ),
        ),
    ),
)

SLIDE_BEARING_GROUPS = (
    ChannelGroup(
        name="rows",
        long_name=N_("one row of table 3.1 per position of the loader limb"),
        aligned=True,
        signals=("p3", "p1", "p2", "p4", "p5"),  # p3: the middle manometer, z = 0
        axis="limb_angle",
        channels=(
            _c("limb_angle", "deg", "φ_limb, loader limb angle", Limit(low=-360, high=720)),
            *(
                _c(f"p{k}", "at", long_name, Limit(low=-1.0, high=100.0), unit_from="gauge_unit")
                for k, long_name in enumerate(
                    (
                        N_("gauge pressure at manometer 1"),
                        N_("gauge pressure at manometer 2"),
                        N_("gauge pressure at manometer 3"),
                        N_("gauge pressure at manometer 4"),
                        N_("gauge pressure at manometer 5"),
                    ),
                    start=1,
                )
            ),
            _c("x", "div", "X, displacement gauge reading"),
            _c("y", "div", "Y, displacement gauge reading"),
            _c("t1", "degC", "t1, oil temperature at the inlet", Limit(low=-20, high=200)),
            _c("t2", "degC", "t2, oil temperature at the outlet", Limit(low=-20, high=200)),
        ),
    ),
    ChannelGroup(
        name=MEASUREMENTS,
        long_name=N_("zero readings, the end of the load zone, the load"),
        aligned=False,
        channels=(
            _c("load_zone_end", "deg", "φ_k, limb angle at the end of the load zone (3.20)"),
            _c("x_zero", "div", "X_set, displacement gauge zero (3.16)"),
            _c("y_zero", "div", "Y_set, displacement gauge zero (3.16)"),
            _c("loader_scale", "mm", "loader scale reading (16.2 N/mm)", Limit(low=0, high=1000)),
        ),
    ),
)

MTOS_GROUPS = (
    ChannelGroup(
        name="steps",
        long_name=N_("one row of tables 4.1-4.3 per load step"),
        aligned=True,
        signals=("indicator",),
        axis="load",
        channels=(
            _c("load", "N", "N, load from the dynamometer", Limit(low=0.0, high=10_000.0)),
            _c(
                "indicator",
                "mm",
                "Δl, friction indicator reading (4.13)",
                Limit(low=0.0, high=10.0),
            ),
            _c("x", "um", "X, displacement sensor"),
            _c("y", "um", "Y, displacement sensor"),
            *(
                _c(f"t{k}", "degC", long_name, Limit(low=-20, high=200))
                for k, long_name in enumerate(
                    (
                        N_("t1, oil temperature at the inlet"),
                        N_("t2, oil temperature at the outlet"),
                        N_("t3, oil temperature near the film, loaded zone"),
                        N_("t4, oil temperature near the film, loaded zone"),
                        N_("t5, oil temperature near the film, loaded zone"),
                    ),
                    start=1,
                )
            ),
            _c(
                "regime",
                "code",
                "lubrication: 1 fluid film (exp. 1), 2 mixed (exp. 2), 3 boundary (exp. 3)",
                Limit(nominal=(1.0, 2.0, 3.0)),
            ),
        ),
    ),
    ChannelGroup(
        name=MEASUREMENTS,
        long_name=N_("zero readings of the displacement sensors"),
        aligned=False,
        channels=(
            _c("x_zero", "um", "X_set, sensor zero (4.11)"),
            _c("y_zero", "um", "Y_set, sensor zero (4.11)"),
        ),
    ),
)

PROFILOMETER_GROUPS = (
    ChannelGroup(
        name="profile",
        long_name=N_("profile trace y(x)"),
        aligned=True,
        signals=("y",),
        axis="x",
        channels=(
            _c(
                "x",
                "mm",
                "x, position along the trace",
                Limit(low=0.0, high=100.0),
                Order.INCREASING,
            ),
            _c("y", "um", "y, profile height", Limit(low=-1000.0, high=1000.0)),
        ),
    ),
    ChannelGroup(
        name=MEASUREMENTS,
        long_name=N_("instrument settings of the trace"),
        aligned=False,
        channels=(
            _c("base_length", "mm", "l, base length", Limit(low=0.01, high=100.0)),
            _c(
                "subrange",
                "um",
                "upper limit of the Ra sub-range (1.14)",
                Limit(nominal=(0.4, 3.2, 12.5)),
            ),
            _c("rz_instrument", "um", "Rz1, the profilometer's reading (1.20)", Limit(low=0.0)),
            _c("rmax_instrument", "um", "Rmax1, the profilometer's reading (1.20)", Limit(low=0.0)),
            _c("ra_instrument", "um", "Ra1, the profilometer's reading (1.20)", Limit(low=0.0)),
        ),
    ),
)


def _friction_group(*extra: Channel) -> ChannelGroup:
    """The friction record of a tribometer as its software exports it."""
    return ChannelGroup(
        name="friction",
        long_name=N_("friction record of the tribometer"),
        aligned=True,
        signals=("friction_coefficient", "friction_force"),
        axis="time",
        required=(("time", "friction_coefficient"), ("time", "friction_force", "normal_load")),
        channels=(
            _TIME,
            _c("normal_load", "N", "F_N, normal load", Limit(low=0.0, high=2000.0)),
            _c("friction_force", "N", "F_t, friction force", Limit(low=-2000.0, high=2000.0)),
            _c("friction_coefficient", "1", "μ, friction coefficient", Limit(low=-5.0, high=5.0)),
            _c("distance", "m", "s, sliding distance", Limit(low=0.0), Order.NON_DECREASING),
            _c("laps", "1", "laps (cycles) run", Limit(low=0.0), Order.NON_DECREASING),
            *extra,
            _c(
                "step",
                "1",
                "step of the test's recipe (a speed or load sweep)",
                Limit(low=0, high=100000, integer=True),
                Order.NON_DECREASING,
            ),
            _c(
                "rotational_speed",
                "rpm",
                "n, rotational speed of the disc",
                Limit(low=0.0, high=100000.0),
            ),
            _c("sliding_speed", "m/s", "v, sliding speed", Limit(low=0.0, high=100.0)),
            _c("track_radius", "m", "R, radius of the track", Limit(low=0.0, high=1.0)),
            _c("temperature", "degC", "temperature of the contact", Limit(low=-100, high=1000)),
            _c(
                "wear_depth",
                "um",
                "wear depth, the instrument's displacement sensor",
                Limit(low=-5000, high=5000),
            ),
        ),
    )


_WEAR_TRACK = ChannelGroup(
    name="wear_track",
    long_name=N_("profiles across the wear track"),
    aligned=True,
    signals=("z",),
    axis="x",
    channels=(
        _c("x", "mm", "x, position across the track", Limit(low=-100.0, high=100.0)),
        _c("z", "um", "z, profile height", Limit(low=-1000.0, high=1000.0)),
        _c(
            "trace",
            "1",
            "number of the trace (one per place along the track)",
            Limit(low=0, high=1000, integer=True),
        ),
    ),
)

_TRIBOMETER_MEASUREMENTS = ChannelGroup(
    name=MEASUREMENTS,
    long_name=N_("weighings, densities and the wear scar"),
    aligned=False,
    channels=(
        _c("pin_mass_before", "g", "pin's or ball's mass before the test", Limit(low=0, high=5000)),
        _c("pin_mass_after", "g", "pin's or ball's mass after the test", Limit(low=0, high=5000)),
        _c(
            "disc_mass_before",
            "g",
            "disc's or flat's mass before the test",
            Limit(low=0, high=5000),
        ),
        _c("disc_mass_after", "g", "disc's or flat's mass after the test", Limit(low=0, high=5000)),
        _c("pin_density", "kg/m^3", "density of the pin or ball", Limit(low=100, high=25000)),
        _c("disc_density", "kg/m^3", "density of the disc or flat", Limit(low=100, high=25000)),
        _c(
            "scar_diameter",
            "um",
            "wear scar diameter on the ball or pin (mean of two across)",
            Limit(low=0, high=50000),
        ),
        _c("pin_height_loss", "um", "height lost by the flat-ended pin", Limit(low=0, high=50000)),
    ),
)

PIN_ON_DISC_GROUPS = (_friction_group(), _WEAR_TRACK, _TRIBOMETER_MEASUREMENTS)

RECIPROCATING_GROUPS = (
    _friction_group(
        _c("position", "mm", "x, position along the stroke", Limit(low=-500.0, high=500.0)),
        _c(
            "stroke",
            "1",
            "number of the stroke (two per cycle)",
            Limit(low=0.0),
            Order.NON_DECREASING,
        ),
    ),
    _WEAR_TRACK,
    _TRIBOMETER_MEASUREMENTS,
)


class Stand(BaseModel):
    """A stand kind as the service describes it: configuration, its schema, channels."""

    model_config = ConfigDict(frozen=True)

    kind: StandKind
    title: str
    lab_work: int | None = Field(
        description="the lab manual's work on the stand; none for a commercial tribometer"
    )
    configuration: StandConfig
    groups: tuple[ChannelGroup, ...]

    def group(self, name: str) -> ChannelGroup | None:
        return next((g for g in self.groups if g.name == name), None)

    def for_run(self, configuration: Mapping[str, object]) -> Stand:
        """The stand as a run with this configuration snapshot sees it: the units that the
        configuration sets (the slide-bearing gauges' unit)."""
        groups = configured_groups(self.groups, configuration)
        return self if groups is self.groups else self.model_copy(update={"groups": groups})


@dataclass(frozen=True, slots=True)
class StandDeclaration:
    """One stand kind as every layer reads it: its names (``name`` the stand's, ``work`` the
    title of its lab work, ``aim`` the work's aim: message ids), its configuration model, its
    channel groups (a record group names its live chart's axis and signals), its results
    model (what ``/results`` answers), how people read its results (labels, per-row tables,
    the result that says whether its theory holds) and what a new run of it asks for
    (specimens, test plan: keys of ``labels.PARTICULARS``)."""

    kind: StandKind
    title: str
    lab_work: int | None
    name: str
    work: str
    aim: str
    configuration: type[StandConfig]
    groups: tuple[ChannelGroup, ...]
    results: type[BaseModel]
    labels: Mapping[str, Label]
    specimens: tuple[str, ...]
    plan: tuple[str, ...]
    tables: tuple[RowTable, ...] = ()
    theory_verdict: str | None = None

    def stand(self) -> Stand:
        """The stand with its defaults: the manual's, a common tribometer test's."""
        return Stand(
            kind=self.kind,
            title=self.title,
            lab_work=self.lab_work,
            configuration=self.configuration(),
            groups=self.groups,
        )


DECLARATIONS: dict[StandKind, StandDeclaration] = {
    StandKind.SMTS2: StandDeclaration(
        kind=StandKind.SMTS2,
        title="SMTs-2 friction and wear machine (pin on disc)",
        lab_work=2,
        name=N_("SMTs-2 friction and wear machine"),
        work=N_("Experimental and theoretical study of wear in sliding under dry friction"),
        aim=N_(
            "To study the experimental and theoretical methods of finding the linear wear "
            "intensity in sliding of a pin on a disc."
        ),
        configuration=Smts2Config,
        groups=SMTS2_GROUPS,
        results=Smts2Results,
        labels=labels.SMTS2,
        specimens=("pin", "disc"),
        plan=("mode", "load_N", "speed_rpm", "revolutions"),
        theory_verdict="validity.within_range",
    ),
    StandKind.SLIDE_BEARING: StandDeclaration(
        kind=StandKind.SLIDE_BEARING,
        title="Slide-bearing stand: hydrodynamic pressure",
        lab_work=3,
        name=N_("Slide-bearing stand"),
        work=N_("Experimental and theoretical hydrodynamic pressure diagrams of a slide bearing"),
        aim=N_(
            "To study the experimental and theoretical methods of finding the hydrodynamic "
            "pressure along the angle and the axis of a bearing, and to compare them."
        ),
        configuration=SlideBearingConfig,
        groups=SLIDE_BEARING_GROUPS,
        results=SlideBearingResults,
        labels=labels.SLIDE_BEARING,
        specimens=("journal", "bearing"),
        plan=("loader_scale_mm", "limb_step_deg"),
        tables=labels.SLIDE_BEARING_TABLES,
    ),
    StandKind.MTOS: StandDeclaration(
        kind=StandKind.MTOS,
        title="MTOS stand: friction moment of a journal bearing",
        lab_work=4,
        name=N_("MTOS stand"),
        work=N_("Friction in slide bearings"),
        aim=N_(
            "To study the experimental and theoretical methods of finding the friction "
            "coefficient of a slide bearing in fluid, mixed and boundary lubrication."
        ),
        configuration=MtosConfig,
        groups=MTOS_GROUPS,
        results=MtosResults,
        labels=labels.MTOS,
        specimens=("journal", "bush"),
        plan=("loads_fluid", "loads_mixed", "loads_boundary"),
        tables=labels.MTOS_TABLES,
    ),
    StandKind.PROFILOMETER: StandDeclaration(
        kind=StandKind.PROFILOMETER,
        title="ABRIS-PM7 profilometer: roughness of a run-in surface",
        lab_work=1,
        name=N_("ABRIS-PM7 profilometer"),
        work=N_(
            "Experimental and theoretical determination of the parameters of equilibrium roughness"
        ),
        aim=N_(
            "To study the equipment and the methods of measuring and computing the roughness "
            "parameters of a run-in surface."
        ),
        configuration=ProfilometerConfig,
        groups=PROFILOMETER_GROUPS,
        results=ProfilometerResults,
        labels=labels.PROFILOMETER,
        specimens=("surface",),
        plan=("ra_um", "base_length_mm"),
        tables=labels.PROFILOMETER_TABLES,
    ),
    StandKind.PIN_ON_DISC: StandDeclaration(
        kind=StandKind.PIN_ON_DISC,
        title="Pin- or ball-on-disc tribometer (ASTM G99, ISO 20808)",
        lab_work=None,
        name=N_("Pin- or ball-on-disc tribometer"),
        work=N_("Friction and wear of a ball or pin on a disc (ASTM G99, ISO 20808)"),
        aim=N_(
            "To find the friction coefficient, its running-in and the specific wear rates of a "
            "ball or pin sliding on a rotating disc."
        ),
        configuration=PinOnDiscConfig,
        groups=PIN_ON_DISC_GROUPS,
        results=PinOnDiscResults,
        labels=labels.PIN_ON_DISC,
        specimens=("ball", "disc"),
        plan=("load_N", "laps"),
        tables=labels.PIN_ON_DISC_TABLES,
    ),
    StandKind.RECIPROCATING: StandDeclaration(
        kind=StandKind.RECIPROCATING,
        title="Reciprocating tribometer (ASTM G133)",
        lab_work=None,
        name=N_("Reciprocating tribometer"),
        work=N_("Friction and wear in reciprocating sliding (ASTM G133)"),
        aim=N_(
            "To find the friction coefficient, its running-in and the specific wear rates of a "
            "ball sliding back and forth on a flat."
        ),
        configuration=ReciprocatingConfig,
        groups=RECIPROCATING_GROUPS,
        results=ReciprocatingResults,
        labels=labels.RECIPROCATING,
        specimens=("ball", "disc"),
        plan=("load_N", "laps"),
        tables=labels.RECIPROCATING_TABLES,
    ),
}
"""Every stand kind, declared once; a new kind is its configuration, channels and labels, its
results module (in :mod:`schemas.results`) and one entry here. ``tests/test_stand_kinds.py``
checks that every layer (analysis, reports, rigsim) registers every kind."""


def default_stands() -> dict[StandKind, Stand]:
    """The stands with their defaults: the manual's, a common tribometer test's."""
    return {kind: declared.stand() for kind, declared in DECLARATIONS.items()}


def theory_outside(kind: StandKind, values: Mapping[str, object]) -> bool:
    """Whether the stand's theory is outside its range for a run: ``values`` holds the key
    results (``{"validity.within_range": 0.0}``) or the results payload's values. Every
    theoretical value shown (runs list, run page, console, report) carries this verdict."""
    path = DECLARATIONS[kind].theory_verdict
    if path is None:
        return False
    found: object = values.get(path)
    if found is None:  # the payload's values: walk the path
        node: object = values
        for part in path.split("."):
            node = node.get(part) if isinstance(node, Mapping) else None
        found = node
    return found is not None and not bool(found)


def configure_stands(
    overrides: dict[str, dict[str, object]] | None = None,
) -> dict[StandKind, Stand]:
    """The stands with a lab's overrides of their configurations (e.g. from a file).

    ``overrides`` maps a stand kind to the fields to change; every value is checked by the
    stand's configuration schema, so a wrong unit or a negative clearance fails here.
    """
    stands = default_stands()
    for kind_name, fields in (overrides or {}).items():
        kind = StandKind(kind_name)
        stand = stands[kind]
        merged = with_overrides(stand.configuration, fields)
        stands[kind] = stand.model_copy(update={"configuration": merged}).for_run(
            merged.model_dump()
        )
    return stands


def with_overrides(config: StandConfig, fields: dict[str, object]) -> StandConfig:
    """A configuration with some fields replaced, validated (nested models merge)."""
    data = config.model_dump()
    _merge(data, fields)
    return type(config).model_validate(data)


def _merge(into: dict[str, object], update: dict[str, object]) -> None:
    for key, value in update.items():
        current = into.get(key)
        if isinstance(current, dict) and isinstance(value, dict):
            _merge(current, value)
        else:
            into[key] = value
