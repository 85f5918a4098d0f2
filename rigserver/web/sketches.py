"""The run page's sketches: for each sketch item of the run's lab's report list, the
students' latest upload and the earlier ones it replaced (every version stays readable)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from rigserver.reports.i18n import Messages
from rigserver.reports.kits import KITS
from schemas.sketches import SKETCH_MAX_BYTES, Sketch
from schemas.stands import StandKind

#: The largest sketch, as the page says it (MiB).
SKETCH_MAX_MIB = SKETCH_MAX_BYTES >> 20


@dataclass(frozen=True, slots=True)
class SketchItem:
    """One sketch item: its number and heading, its versions uploaded, the latest last."""

    number: int
    heading: str
    versions: Sequence[Sketch]

    @property
    def latest(self) -> Sketch | None:
        return self.versions[-1] if self.versions else None


def sketch_items(t: Messages, stand: StandKind, sketches: Sequence[Sketch]) -> list[SketchItem]:
    """The sketch items of ``stand``'s lab, each with its versions among ``sketches``."""
    return [
        SketchItem(
            item.number,
            t.gettext(item.heading),
            sorted((s for s in sketches if s.item == item.number), key=lambda s: s.version),
        )
        for item in KITS[stand].contents.sketches()
    ]
