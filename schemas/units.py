"""The closed list of units that channels and results may carry, each with its factor to SI.

Raw values are stored as measured (divisions, technical atmospheres, mm of the loader
scale); each analysis converts what it reads by the manual's own formulas, and the factor
serves where a value changes unit (the new-run form's display units, the X3P export). A unit
not in this list cannot be declared, so a typo in a stand declaration fails when the module
is imported in tests.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

UnitSymbol = Literal[
    "1",
    "s",
    "min",
    "N",
    "N*m",
    "kg",
    "g",
    "mg",
    "m",
    "mm",
    "um",
    "rad",
    "deg",
    "rev",
    "100 rev",
    "rpm",
    "rad/s",
    "Pa",
    "MPa",
    "at",
    "atm",
    "Pa*s",
    "degC",
    "1/degC",
    "kg/m^3",
    "N/mm",
    "N/m",
    "m^2",
    "mm^2",
    "m^3",
    "mm^3",
    "m^2/N",
    "mm^3/(N*m)",
    "1/m",
    "m/N",
    "m/N^(2/3)",
    "N*m/rad",
    "N*m*s/rad",
    "drops/min",
    "div",
    "code",
    "%",
    "Hz",
    "m/s",
    "GPa",
]


@dataclass(frozen=True, slots=True)
class Unit:
    """A unit: its symbol, the SI unit it converts to, and the factor (value_si = factor·value).

    Temperatures in °C are kept in °C (the manual's viscosity law takes °C), so ``degC``
    converts to itself.
    """

    symbol: UnitSymbol
    si: UnitSymbol
    factor: float
    long_name: str


UNITS: dict[str, Unit] = {
    u.symbol: u
    for u in (
        Unit("1", "1", 1.0, "dimensionless"),
        Unit("s", "s", 1.0, "second"),
        Unit("min", "s", 60.0, "minute"),
        Unit("N", "N", 1.0, "newton"),
        Unit("N*m", "N*m", 1.0, "newton metre"),
        Unit("kg", "kg", 1.0, "kilogram"),
        Unit("g", "kg", 1e-3, "gram"),
        Unit("mg", "kg", 1e-6, "milligram"),
        Unit("m", "m", 1.0, "metre"),
        Unit("mm", "m", 1e-3, "millimetre"),
        Unit("um", "m", 1e-6, "micrometre"),
        Unit("rad", "rad", 1.0, "radian"),
        Unit("deg", "rad", float(np.pi / 180.0), "degree"),
        Unit("rev", "rev", 1.0, "revolution"),
        Unit("100 rev", "rev", 100.0, "hundreds of revolutions (SMTs-2 counter)"),
        Unit("rpm", "rad/s", float(2.0 * np.pi / 60.0), "revolutions per minute"),
        Unit("rad/s", "rad/s", 1.0, "radian per second"),
        Unit("Pa", "Pa", 1.0, "pascal"),
        Unit("MPa", "Pa", 1e6, "megapascal"),
        Unit("at", "Pa", 98_066.5, "technical atmosphere (kgf/cm²), the usual gauge unit"),
        Unit("atm", "Pa", 101_325.0, "standard atmosphere"),
        Unit("Pa*s", "Pa*s", 1.0, "pascal second"),
        Unit("degC", "degC", 1.0, "degree Celsius"),
        Unit("1/degC", "1/degC", 1.0, "per degree Celsius"),
        Unit("kg/m^3", "kg/m^3", 1.0, "kilogram per cubic metre"),
        Unit("N/mm", "N/m", 1e3, "newton per millimetre"),
        Unit("N/m", "N/m", 1.0, "newton per metre"),
        Unit("m^2", "m^2", 1.0, "square metre"),
        Unit("mm^2", "m^2", 1e-6, "square millimetre"),
        Unit("m^3", "m^3", 1.0, "cubic metre"),
        Unit("mm^3", "m^3", 1e-9, "cubic millimetre"),
        Unit("m^2/N", "m^2/N", 1.0, "cubic metre per newton metre (specific wear rate)"),
        Unit("mm^3/(N*m)", "m^2/N", 1e-9, "cubic millimetre per newton metre (ASTM G99)"),
        Unit("1/m", "1/m", 1.0, "per metre"),
        Unit("m/N", "m/N", 1.0, "metre per newton (compliance)"),
        Unit("m/N^(2/3)", "m/N^(2/3)", 1.0, "contact compliance of a ball-screw pair"),
        Unit("N*m/rad", "N*m/rad", 1.0, "newton metre per radian (joint stiffness)"),
        Unit("N*m*s/rad", "N*m*s/rad", 1.0, "newton metre second per radian (joint damping)"),
        Unit("drops/min", "drops/min", 1.0, "drops of oil per minute"),
        Unit("div", "div", 1.0, "scale divisions of an instrument (calibrated per stand)"),
        Unit("code", "code", 1.0, "an integer code from a declared list"),
        Unit("%", "1", 1e-2, "percent"),
        Unit("Hz", "Hz", 1.0, "hertz (strokes of a reciprocating tribometer)"),
        Unit("m/s", "m/s", 1.0, "metre per second (sliding speed)"),
        Unit("GPa", "Pa", 1e9, "gigapascal"),
    )
}
