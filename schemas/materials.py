"""The materials test specimens are commonly made of, with the properties the analyses use:
a run's specimen names its material (``specimen = {ball = "Si3N4", disc = "brass"}``) and
the theory takes that material's properties, unless the run's configuration gives them
(``configuration.pin``, ``configuration.disc``).

A stand asks for the properties of its own specimen model (:func:`properties`): the
tribometers E, ν, HV and ρ (``SpecimenMaterial``), the SMTs-2's pin E, μ, HB, σ_T, σ_B, δ
and ρ (``PinMaterial``, the manual's (2.1), (2.10)). A material the table holds without
one of them gives that stand nothing, as a name the table does not hold: the results ask
for the properties and borrow no other material's. A specimen's own certificate wins: give
its values in the configuration.

Sources: typical values of the grades (the producers' data sheets and handbooks: ASM
Handbook vol. 1 and 2 for the metals, the ceramics' producers for Al2O3, Si3N4, WC-Co); the
steels' σ_T, σ_B, HB and δ are the manual's table 2.2 (lab work 2), St3sp's E and ρ its
item 18 and (2.10); each other value's source is beside it.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any, TypeVar

from schemas.stands import DiscMaterial, PinMaterial, SpecimenMaterial

_GPA = 1e9
_MPA = 1e6
_KGF_MM2 = 9.80665 * _MPA

Model = TypeVar("Model", bound=SpecimenMaterial | PinMaterial | DiscMaterial)


@dataclass(frozen=True, slots=True)
class Material:
    """A material's properties in SI units (Pa, kg/m³; δ as a fraction); None where the
    table has no sourced value."""

    name: str
    youngs_modulus: float
    poisson: float
    density: float | None = None
    vickers: float | None = None  # HV
    brinell: float | None = None  # HB
    yield_strength: float | None = None  # σ_T
    tensile_strength: float | None = None  # σ_B
    elongation: float | None = None  # δ/100


def _m(name: str, e_gpa: float, nu: float, hv_gpa: float, rho: float) -> Material:
    return Material(name, e_gpa * _GPA, nu, density=rho, vickers=hv_gpa * _GPA)


def _steel(material: Material, sigma_t: float, sigma_b: float, hb: float, delta: float) -> Material:
    """``material`` with its strength from the manual's table 2.2 (MPa, MPa, MPa, %)."""
    return Material(
        **{s: getattr(material, s) for s in Material.__slots__}
        | {
            "yield_strength": sigma_t * _MPA,
            "tensile_strength": sigma_b * _MPA,
            "brinell": hb * _MPA,
            "elongation": delta / 100.0,
        }
    )


