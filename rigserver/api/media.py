"""The media type a request's ``Content-Type`` names: case-insensitive, its parameters
(``; charset=utf-8``) left out (RFC 9110, 8.3.1)."""

from __future__ import annotations


def media_type(content_type: str | None) -> str:
    """The media type of a ``Content-Type`` header, in lower case ('' without one)."""
    return (content_type or "").partition(";")[0].strip().lower()
