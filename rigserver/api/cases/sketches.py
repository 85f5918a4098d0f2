"""The students' sketches: the items of a lab's list that take one, and an upload stored
as the next version, for a key with the run's stand's write scope."""

from __future__ import annotations

from rigserver.api.auth import ApiKey
from rigserver.api.cases.found import load_run
from rigserver.api.cases.notes import author
from rigserver.api.deps import Services, require_write
from rigserver.api.problems import ApiProblem
from rigserver.api.sketch_images import SketchImage
from rigserver.reports.kits import KITS
from schemas.runs import Run
from schemas.sketches import Sketch


def sketch_items(run: Run) -> list[int]:
    """The numbers of the sketch items of the run's lab's report list."""
    return [i.number for i in KITS[run.stand].contents.sketches()]


def sketch_item(run: Run, item: int) -> int:
    """``item`` if it is a sketch item of the run's lab (422 naming the ones that are)."""
    items = sketch_items(run)
    if item not in items:
        raise ApiProblem(
            422,
            "Not a sketch item",
            f"item {item} of the {run.stand.value} lab's report list takes no sketch; its "
            f"sketch items are {', '.join(map(str, items))}",
        )
    return item


def upload_sketch(
    services: Services, run_id: str, item: int, image: SketchImage, caller: ApiKey | None
) -> Sketch:
    """Store ``image`` as the next version of the run's sketch of ``item``, for a key with
    the run's stand's write scope (403 else)."""
    run = load_run(services, run_id)
    sketch_item(run, item)
    key = require_write(caller, run.stand)
    return services.sketches.put(
        run.id, item, image.data, media_type=image.media_type, size=image.size, by=author(key)
    )
