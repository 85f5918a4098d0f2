"""The materials a tribometer's specimens are commonly made of, with the properties the
analysis uses (E, ν, H, ρ): a run's specimen names its material (``specimen = {ball =
"Si3N4", disc = "brass"}``) and the theory takes that material's properties, unless the
run's configuration gives them (``configuration.pin``, ``configuration.disc``).

Typical values of the grades named (the producers' data sheets and handbooks: ASM Handbook
vol. 1 and 2 for the metals, the ceramics' producers for Al2O3, Si3N4, WC-Co); a specimen's
own certificate wins: give its values in the configuration. A name the table does not hold
takes no one else's properties: the results ask for them.
"""

from __future__ import annotations

import re

from schemas.stands import SpecimenMaterial

_GPA = 1e9


def _m(name: str, e_gpa: float, nu: float, hv_gpa: float, rho: float) -> SpecimenMaterial:
    return SpecimenMaterial(
        name=name,
        youngs_modulus=e_gpa * _GPA,
        poisson=nu,
        hardness=hv_gpa * _GPA,
        density=rho,
    )


#: The table: a material's name -> its properties (E, GPa; ν; HV, GPa; ρ, kg/m³).
MATERIALS: dict[str, SpecimenMaterial] = {
    m.name: m
    for m in (
        _m("100Cr6", 210.0, 0.30, 7.5, 7810.0),  # bearing steel, hardened (AISI 52100)
        _m("Al2O3", 370.0, 0.22, 15.0, 3950.0),  # alumina, 99.5 %
        _m("Si3N4", 310.0, 0.27, 15.0, 3200.0),  # silicon nitride, bearing grade
        _m("ZrO2", 205.0, 0.31, 12.0, 6050.0),  # zirconia, yttria-stabilised
        _m("WC-Co", 620.0, 0.24, 16.0, 14900.0),  # tungsten carbide, 6 % cobalt
        _m("AISI 304", 193.0, 0.29, 2.0, 8000.0),  # austenitic stainless steel, annealed
        _m("C45", 210.0, 0.30, 2.0, 7850.0),  # carbon steel, normalised (AISI 1045)
        _m("Ti6Al4V", 114.0, 0.34, 3.4, 4430.0),  # titanium alloy, grade 5
        _m("CuZn37", 110.0, 0.34, 1.0, 8440.0),  # brass, half-hard
        _m("CuSn8", 115.0, 0.34, 1.2, 8800.0),  # tin bronze
        _m("AlSi12", 75.0, 0.33, 0.9, 2650.0),  # cast aluminium alloy
        _m("PTFE", 0.5, 0.46, 0.05, 2200.0),  # polytetrafluoroethylene
    )
}

#: Other names of the table's materials (the lab's and the standards' spellings).
ALIASES: dict[str, str] = {
    "aisi 52100": "100Cr6",
    "52100": "100Cr6",
    "шх15": "100Cr6",
    "gcr15": "100Cr6",
    "alumina": "Al2O3",
    "silicon nitride": "Si3N4",
    "zirconia": "ZrO2",
    "tungsten carbide": "WC-Co",
    "wc": "WC-Co",
    "304": "AISI 304",
    "12х18н10т": "AISI 304",
    "aisi 1045": "C45",
    "сталь 45": "C45",
    "ti-6al-4v": "Ti6Al4V",
    "вт6": "Ti6Al4V",
    "brass": "CuZn37",
    "латунь": "CuZn37",
    "bronze": "CuSn8",
    "бронза": "CuSn8",
    "teflon": "PTFE",
    "фторопласт": "PTFE",
}


def _key(name: str) -> str:
    return re.sub(r"\s+", " ", name.strip().casefold())


_BY_KEY = {_key(n): m for n, m in MATERIALS.items()} | {
    _key(a): MATERIALS[n] for a, n in ALIASES.items()
}


def material_named(name: str) -> SpecimenMaterial | None:
    """The table's material of that name (or one of its other names; case and blanks set
    aside), None when the table does not hold it."""
    return _BY_KEY.get(_key(name))
