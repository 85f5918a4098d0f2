"""The run page's configuration (issue 37, item 5): every value with its words and unit as
the report prints them, and who gave it: the operator, the file and its map, the materials
table for the material the specimen names, or nobody ("not given: the stand's default"),
in both languages."""

from __future__ import annotations

import re
from html import unescape

import pytest
from fastapi.testclient import TestClient

from schemas.materials import properties
from schemas.stands import PinMaterial
from tests.api.conftest import READER, WRITER, auth

GIVEN_BY = {
    "en": {
        "operator": "the operator",
        "file": "the file and its map",
        "default": "not given: the stand's default",
        "table": "the materials table",
    },
    "ru": {
        "operator": "оператор",
        "file": "файл и его карта",
        "default": "не задано: значение стенда по умолчанию",
        "table": "таблица материалов",
    },
}


def _rows(client: TestClient, lang: str, **body: object) -> dict[str, tuple[str, str, str]]:
    """The page's configuration rows: the words -> (value, unit, who gave it), each cell
    as the reader sees it, after checking its ``data-given-by``."""
    opened = client.post("/api/v1/runs", json={"operator": "Orlova", **body}, headers=auth(WRITER))
    assert opened.status_code == 201, opened.text
    page = client.get(f"/runs/{opened.json()['id']}?lang={lang}", headers=auth(READER))
    assert page.status_code == 200, page.text
    table = re.search(r'<table [^>]*data-table="configuration">(.*?)</table>', page.text, re.S)
    assert table is not None
    rows = {}
    for source, cells in re.findall(r'<tr data-given-by="(\w+)">(.*?)</tr>', table.group(1)):
        words, value, unit, said = (
            unescape(re.sub(r"<[^>]+>", "", c)) for c in re.findall(r"<td>(.*?)</td>", cells)
        )
        assert said.startswith(GIVEN_BY[lang][source]), (source, said)
        rows[words] = (value, unit, source)
    return rows


@pytest.mark.parametrize("lang", ["en", "ru"])
def test_a_default_is_marked_so_and_a_given_value_is_not(client: TestClient, lang: str) -> None:
    body = {"stand": "pin_on_disc", "configuration": {"plan": {"load": 3.0}}}
    rows = _rows(client, lang, **body)
    default = GIVEN_BY[lang]["default"]
    (load,) = [v for w, v in rows.items() if ": F, " in w]  # the plan's F, normal load
    (speed,) = [v for w, v in rows.items() if ": v, " in w]  # and v, sliding speed
    assert load[0] == "3" and load[2] == "operator" and default not in load[0]
    assert speed[0].startswith(default) and speed[2] == "default"
    by_file = _rows(client, lang, given_by="file", **body)
    assert {v[2] for v in by_file.values()} == {"file", "default"}


def test_the_pins_properties_from_the_materials_table(client: TestClient) -> None:
    rows = _rows(client, "en", stand="smts2", specimen={"pin": "brass"})
    brass = properties("brass", PinMaterial)
    assert brass is not None
    pin = {w: v for w, v in rows.items() if w.startswith("pin")}
    assert pin and {v[2] for v in pin.values()} == {"table"}
    (density,) = [v for w, v in pin.items() if "ρ" in w]
    assert density[0] == f"{brass.density:g}, the materials table's"
    (name,) = [v for w, v in pin.items() if "material" in w]
    assert name[0].startswith("CuZn40Pb2")  # not the stand's St3sp
    assert "St3sp" not in "".join(v[0] for v in pin.values())
