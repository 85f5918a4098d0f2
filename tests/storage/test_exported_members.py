"""The public surface of rigserver.storage is what __all__ says, sorted."""

from __future__ import annotations

import pkgutil

import rigserver.storage as storage


def test_all_is_sorted_and_importable() -> None:
    assert storage.__all__ == sorted(storage.__all__)
    for name in storage.__all__:
        member = getattr(storage, name)
        if isinstance(member, type):
            assert member.__module__.startswith("rigserver.storage."), name
    public = {n for n in dir(storage) if not n.startswith("_")} - {"annotations"}
    modules = {m.name for m in pkgutil.iter_modules(storage.__path__)}  # submodules, once imported
    assert public - modules == set(storage.__all__)
