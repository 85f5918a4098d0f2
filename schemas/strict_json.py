"""JSON read strictly, the one reader of every JSON text rig takes from outside: a key
given twice in an object, or a number too long to convert, is refused naming where, never
decided silently by the last copy; a text nested deeper than :data:`MAX_DEPTH` arrays and
objects is refused naming the limit (nothing rig reads nests deeper than a few levels, and
Python's parser and every walk over the tree recurse once per level: 1 000 levels end in
a ``RecursionError``).

Its readers: the service's JSON bodies (``rigserver.api.strict_json``, and the ingest
route as the judge of what its fast parser refuses), the ``.eln`` archives an import
reads (``rigserver.reports.eln_read``), the run files they carry, the stands and keys
files; and what ``rigclient`` reads (its maps, its spool).
"""

from __future__ import annotations

import json
from typing import Any

#: Arrays and objects a JSON text may nest, one in another.
MAX_DEPTH = 64


class JsonRefused(json.JSONDecodeError):
    """A text that is JSON but not strict JSON. ``pos`` is where: the dotted path of the
    duplicated key (FastAPI puts a body's in the error's ``loc``), or ``"body"``."""

    def __init__(self, message: str, doc: str, where: str) -> None:
        super().__init__(message, doc, 0)
        self.pos = where  # type: ignore[assignment]
        self.args = (message if where == "body" else f"{message} (at {where})",)


class _Duplicate(Exception):
    def __init__(self, path: list[str]) -> None:
        self.path = path


class _TooDeep(Exception):
    pass


def too_deep() -> str:
    """What a text nested too deeply is told."""
    return f"arrays and objects are nested deeper than {MAX_DEPTH} levels, the limit"


class _Pairs(list[tuple[str, Any]]):
    """An object as its key-value pairs, in order, duplicates kept (checked afterwards)."""


def strict_loads(body: bytes | str) -> Any:
    """The JSON value of ``body``; :class:`JsonRefused` for a duplicated key, an integer
    longer than Python converts (``sys.get_int_max_str_digits``) or nesting deeper than
    :data:`MAX_DEPTH`, ``json.JSONDecodeError`` for text that is not JSON. NaN, Infinity
    and lone surrogates are left to the models, which refuse them naming the field."""
    try:
        text = body.decode("utf-8") if isinstance(body, bytes) else body
    except UnicodeDecodeError as exc:
        raise JsonRefused(
            f"the text is not UTF-8 ({exc.reason} at byte {exc.start})", "", "body"
        ) from None
    try:
        tree = json.loads(text, object_pairs_hook=_Pairs)
    except RecursionError:  # the parser's own limit: deeper than MAX_DEPTH all the same
        raise JsonRefused(too_deep(), text, "body") from None
    except ValueError as exc:
        if isinstance(exc, json.JSONDecodeError):
            raise
        raise JsonRefused(f"a number is too long: {exc}", text, "body") from None
    try:
        return _objects(tree, [])
    except _Duplicate as dup:
        where = ".".join(dup.path)
        raise JsonRefused(f"the key {dup.path[-1]!r} is given twice", text, where) from None
    except _TooDeep:
        raise JsonRefused(too_deep(), text, "body") from None


def _objects(node: Any, path: list[str]) -> Any:
    if isinstance(node, _Pairs):
        if len(path) >= MAX_DEPTH:
            raise _TooDeep
        found: dict[str, Any] = {}
        for key, value in node:
            if key in found:
                raise _Duplicate([*path, key])
            found[key] = _objects(value, [*path, key])
        return found
    if isinstance(node, list):
        if len(path) >= MAX_DEPTH:
            raise _TooDeep
        return [_objects(item, [*path, str(i)]) for i, item in enumerate(node)]
    return node
