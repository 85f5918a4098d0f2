"""What the API's documentation offers as examples of the bodies it takes: a readings
batch (npz), a run's archive (.eln) and a sketch of each image type, each served at its
path below ``/docs/examples``."""

from __future__ import annotations

import io
import tempfile
from collections.abc import Mapping
from contextlib import ExitStack
from datetime import UTC, datetime
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
from PIL import Image, ImageDraw

from rigserver.analysis import analyse
from rigserver.api.report_jobs import FileReadings
from rigserver.reports.eln import Publisher, RunPart, write_run_archive
from rigserver.storage.runfile import write_file
from schemas.runs import Run, RunState
from schemas.stands import MEASUREMENTS, StandKind, default_stands

#: Where the documentation serves an example sketch of each type (:func:`example_sketch`).
SKETCH_EXAMPLES = {
    "image/png": "/docs/examples/sketch.png",
    "image/jpeg": "/docs/examples/sketch.jpg",
}


@lru_cache(maxsize=2)
def example_sketch(media_type: str) -> bytes:
    """A sketch of ``media_type`` for the documentation: a pin on a disc, seen from the
    side, drawn in ink on white."""
    image = Image.new("RGB", (320, 200), "white")
    draw = ImageDraw.Draw(image)
    draw.rectangle((40, 140, 280, 170), outline="black", width=3)  # the disc
    draw.rectangle((145, 40, 175, 140), outline="black", width=3)  # the pin
    draw.line((160, 10, 160, 40), fill="black", width=3)  # the load
    out = io.BytesIO()
    image.save(out, {"image/png": "PNG", "image/jpeg": "JPEG"}[media_type])
    return out.getvalue()


#: Where the OpenAPI document's example archive is served (rigserver.api.routes.api_docs).
ELN_EXAMPLE = "/docs/examples/run.eln"


@lru_cache(maxsize=1)
def example_archive() -> bytes:
    """The archive of a small profilometer run made up here (a sine trace of 1 µm amplitude
    and 0.1 mm pitch over the 0.8 mm base length, sampled every 0.5 µm), the import's
    example in the OpenAPI document."""
    made = datetime(2026, 11, 22, 11, 40, 26, tzinfo=UTC)
    stand = default_stands()[StandKind.PROFILOMETER]
    x = np.linspace(0.0, 0.8, 1601)
    trace = {"x": x, "y": np.sin(2.0 * np.pi * x / 0.1)}
    weighed = {"base_length": np.array([0.8]), "subrange": np.array([3.2])}
    run = Run(
        id="20261122T114026Z-0e1ec0de",
        stand=StandKind.PROFILOMETER,
        state=RunState.FINISHED,
        operator="Ivanova",
        title="Run-in surface, example",
        specimen={"surface": "steel 45, run in"},
        test_plan={"base_length_mm": 0.8},
        configuration=stand.configuration.model_dump(mode="json"),
        created=made,
        ended=made,
        batches=2,
        rows={"profile": len(x), "measurements": 1},
    )
    with tempfile.TemporaryDirectory(prefix="rig-example-") as directory, ExitStack() as stack:
        path = Path(directory) / "run.h5"
        write_file(
            path, run, [("profile", trace, len(x)), (MEASUREMENTS, weighed, 1)], None, final=True
        )
        readings = FileReadings(path, stack)
        part = RunPart(
            run=run,
            stand=stand,
            readings=readings,
            payload=analyse(run, readings).payload,
            run_file=path,
        )
        target = io.BytesIO()
        publisher = Publisher("http://rig.example/")
        write_run_archive(target, part, made=made, publisher=publisher, licence=None)
    return target.getvalue()


#: The binary form of :class:`ReadingBatch`'s example, the request body's example in the
#: OpenAPI document.
NPZ_EXAMPLE = "/docs/examples/readings.npz"


def file_body(examples: Mapping[str, str], name: str, summary: str) -> dict[str, Any]:
    """The ``openapi_extra`` of a route whose body is a file of one of ``examples``' media
    types, each with its example (``name``, ``summary``) served at the path given."""
    return {
        "requestBody": {
            "required": True,
            "content": {
                media_type: {
                    "schema": {"type": "string", "format": "binary"},
                    "examples": {name: {"summary": summary, "externalValue": url}},
                }
                for media_type, url in examples.items()
            },
        }
    }
