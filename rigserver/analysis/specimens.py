"""A run's specimens' materials: the names its specimen gives (a tribometer's ``pin`` or
``ball``, ``disc`` or ``flat``; the SMTs-2's ``pin``) looked up in the materials table
(:mod:`schemas.materials`) where the run's configuration does not give the properties
itself; a name the table does not hold (or holds without a property the stand's theory
uses) borrows no other material's properties: the results ask for them."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Generic, TypeVar

from pydantic import BaseModel

from schemas.materials import properties
from schemas.messages import N_
from schemas.runs import Run
from schemas.stands import PinMaterial, SpecimenMaterial

Config = TypeVar("Config", bound=BaseModel)


@dataclass(frozen=True, slots=True)
class Roles:
    """A stand's specimens whose materials the table gives: each role (the configuration's
    key, ``pin``, ``disc``) with the specimen's keys that name its material, the model of
    its properties, and the words of the results' note and pending item."""

    keys: dict[str, tuple[str, ...]]
    model: type[SpecimenMaterial] | type[PinMaterial]
    note: str
    pending: str


#: The tribometers' ball (pin) and disc (flat): the Hertz contact and the wear by mass.
TRIBOMETER = Roles(
    keys={"pin": ("pin", "ball"), "disc": ("disc", "flat")},
    model=SpecimenMaterial,
    note=N_(
        "the specimens' properties (E, ν, H, ρ) are the materials table's for the materials "
        "the specimen names"
    ),
    pending=N_(
        "the specimen names a material the materials table does not hold with all of E, ν, "
        "H and ρ: give its properties (E, ν, H, ρ) in the configuration's pin or disc; the "
        "Hertz contact and the wear by mass wait for them"
    ),
)

#: The SMTs-2's pin, the wearing body of (2.1) and the density of (2.10); the disc enters
#: the theory by its radius and its Ra alone.
SMTS2 = Roles(
    keys={"pin": ("pin",)},
    model=PinMaterial,
    note=N_(
        "the pin's properties (E1, μ1, HB1, σ_T, σ_B, e_B, ρ) are the materials table's for "
        "the material the specimen names"
    ),
    pending=N_(
        "the pin names a material the materials table does not hold with all of E1, μ1, HB1, "
        "σ_T, σ_B, e_B and ρ: give them in the configuration as pin.name, "
        "pin.youngs_modulus, pin.poisson, pin.hardness, pin.yield_strength, "
        "pin.tensile_strength, pin.elongation and pin.density; the experimental and the "
        "theoretical wear wait for them"
    ),
)


@dataclass(frozen=True, slots=True)
class Specimens(Generic[Config]):
    """The configuration with the named materials' properties, the roles (``pin``,
    ``disc``) whose properties the table gave, and those whose named material is unknown."""

    config: Config
    found: frozenset[str] = frozenset()
    unknown: frozenset[str] = frozenset()
    notes: list[str] = field(default_factory=list)
    pending: list[str] = field(default_factory=list)


def specimen_materials(run: Run, config: Config, roles: Roles = TRIBOMETER) -> Specimens[Config]:
    """The materials the run's specimen names, where its configuration leaves the roles'
    properties to the stand's default (nothing changes for a run that did not record where
    its configuration came from)."""
    given = run.configuration_given
    if given is None:
        return Specimens(config)
    update, unknown = {}, set()
    for role, keys in roles.keys.items():
        if any(path.startswith(f"{role}.") for path in given):
            continue  # the run gives the properties itself
        named = next(
            (v.strip() for k in keys if isinstance(v := run.specimen.get(k), str) and v.strip()),
            None,
        )
        if named is None:
            continue
        found = properties(named, roles.model)
        if found is None:
            unknown.add(role)
        else:
            update[role] = found
    return Specimens(
        config.model_copy(update=update),
        frozenset(update),
        frozenset(unknown),
        [roles.note] if update else [],
        [roles.pending] if unknown else [],
    )
