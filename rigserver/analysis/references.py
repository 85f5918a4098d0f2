"""Profilometer runs that another run names: the roughness of its surfaces, measured.

A run names them in its specimen, ``<role>_profile_run: <run id>`` (roles ``journal`` and
``bush`` on the MTOS stand, ``disc`` on the SMTs-2 for the wear track). The caller gives a
lookup from a run id to that run and its readings (the API gives the store's); each named run
is analysed by the profilometer pipeline.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from rigserver.analysis import profilometer
from rigserver.analysis.readings import Readings
from schemas.results import ProfilometerResults
from schemas.runs import Run
from schemas.stands import StandKind

#: A run id -> the run and its readings, or None when the store has no such run.
RunLookup = Callable[[str], tuple[Run, Readings] | None]
SUFFIX = "_profile_run"


@dataclass(frozen=True)
class Profiles:
    """The referenced profilometer runs' results by role, and why any could not be used."""

    found: dict[str, ProfilometerResults] = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)
    traces: dict[str, Readings] = field(default_factory=dict)
    """The profilometer runs' readings by role (a wear track's cross-section needs them)."""

    def rq(self, role: str) -> float | None:
        found = self.found.get(role)
        return None if found is None else found.rq


def referenced_profiles(run: Run, lookup: RunLookup | None) -> Profiles:
    """The profilometer results of every ``<role>_profile_run`` in the run's specimen."""
    profiles = Profiles()
    for key, value in run.specimen.items():
        if not key.endswith(SUFFIX):
            continue
        role = key.removesuffix(SUFFIX)
        found = lookup(str(value)) if lookup is not None else None
        if found is None:
            profiles.problems.append(f"{key} = {value!r}: no such run in the store")
            continue
        other, readings = found
        if other.stand is not StandKind.PROFILOMETER:
            profiles.problems.append(
                f"{key} = {value!r}: a {other.stand.value} run, not a profilometer run"
            )
            continue
        profiles.traces[role] = readings
        results = profilometer.analyse(other, readings)
        if results.rq is None:
            profiles.problems.append(f"{key} = {value!r}: the profile gives no Rq yet")
            continue
        profiles.found[role] = results
    return profiles
