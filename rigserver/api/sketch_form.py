"""The run page's form of a sketch (``multipart/form-data``: the session's form token and
one image file), read with the standard library's MIME parser; anything else in it is
refused with 422 naming it."""

from __future__ import annotations

import email
import email.policy
from dataclasses import dataclass

from rigserver.api.media import media_type
from rigserver.api.problems import ApiProblem

#: The fields of the form: the session's form token, the image file.
TOKEN, IMAGE = "form_token", "image"


@dataclass(frozen=True, slots=True)
class SketchForm:
    """What the form carries: the form token, the file's bytes and the type the browser
    gave them (checked against the bytes by :func:`rigserver.api.sketch_images.checked`)."""

    token: str
    data: bytes
    media_type: str


def _invalid(detail: str) -> ApiProblem:
    return ApiProblem(422, "Invalid form", detail)


def read_sketch_form(body: bytes, content_type: str | None) -> SketchForm:
    """The form of ``body``, sent as ``content_type`` (415 for another type than
    ``multipart/form-data``, 422 for a form that is not the sketch's)."""
    header = content_type or ""
    if media_type(header) != "multipart/form-data":
        raise ApiProblem(
            415,
            "Invalid form",
            f"a sketch's form is sent as multipart/form-data, not {header[:60]!r}",
        )
    message = email.message_from_bytes(
        b"Content-Type: " + header.encode("latin-1") + b"\r\n\r\n" + body,
        policy=email.policy.HTTP,
    )
    if not message.is_multipart() or message.defects:
        raise _invalid("the form's parts cannot be read (multipart/form-data expected)")
    fields: dict[str, tuple[bytes, str]] = {}
    for part in message.iter_parts():
        name = str(part.get_param("name", "", header="content-disposition"))
        if name not in (TOKEN, IMAGE):
            raise _invalid(f"unknown field {name[:40]!r}")
        if name in fields:
            raise _invalid(f"the field {name!r} is given twice")
        data = part.get_payload(decode=True)
        fields[name] = (data if isinstance(data, bytes) else b"", part.get_content_type())
    if IMAGE not in fields:
        raise _invalid(f"the field {IMAGE!r} (the sketch's file) is missing")
    token = fields.get(TOKEN, (b"", ""))[0].decode("utf-8", "replace")
    return SketchForm(token, *fields[IMAGE])
