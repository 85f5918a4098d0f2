"""A tribometer run's specimens' materials: the names its specimen gives (``pin`` or
``ball``, ``disc`` or ``flat``) looked up in the materials table (:mod:`schemas.materials`)
where the run's configuration does not give the properties itself; a name the table does
not hold borrows no other material's properties (the results ask for them)."""

from __future__ import annotations

from dataclasses import dataclass, field

from schemas.materials import material_named
from schemas.messages import N_
from schemas.runs import Run
from schemas.stands import PinOnDiscConfig, ReciprocatingConfig

Config = PinOnDiscConfig | ReciprocatingConfig

#: The specimen's keys that name the pin's (ball's) and the disc's (flat's) material.
SPECIMEN_KEYS = {"pin": ("pin", "ball"), "disc": ("disc", "flat")}

NOTE_TABLE = N_(
    "the specimens' properties (E, ν, H, ρ) are the materials table's for the materials the "
    "specimen names"
)
PENDING_UNKNOWN = N_(
    "the specimen names a material the materials table does not hold: give its properties "
    "(E, ν, H, ρ) in the configuration's pin or disc; the Hertz contact and the wear by mass "
    "wait for them"
)


@dataclass(frozen=True, slots=True)
class Specimens:
    """The configuration with the named materials' properties, and the roles (``pin``,
    ``disc``) whose named material is unknown."""

    config: Config
    unknown: frozenset[str] = frozenset()
    notes: list[str] = field(default_factory=list)
    pending: list[str] = field(default_factory=list)


def specimen_materials(run: Run, config: Config) -> Specimens:
    """The materials the run's specimen names, where its configuration leaves the pin's or
    the disc's properties to the stand's default (nothing changes for a run that did not
    record where its configuration came from)."""
    given = run.configuration_given
    if given is None:
        return Specimens(config)
    update, unknown = {}, set()
    for role, keys in SPECIMEN_KEYS.items():
        if any(path.startswith(f"{role}.") for path in given):
            continue  # the run gives the properties itself
        named = next(
            (v.strip() for k in keys if isinstance(v := run.specimen.get(k), str) and v.strip()),
            None,
        )
        if named is None:
            continue
        found = material_named(named)
        if found is None:
            unknown.add(role)
        else:
            update[role] = found
    return Specimens(
        config.model_copy(update=update),
        frozenset(unknown),
        [NOTE_TABLE] if update else [],
        [PENDING_UNKNOWN] if unknown else [],
    )
