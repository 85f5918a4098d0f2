"""JSON and TOML that rigclient reads (maps, the spool's openings and problems, the spool
lock's owner), held to the server's rules: arrays and tables nested at most
:data:`MAX_DEPTH` deep (the limit of :mod:`schemas.strict_json`, which the server applies to
the wire and the archives: Python's parser and every walk over a tree recurse once per
level), a key given twice refused. TOML and the spool's own JSON (which may hold NaN for a
channel a batch lacks) are read here; the limit is the one number.
"""

from __future__ import annotations

import json
import tomllib
from typing import Any

from schemas.strict_json import MAX_DEPTH


class TooDeep(ValueError):
    """A text nested deeper than :data:`MAX_DEPTH`; ``where``: the path to the level."""

    def __init__(self, where: str) -> None:
        at = f" (at {where if len(where) <= 120 else where[:117] + '...'})" if where else ""
        super().__init__(
            f"arrays and tables are nested deeper than {MAX_DEPTH} levels, the limit{at}"
        )


class DuplicateKey(ValueError):
    """A JSON object that gives a key twice."""


def _pairs(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    found: dict[str, Any] = {}
    for key, value in pairs:
        if key in found:
            raise DuplicateKey(f"the key {key!r} is given twice")
        found[key] = value
    return found


def loads_json(text: str | bytes) -> Any:
    """The JSON value of ``text``; :class:`TooDeep`, :class:`DuplicateKey`, or
    ``json.JSONDecodeError`` for what is not JSON."""
    try:
        tree = json.loads(text, object_pairs_hook=_pairs)
    except RecursionError:  # the parser's own limit: deeper than ours all the same
        raise TooDeep("") from None
    check_depth(tree)
    return tree


def loads_toml(text: str) -> dict[str, Any]:
    """The TOML table of ``text``; :class:`TooDeep`, or ``tomllib.TOMLDecodeError``."""
    try:
        tree = tomllib.loads(text)
    except RecursionError:
        raise TooDeep("") from None
    check_depth(tree)
    return tree


def check_depth(tree: Any) -> None:
    """:class:`TooDeep` if ``tree`` (dicts and lists) nests deeper than :data:`MAX_DEPTH`;
    walked without recursion."""
    stack: list[tuple[Any, int, str]] = [(tree, 0, "")]
    while stack:
        node, depth, path = stack.pop()
        if isinstance(node, dict):
            items: list[tuple[str, Any]] = [(str(k), v) for k, v in node.items()]
        elif isinstance(node, list):
            items = [(str(i), v) for i, v in enumerate(node)]
        else:
            continue
        if depth >= MAX_DEPTH:
            raise TooDeep(path)
        for key, value in items:
            stack.append((value, depth + 1, f"{path}.{key}" if path else key))
