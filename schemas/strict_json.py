"""JSON bodies read strictly: a key given twice in an object, or a number too long to
convert, is refused (422 naming where), never decided silently by the last copy; a body
nested deeper than :data:`MAX_DEPTH` arrays and objects is refused naming the limit (no
body the service takes nests deeper than a few levels, and Python's parser and every
walk over the tree recurse once per level: 1 000 levels end in a ``RecursionError``).

:class:`StrictJsonRoute` is the route class of the routers that take JSON bodies through
FastAPI (``/runs``, ``/models``); the ingest route parses its own (``routes.readings``)
with :func:`strict_loads` as the judge of what its fast parser refuses.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Coroutine
from typing import Any

from fastapi import Request, Response
from fastapi.routing import APIRoute

#: Arrays and objects a JSON body may nest, one in another.
MAX_DEPTH = 64


class JsonRefused(json.JSONDecodeError):
    """A body that is JSON but not strict JSON. ``pos`` is where: the dotted path of the
    duplicated key (FastAPI puts it in the error's ``loc``), or ``"body"``."""

    def __init__(self, message: str, doc: str, where: str) -> None:
        super().__init__(message, doc, 0)
        self.pos = where  # type: ignore[assignment]


class _Duplicate(Exception):
    def __init__(self, path: list[str]) -> None:
        self.path = path


class _TooDeep(Exception):
    pass


def too_deep() -> str:
    """What a body nested too deeply is told."""
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
            f"the body is not UTF-8 ({exc.reason} at byte {exc.start})", "", "body"
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


class _StrictJsonRequest(Request):
    async def json(self) -> Any:
        if not hasattr(self, "_json"):
            self._json = strict_loads(await self.body())
        return self._json


class StrictJsonRoute(APIRoute):
    """A route whose JSON body is read by :func:`strict_loads`."""

    def get_route_handler(self) -> Callable[[Request], Coroutine[Any, Any, Response]]:
        handler = super().get_route_handler()

        async def strict(request: Request) -> Response:
            return await handler(_StrictJsonRequest(request.scope, request.receive))

        return strict
