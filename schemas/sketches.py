"""The students' sketches on a run: an image (PNG or JPEG) uploaded for a sketch item of
their lab's report list (the specimen, the stand's scheme), printed in the report in place
of the frame to draw in; every version kept (what ``/runs/{id}/sketches`` answers)."""

from __future__ import annotations

from datetime import datetime

from pydantic import BaseModel, Field

#: The largest sketch taken, bytes (5 MiB: a phone's photo of a drawing).
SKETCH_MAX_BYTES = 5 << 20
#: The longest side of a sketch taken, pixels.
SKETCH_MAX_SIDE = 8000
#: The most pixels of a sketch taken (checked before decoding: no decompression bomb).
SKETCH_MAX_PIXELS = 40_000_000
#: The image types taken, by their media type.
SKETCH_TYPES = ("image/png", "image/jpeg")


class Sketch(BaseModel):
    """One version of the sketch of one item: the image's type, size in pixels and bytes,
    its SHA-256, who uploaded it (the API key's name) and when."""

    item: int = Field(description="the item's number in the lab's report list")
    version: int = Field(ge=1, description="1 for the first upload of the item, then 2, ...")
    media_type: str = Field(description="image/png or image/jpeg")
    width: int = Field(ge=1, description="pixels")
    height: int = Field(ge=1, description="pixels")
    size: int = Field(ge=1, description="bytes")
    sha256: str
    by: str
    written: datetime


class Sketches(BaseModel):
    """Every version of every sketch of a run, the first first (the latest of each item is
    the one printed)."""

    sketches: list[Sketch]
