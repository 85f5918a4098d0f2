"""Every result the pipelines produce and every channel has a label in both languages and a
display unit (issue 15): a new result without one fails here."""

from __future__ import annotations

import re

import pytest

from rigserver.reports.export import result_rows
from rigserver.reports.i18n import Messages
from schemas.labels import NOT_QUANTITIES, RESULTS, TABLES, Label
from schemas.stands import StandKind, default_stands
from schemas.units import UNITS
from tests.reports.simulated import simulated

RU = Messages("ru")


def _translated(text: str) -> bool:
    return bool(text) and RU.gettext(text) != text


def _label_of(kind: StandKind, path: str) -> Label | None:
    labels = RESULTS[kind]
    general = re.sub(r"\[\d+\]", "[]", path)
    for candidate in (general, general.removesuffix("[]"), general.rsplit(".", 1)[0]):
        if candidate in labels:
            return labels[candidate]
    return None


@pytest.mark.parametrize("kind", list(StandKind))
def test_every_result_produced_has_a_label(kind: StandKind) -> None:
    payload = simulated(kind).result.payload
    missing = []
    for path, _, unit in result_rows(payload):
        if re.split(r"[.\[]", path)[0] in NOT_QUANTITIES:
            continue
        label = _label_of(kind, path)
        if label is None:
            missing.append(path)
            continue
        if unit and label.unit != "1":  # the display unit converts from the stored one
            assert UNITS[unit].si == UNITS[label.unit].si, (path, unit, label.unit)
    assert not missing


@pytest.mark.parametrize("kind", list(StandKind))
def test_every_label_has_both_languages_and_a_unit(kind: StandKind) -> None:
    for path, label in RESULTS[kind].items():
        assert _translated(label.text), f"{kind.value}.{path}: no Russian for {label.text!r}"
        assert label.unit in UNITS, path
        assert 1 <= label.digits <= 9, path
    for table in TABLES[kind]:
        assert _translated(table.caption)
        assert set(table.columns) <= set(RESULTS[kind])


def test_every_channel_has_both_languages_and_a_unit() -> None:
    for stand in default_stands().values():
        for group in stand.groups:
            assert _translated(group.long_name), group.long_name
            for channel in group.channels:
                assert _translated(channel.long_name), f"{stand.kind.value}.{channel.name}"
                assert channel.unit in UNITS
