"""The finite bearing (3.1) at many relative eccentricities: warm-started and remembered.

The MTOS stand's results solve the Reynolds equation once per load step, and an open run's
results are computed again whenever a step arrives. A stationary bearing without supply
(Ω = μ̄ = 1, δ = 0) depends on χ and a = B/D alone, so each distinct (χ, a) is solved once
and remembered (the results of an open run then cost one solve per new step); the χ not
yet known are solved in ascending order, each one's active-set iteration started from the
ruptured zone of the one before (warm start, ``docs/reynolds.md``) instead of from the
coarse grids. The complementarity problem has one solution and the iteration stops on it
whatever the start, so the figures are those of a cold solve to round-off.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Iterable
from dataclasses import dataclass

from rigserver.core import reynolds

#: (χ, a) pairs remembered, the least recently used forgotten first (two floats each).
REMEMBERED = 8192
#: A warm start from a χ further away than this costs more steps than the coarse grids.
WARM_GAP = 0.15


@dataclass(frozen=True, slots=True)
class FiniteFigures:
    """What a step's results take from the finite bearing, in the scales of (3.6)."""

    load: float
    """|F|, unit μωR⁴/h0²."""
    journal_torque_full_film: float
    """Friction torque on the journal with a full film's shear, unit μωR⁴/h0."""


class FiniteBearingSteps:
    """Solves of (3.1) by (χ, a) on one grid, remembered (thread-safe; the solves run
    unlocked)."""

    def __init__(
        self, size: int = REMEMBERED, *, n_phi: int | None = None, n_z: int | None = None
    ) -> None:
        self._size = size
        self._n_phi, self._n_z = n_phi, n_z  # None: the solver's default grid
        self._known: OrderedDict[tuple[float, float], FiniteFigures] = OrderedDict()
        self._lock = threading.Lock()

    def _get(self, key: tuple[float, float]) -> FiniteFigures | None:
        with self._lock:
            found = self._known.get(key)
            if found is not None:
                self._known.move_to_end(key)
            return found

    def _put(self, key: tuple[float, float], figures: FiniteFigures) -> None:
        with self._lock:
            self._known[key] = figures
            self._known.move_to_end(key)
            while len(self._known) > self._size:
                self._known.popitem(last=False)

    def solve_all(self, chis: Iterable[float], half_width: float) -> None:
        """Solve the χ not known yet, in ascending order, each from the one before."""
        a = float(half_width)
        todo = sorted(x for x in {float(c) for c in chis} if self._get((x, a)) is None)
        previous: reynolds.ReynoldsSolution | None = None
        last = -1.0
        for chi in todo:
            warm = previous if previous is not None and chi - last <= WARM_GAP else None
            previous = self._solve(chi, a, warm)
            last = chi
            self._put((chi, a), _figures(previous))

    def figures(self, *, chi: float, half_width: float) -> FiniteFigures:
        """(3.1) at χ for a = B/D; the remembered figures when this (χ, a) was solved."""
        key = (float(chi), float(half_width))
        found = self._get(key)
        if found is None:
            found = _figures(self._solve(key[0], key[1], None))
            self._put(key, found)
        return found

    def _solve(
        self, chi: float, half_width: float, warm: reynolds.ReynoldsSolution | None
    ) -> reynolds.ReynoldsSolution:
        return reynolds.solve_reynolds(
            chi=chi, half_width=half_width, n_phi=self._n_phi, n_z=self._n_z, warm_start=warm
        )


def _figures(solution: reynolds.ReynoldsSolution) -> FiniteFigures:
    return FiniteFigures(
        load=solution.load, journal_torque_full_film=solution.journal_torque_full_film
    )