#: The table: a material's name -> its properties.
MATERIALS: dict[str, Material] = {
    m.name: m
    for m in (
        _m("100Cr6", 210.0, 0.30, 7.5, 7810.0),  # bearing steel, hardened (AISI 52100)
        _m("Al2O3", 370.0, 0.22, 15.0, 3950.0),  # alumina, 99.5 %
        _m("Si3N4", 310.0, 0.27, 15.0, 3200.0),  # silicon nitride, bearing grade
        _m("ZrO2", 205.0, 0.31, 12.0, 6050.0),  # zirconia, yttria-stabilised
        _m("WC-Co", 620.0, 0.24, 16.0, 14900.0),  # tungsten carbide, 6 % cobalt
        _m("AISI 304", 193.0, 0.29, 2.0, 8000.0),  # austenitic stainless steel, annealed
        # carbon steel 45 (AISI 1045): E, ν, HV, ρ typical; σ_T, σ_B, HB, δ table 2.2
        _steel(_m("C45", 210.0, 0.30, 2.0, 7850.0), 245.0, 470.0, 1700.0, 17.0),
        _m("Ti6Al4V", 114.0, 0.34, 3.4, 4430.0),  # titanium alloy, grade 5
        _m("CuZn37", 110.0, 0.34, 1.0, 8440.0),  # brass, half-hard
        _m("CuSn8", 115.0, 0.34, 1.2, 8800.0),  # tin bronze
        _m("AlSi12", 75.0, 0.33, 0.9, 2650.0),  # cast aluminium alloy
        _m("PTFE", 0.5, 0.46, 0.05, 2200.0),  # polytetrafluoroethylene
        # the SMTs-2's pin steel VSt3ps as delivered: E = 2.13·10⁵ MPa, μ = 0.3 (item 18),
        # ρ = 7800 kg/m³ (2.10), σ_T, σ_B, HB, δ table 2.2 (the stand's default pin)
        _steel(Material("St3sp", 2.13e11, 0.30, density=7800.0), 225.0, 420.0, 1240.0, 23.0),
        # steel 20 as delivered: E 2.13·10⁵ MPa, ρ 7859 kg/m³ (Marochnik stalei i splavov,
        # 2003); σ_T, σ_B, HB, δ table 2.2
        _steel(Material("Steel 20", 2.13e11, 0.30, density=7859.0), 175.0, 350.0, 1300.0, 28.0),
        # leaded brass LS59-1 (CuZn40Pb2), annealed: E = 1.05·10⁵ MPa, ρ = 8500 kg/m³
        # (Marochnik stalei i splavov, 2003); σ_B = 400 MPa, σ_T = 140 MPa, δ = 45 %,
        # HB 90 kgf/mm² = 883 MPa (Lakhtin, Leont'eva, Materialovedenie, 1990, the table of
        # wrought brasses), HV the same (HV ≈ HB in ASTM E140's table for brass); μ = 0.34
        # as the other brasses (ASM Handbook vol. 2)
        Material(
            "CuZn40Pb2",
            1.05e11,
            0.34,
            density=8500.0,
            vickers=90.0 * _KGF_MM2,
            brinell=90.0 * _KGF_MM2,
            yield_strength=140.0 * _MPA,
            tensile_strength=400.0 * _MPA,
            elongation=0.45,
        ),
        # the SMTs-2's disc, high-speed steel R9 hardened: the stand's passport E = 2.2·10⁵
        # MPa, μ = 0.3, HB = 6400 MPa (its hardness and ρ in other scales not sourced)
        Material("R9", 2.2e11, 0.30, brinell=6400.0 * _MPA),
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
    "steel 45": "C45",
    "ti-6al-4v": "Ti6Al4V",
    "вт6": "Ti6Al4V",
    "brass": "CuZn40Pb2",
    "латунь": "CuZn40Pb2",
    "лс59-1": "CuZn40Pb2",
    "ls59-1": "CuZn40Pb2",
    "cw617n": "CuZn40Pb2",
    "л63": "CuZn37",
    "cw508l": "CuZn37",
    "bronze": "CuSn8",
    "бронза": "CuSn8",
    "teflon": "PTFE",
    "фторопласт": "PTFE",
    "ст3сп": "St3sp",
    "вст3пс": "St3sp",
    "vst3ps": "St3sp",
    "st3ps": "St3sp",
    "сталь 20": "Steel 20",
    "р9": "R9",
}


def _key(name: str) -> str:
    return re.sub(r"\s+", " ", name.strip().casefold())


_BY_KEY = {_key(n): m for n, m in MATERIALS.items()} | {
    _key(a): MATERIALS[n] for a, n in ALIASES.items()
}

#: Which of the table's hardnesses a specimen model's ``hardness`` is.
_HARDNESS: dict[type, str] = {
    SpecimenMaterial: "vickers",
    PinMaterial: "brinell",
    DiscMaterial: "brinell",
}


def material_named(name: str) -> Material | None:
    """The table's material of that name (or one of its other names; case and blanks set
    aside), None when the table does not hold it."""
    return _BY_KEY.get(_key(name))


def properties(name: str, model: type[Model]) -> Model | None:
    """The named material as a stand's specimen ``model`` (its hardness in the model's
    scale), None when the table does not hold it or holds it without one of the model's
    properties."""
    material = material_named(name)
    if material is None:
        return None
    values: dict[str, Any] = {}
    for field in model.model_fields:
        source = _HARDNESS[model] if field == "hardness" else field
        value = getattr(material, source)
        if value is None:
            return None
        values[field] = value
    return model(**values)
