"""The public surface of rigclient is what __all__ says, sorted."""

from __future__ import annotations

import types

import rigclient


def test_all_is_sorted_and_importable() -> None:
    assert rigclient.__all__ == sorted(rigclient.__all__)
    for name in rigclient.__all__:
        member = getattr(rigclient, name)
        if isinstance(member, type):
            assert member.__module__.startswith("rigclient."), name
    public = {
        n
        for n in dir(rigclient)
        if not n.startswith("_") and not isinstance(getattr(rigclient, n), types.ModuleType)
    }
    assert public == set(rigclient.__all__)
