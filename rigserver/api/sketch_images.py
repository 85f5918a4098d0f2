"""A sketch's image checked at the door: PNG or JPEG by its first bytes (a header that says
another type is refused), no larger than :data:`~schemas.sketches.SKETCH_MAX_BYTES`, its
declared size in pixels within the limits before a pixel is decoded (no decompression
bomb), then decoded whole (a damaged image is refused, not stored)."""

from __future__ import annotations

import io
import threading
import warnings
from dataclasses import dataclass

from PIL import Image, UnidentifiedImageError

from rigserver.api.media import media_type
from rigserver.api.problems import ApiProblem
from schemas.sketches import SKETCH_MAX_BYTES, SKETCH_MAX_PIXELS, SKETCH_MAX_SIDE, SKETCH_TYPES

#: The first bytes of each image type taken, and Pillow's name of its format.
MAGIC = {"image/png": (b"\x89PNG\r\n\x1a\n", "PNG"), "image/jpeg": (b"\xff\xd8\xff", "JPEG")}
#: Sketches decoded at once (the others wait): a decode holds up to 4 bytes a pixel, 160 MB
#: at the limit, so uploads at once cannot take the service's memory from the others.
DECODING = threading.BoundedSemaphore(2)


@dataclass(frozen=True, slots=True)
class SketchImage:
    """An image that passed the door: its bytes as sent, its type and size in pixels."""

    data: bytes
    media_type: str
    size: tuple[int, int]


def too_large(size: int | None = None) -> ApiProblem:
    """The 413 of a sketch over :data:`SKETCH_MAX_BYTES` (``size`` bytes, if known)."""
    sent = f"is {size} bytes" if size is not None else "is larger"
    return ApiProblem(
        413,
        "Sketch too large",
        f"the sketch {sent}; the largest taken is {SKETCH_MAX_BYTES} bytes (5 MiB)",
    )


def media_type_of(data: bytes) -> str | None:
    """The type of an image by its first bytes; None for neither PNG nor JPEG."""
    return next((t for t, (magic, _) in MAGIC.items() if data.startswith(magic)), None)


def checked(data: bytes, declared: str | None) -> SketchImage:
    """``data`` as a sketch, sent as ``declared`` (its Content-Type); 413 too large, 415 not
    PNG or JPEG or not what the header says, 422 too many pixels or damaged."""
    if len(data) > SKETCH_MAX_BYTES:
        raise too_large(len(data))
    said = media_type(declared)
    if said not in SKETCH_TYPES:
        raise ApiProblem(
            415,
            "Sketch type not taken",
            f"the Content-Type is {said or 'missing'!r:.60}; a sketch is sent as "
            + " or ".join(SKETCH_TYPES),
        )
    found = media_type_of(data)
    if found is None:
        raise ApiProblem(
            415,
            "Sketch is not an image",
            f"the body is no PNG or JPEG image (its first bytes are {data[:8].hex(' ')!r}, "
            "neither PNG's 89 50 4e 47 nor JPEG's ff d8 ff)",
        )
    if found != said:
        raise ApiProblem(
            415,
            "Sketch type mismatch",
            f"the Content-Type says {said}, but the bytes are {found}",
        )
    return SketchImage(data, found, _decoded_size(data, MAGIC[found][1]))


def _decoded_size(data: bytes, fmt: str) -> tuple[int, int]:
    """The image's width and height in pixels, checked against the limits from its header
    before it is decoded whole (422 over them or damaged)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            with Image.open(io.BytesIO(data), formats=[fmt]) as image:
                width, height = image.size
                _within_limits(width, height)
                with DECODING:
                    image.load()
            # load() pads a truncated image once anything in the process has set Pillow's
            # LOAD_TRUNCATED_IMAGES (WeasyPrint does as it is imported); verify() does not
            with Image.open(io.BytesIO(data), formats=[fmt]) as whole:
                whole.verify()
    except (Image.DecompressionBombError, Image.DecompressionBombWarning) as exc:
        # Pillow's own guard, met in the header before ours: far over the limits
        raise too_many_pixels(str(exc).split(",")[0]) from None
    except (UnidentifiedImageError, OSError, SyntaxError, ValueError) as exc:
        raise ApiProblem(
            422, "Sketch damaged", f"the {fmt} image cannot be decoded: {exc}"[:300]
        ) from None
    return width, height


def _within_limits(width: int, height: int) -> None:
    if max(width, height) > SKETCH_MAX_SIDE or width * height > SKETCH_MAX_PIXELS:
        raise too_many_pixels(f"the image is {width} × {height} pixels")


def too_many_pixels(found: str) -> ApiProblem:
    """The 422 of an image over the limits in pixels (``found``: what its header says)."""
    return ApiProblem(
        422,
        "Sketch too many pixels",
        f"{found}; a sketch is at most {SKETCH_MAX_SIDE} pixels a side and "
        f"{SKETCH_MAX_PIXELS} pixels in all",
    )
