"""Issue 40, item 4: no route module imports another (import-linter's independence contract
in pyproject.toml); a route module added later is in that contract too."""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).parents[2]


def test_every_route_module_is_in_the_independence_contract() -> None:
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
    (independent,) = [
        c["modules"]
        for c in contracts["contracts"]
        if c["type"] == "independence" and "rigserver.api.routes.runs" in c["modules"]
    ]
    modules = {
        f"rigserver.api.routes.{p.stem}"
        for p in (ROOT / "rigserver" / "api" / "routes").glob("*.py")
        if p.stem != "__init__"
    }
    assert set(independent) == modules
