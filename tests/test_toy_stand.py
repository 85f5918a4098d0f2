"""A new stand kind is one module per layer plus its registration, and then it is served,
simulated, analysed and reported.

The test copies the packages, puts the toy stand of :mod:`tests.toy_stand` (a spring on a
tensile tester) into them as one module per layer, registers it in the four registries
(:data:`tests.test_stand_kinds.REGISTRIES`) and nothing else, then starts that copy's
``rigserver serve``, posts a ``rigsim run`` of the toy to it, and reads its results, its
pages and its report over HTTP.
"""

from __future__ import annotations

import filecmp
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import httpx
import pytest

from tests.api.conftest import KEYS, READER, WRITER, Server, auth
from tests.test_stand_kinds import PACKAGES, REGISTRIES

ROOT = Path(__file__).resolve().parent.parent
TOY = Path(__file__).resolve().parent / "toy_stand"

#: Each layer's toy module and where it goes.
MODULES = {
    "schemas_toy.py": "schemas/toy.py",
    "analysis_toy.py": "rigserver/analysis/toy.py",
    "reports_toy.py": "rigserver/reports/labs/toy.py",
    "rigsim_toy.py": "rigsim/simulators/toy.py",
}

#: The registration, registry by registry: (the text it follows, the text added after it);
#: an empty anchor appends to the module.
REGISTRATION: dict[str, list[tuple[str, str]]] = {
    "schemas/stands.py": [
        ("from schemas import labels\n", "from schemas import toy as toy_stand\n"),
        ('    RECIPROCATING = "reciprocating"\n', '    TOY = "toy"\n'),
        ("    | ReciprocatingConfig\n", "    | toy_stand.ToyConfig\n"),
        (
            "",
            "DECLARATIONS[StandKind.TOY] = StandDeclaration(\n"
            "    kind=StandKind.TOY,\n"
            '    title="Toy stand: a spring on a tensile tester",\n'
            "    lab_work=None,\n"
            '    name="Spring tester",\n'
            '    work="Stiffness of a coil spring",\n'
            '    aim="To find the stiffness of a spring from its force against its extension.",\n'
            "    configuration=toy_stand.ToyConfig,\n"
            "    groups=toy_stand.GROUPS,\n"
            "    results=toy_stand.ToyResults,\n"
            "    labels=toy_stand.LABELS,\n"
            '    specimens=("surface",),\n'
            "    plan=(),\n"
            ")\n",
        ),
    ],
    "rigserver/analysis/kits.py": [
        (
            "",
            "from rigserver.analysis import toy  # noqa: E402\n\n"
            "KITS[StandKind.TOY] = Kit(\n"
            "    analyse=_without_profiles(toy.analyse),\n"
            '    key_results=("stiffness",),\n'
            '    series=(Headline("stiffness", "k"),),\n'
            ")\n",
        )
    ],
    "rigserver/reports/kits.py": [
        (
            "",
            "from rigserver.reports.labs import toy  # noqa: E402\n\n"
            "KITS[StandKind.TOY] = ReportKit(\n"
            "    build=toy.build, contents=toy.CONTENTS, series_plots=()\n"
            ")\n",
        )
    ],
    "rigsim/simulators/__init__.py": [
        (
            "",
            "from rigsim.simulators import toy  # noqa: E402\n\n"
            "SIMULATORS[StandKind.TOY] = Simulator(toy.ToySettings, toy.simulate)\n",
        )
    ],
}


def _register(path: Path, additions: list[tuple[str, str]]) -> None:
    text = path.read_text(encoding="utf-8")
    for anchor, added in additions:
        if not anchor:
            text += "\n\n" + added
            continue
        assert text.count(anchor) == 1, f"{path}: the registration's place {anchor!r} moved"
        text = text.replace(anchor, anchor + added)
    path.write_text(text, encoding="utf-8")


@pytest.fixture(scope="module")
def packages(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A copy of the packages with the toy stand added."""
    root = tmp_path_factory.mktemp("toy")
    for package in PACKAGES:
        shutil.copytree(
            ROOT / package, root / package, ignore=shutil.ignore_patterns("__pycache__")
        )
    for source, target in MODULES.items():
        shutil.copy(TOY / source, root / target)
    for registry, additions in REGISTRATION.items():
        _register(root / registry, additions)
    return root


def _changed(left: Path, right: Path, prefix: str = "") -> tuple[set[str], set[str]]:
    """The files that differ between two trees, and those only in ``right``."""
    compared = filecmp.dircmp(left, right, ignore=["__pycache__"])
    changed = {prefix + name for name in compared.diff_files}
    added = {prefix + name for name in compared.right_only}
    for name, sub in compared.subdirs.items():
        more_changed, more_added = _changed(sub.left, sub.right, f"{prefix}{name}/")
        changed |= more_changed
        added |= more_added
    return changed, added


def test_the_toy_is_one_module_per_layer_and_its_registration(packages: Path) -> None:
    changed: set[str] = set()
    added: set[str] = set()
    for package in PACKAGES:
        more_changed, more_added = _changed(ROOT / package, packages / package, f"{package}/")
        changed |= more_changed
        added |= more_added
    assert changed == set(REGISTRATION) == REGISTRIES
    assert added == set(MODULES.values())


def _run(packages: Path, *args: str) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(packages), "RIG_KEY": WRITER}
    return subprocess.run(
        [sys.executable, *args],
        cwd=packages,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )


def test_the_toy_is_served_simulated_analysed_and_reported(packages: Path, tmp_path: Path) -> None:
    keys = tmp_path / "keys.json"
    keys.write_text(json.dumps(KEYS))
    server = Server(tmp_path / "data", keys, env={"PYTHONPATH": str(packages)}, cwd=packages)
    server.start()
    try:
        stands = httpx.get(f"{server.url}/api/v1/stands", headers=auth(READER), timeout=30)
        assert "toy" in json.dumps(stands.json())
        posted = _run(
            packages,
            "-m",
            "rigsim.cli",
            "run",
            "--stand=toy",
            f"--url={server.url}",
            "--noise=off",
            "--speed=max",
            "--truth",
            "--json",
        )
        assert posted.returncode == 0, posted.stderr[-3000:]
        document = json.loads(posted.stdout)
        run_id = document["run_id"]
        values = document["results"]["values"]
        # ideal instruments: the readings lie on F = F_0 + k·x, whose least-squares line is
        # itself (the simulator's truth: k 2500 N/m, F_0 1.5 N)
        assert values["stiffness"] == pytest.approx(document["truth"]["stiffness"], rel=1e-9)
        assert values["preload"] == pytest.approx(document["truth"]["preload"], rel=1e-9)
        assert values["rows"] == 201
        base = f"{server.url}/api/v1/runs/{run_id}"
        stored = httpx.get(f"{base}/results", headers=auth(READER), timeout=30).json()
        assert stored["values"] == values
        assert stored["units"]["stiffness"] == "N/m"
        page = httpx.get(f"{server.url}/runs/{run_id}", headers=auth(READER), timeout=30)
        assert page.status_code == 200
        assert "stiffness of the spring" in page.text
        report = httpx.get(f"{base}/report.html?lang=en", headers=auth(READER), timeout=120)
        assert report.status_code == 200, report.text[:2000]
        assert "Stiffness of a coil spring" in report.text  # the work's title
        assert "<td>2.5</td>" in report.text  # k, 2500 N/m, in its label's N/mm
        pdf = httpx.get(f"{base}/report.pdf?lang=en", headers=auth(READER), timeout=120)
        assert pdf.status_code == 200 and pdf.content.startswith(b"%PDF")
    finally:
        server.stop()
