"""Every result the pipelines produce and every channel has a label in both languages and a
display unit (issue 15): a new result without one fails here."""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping
from typing import Any

import pytest

from rigserver.reports.i18n import Messages
from schemas.labels import NOT_QUANTITIES, Label
from schemas.stands import DECLARATIONS, StandKind, default_stands
from schemas.units import UNITS
from tests.reports.simulated import simulated

RU = Messages("ru")


def result_rows(payload: Mapping[str, Any]) -> Iterator[tuple[str, Any, str]]:
    """``(path, value, unit)`` of every number, flag and word in a results payload: what
    the pipelines produce, whether or not anything shows it (lists expanded with their
    index, ``steps[2].chi``; the unit as the payload's ``units`` names it)."""
    units: Mapping[str, str] = payload.get("units", {})

    def walk(node: Any, path: str, unit_path: str) -> Iterator[tuple[str, Any, str]]:
        if isinstance(node, dict):
            for key, value in node.items():
                sep = "." if path else ""
                yield from walk(value, f"{path}{sep}{key}", f"{unit_path}{sep}{key}")
        elif isinstance(node, list):
            for index, value in enumerate(node):
                yield from walk(value, f"{path}[{index}]", f"{unit_path}[]")
        else:
            unit = units.get(unit_path) or units.get(unit_path.removesuffix("[]")) or ""
            if not unit and "." in unit_path:  # a dict of quantities: temperature_rise.t2
                unit = units.get(unit_path.rsplit(".", 1)[0], "")
            yield path, node, unit

    yield from walk(payload.get("values", {}), "", "")


def _translated(text: str) -> bool:
    return bool(text) and RU.gettext(text) != text


def _label_of(kind: StandKind, path: str) -> Label | None:
    labels = DECLARATIONS[kind].labels
    general = re.sub(r"\[\d+\]", "[]", path)
    for candidate in (general, general.removesuffix("[]"), general.rsplit(".", 1)[0]):
        if candidate in labels:
            return labels[candidate]
    return None


@pytest.mark.parametrize("kind", list(StandKind))
def test_every_result_produced_has_a_label(kind: StandKind) -> None:
    payload = simulated(kind).result.payload
    missing = []
    for path, value, unit in result_rows(payload):
        if re.split(r"[.\[]", path)[0] in NOT_QUANTITIES:
            continue
        label = _label_of(kind, path)
        if value is None and any(key.startswith(f"{path}.") for key in DECLARATIONS[kind].labels):
            continue  # a part of the results this run has not got (no disc profile)
        if label is None:
            missing.append(path)
            continue
        if unit and label.unit != "1":  # the display unit converts from the stored one
            assert UNITS[unit].si == UNITS[label.unit].si, (path, unit, label.unit)
    assert not missing


@pytest.mark.parametrize("kind", list(StandKind))
def test_every_label_has_both_languages_and_a_unit(kind: StandKind) -> None:
    for path, label in DECLARATIONS[kind].labels.items():
        assert _translated(label.text), f"{kind.value}.{path}: no Russian for {label.text!r}"
        assert label.unit in UNITS, path
        assert 1 <= label.digits <= 9, path
    for table in DECLARATIONS[kind].tables:
        assert _translated(table.caption)
        assert set(table.columns) <= set(DECLARATIONS[kind].labels)


def test_every_channel_has_both_languages_and_a_unit() -> None:
    for stand in default_stands().values():
        for group in stand.groups:
            assert _translated(group.long_name), group.long_name
            for channel in group.channels:
                assert _translated(channel.long_name), f"{stand.kind.value}.{channel.name}"
                assert channel.unit in UNITS
