"""The public surface of a package is what its __all__ says, sorted."""

from __future__ import annotations
import __future__

import pkgutil
import types

import pytest

import rigclient
import rigserver.storage


@pytest.mark.parametrize("package", [rigclient, rigserver.storage], ids=lambda p: p.__name__)
def test_all_is_sorted_and_importable(package: types.ModuleType) -> None:
    names = package.__all__
    assert names == sorted(names)
    for name in names:
        member = getattr(package, name)
        if isinstance(member, type):
            assert member.__module__.startswith(f"{package.__name__}."), name
    # the submodules are attributes too, once imported
    submodules = {m.name for m in pkgutil.iter_modules(package.__path__)}
    public = {
        n
        for n in dir(package)
        if not n.startswith("_")
        and n not in submodules
        and getattr(package, n) is not __future__.annotations  # `from __future__ import`
    }
    assert public == set(names)
