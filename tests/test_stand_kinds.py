"""Every stand kind is complete in every layer, and each layer names the kinds in one place.

A kind is declared once in the schemas (:data:`schemas.stands.DECLARATIONS`) and registered
once per layer: its analysis kit, its report kit, its simulator. A kind missing from a
registry fails here, not as a KeyError in a page; a new table of kinds elsewhere fails the
count of the files that name them.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from rigserver.analysis.kits import KITS as ANALYSIS_KITS
from rigserver.analysis.series import label_of
from rigserver.reports.kits import KITS as REPORT_KITS
from rigserver.reports.series_report import TEXT
from rigsim.simulators import SIMULATORS
from schemas.stands import DECLARATIONS, StandKind

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("schemas", "rigserver", "rigsim", "rigclient")
#: The registries, one per layer: the only modules that may name three kinds or more.
REGISTRIES = {
    "schemas/stands.py",
    "rigserver/analysis/kits.py",
    "rigserver/reports/kits.py",
    "rigsim/simulators/__init__.py",
}


@pytest.mark.parametrize("kind", list(StandKind))
def test_every_kind_is_declared_with_its_own_models(kind: StandKind) -> None:
    declared = DECLARATIONS[kind]
    assert declared.kind is kind
    assert declared.results.model_fields["stand"].default == kind.value
    assert declared.configuration.model_validate({}) == declared.configuration()
    assert declared.labels and declared.specimens and declared.groups
    assert sum(g.aligned for g in declared.groups) >= 1  # the record a live chart draws


@pytest.mark.parametrize("kind", list(StandKind))
def test_every_kind_has_an_analysis_kit_whose_results_are_labelled(kind: StandKind) -> None:
    kit = ANALYSIS_KITS[kind]
    labels = DECLARATIONS[kind].labels
    assert [p for p in kit.headline_paths(kind) if p not in labels] == []
    assert [h.path for h in kit.series if label_of(kind, h.path) is None] == []


@pytest.mark.parametrize("kind", list(StandKind))
def test_every_kind_has_a_report_kit_and_a_simulator(kind: StandKind) -> None:
    kit = REPORT_KITS[kind]
    assert kit.contents.items
    assert [p.caption for p in kit.series_plots if p.caption not in TEXT] == []
    assert SIMULATORS[kind].settings() is not None


def _kinds_named(text: str) -> set[StandKind]:
    return {
        kind
        for kind in StandKind
        if re.search(rf"StandKind\.{kind.name}\b|[\"']{kind.value}[\"']", text)
    }


def test_only_the_registries_name_three_kinds_or_more() -> None:
    naming = {
        path.relative_to(ROOT).as_posix()
        for package in PACKAGES
        for path in (ROOT / package).rglob("*.py")
        if len(_kinds_named(path.read_text(encoding="utf-8"))) >= 3
    }
    assert naming == REGISTRIES


def test_the_count_sees_a_table_of_kinds() -> None:
    table = 'X = {StandKind.SMTS2: 1, StandKind.MTOS: 2}\nY = ("pin_on_disc",)\n'
    assert _kinds_named(table) == {StandKind.SMTS2, StandKind.MTOS, StandKind.PIN_ON_DISC}
