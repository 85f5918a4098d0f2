"""The Russian pages in headless Chromium: the runs list and a run page of each stand,
finished and open, show no Latin word beyond symbols, units and the user's own data; the
results are grouped as in the report. Screenshots of every page in both languages are left
in the test's directory for a person to look at (``run-<stand>-<lang>.png``)."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import httpx
import pytest

from rigserver.reports.i18n import Messages
from schemas.stands import DECLARATIONS, StandKind
from tests.api.conftest import READER, WRITER, Server
from tests.i18n.messages import every_message
from tests.reports.simulated import post, simulated
from tests.web.test_browser import CHROMIUM, signed_in

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(not CHROMIUM.exists(), reason="needs Debian's chromium"),
]

ALLOWED = {
    # the manual's symbols and their subscripts (R_max, M_rev, I_h,exp, p_max, φ_pmax)
    "Ra", "Rz", "Rq", "Rmax", "Sm", "max", "min", "rev", "exp", "theor", "pmax", "crit",
    # the service's name, formats and the link to the other language
    "rig", "UTC", "API", "CSV", "PDF", "HDF5", "JSON", "zip", "Excel", "English", "A4",
}  # fmt: skip


def _words(text: str) -> set[str]:
    return set(re.findall(r"[A-Za-z][A-Za-z0-9]+", re.sub(r"[_^{}]", "", text)))


def symbols() -> set[str]:
    """The Latin of the declared symbols, as a page prints them (``A_a`` reads ``Aa``): the
    results' labels, and the symbols the Russian texts of the catalog carry (``E1, модуль
    упругости``, ``HB2``)."""
    found = {
        w
        for declared in DECLARATIONS.values()
        for label in declared.labels.values()
        for w in _words(label.symbol)
    }
    ru = Messages("ru")
    for context, text in every_message():
        translated = ru.translations.pgettext(context, text) if context else ru.gettext(text)
        found |= _words(re.sub(r"\{\w+\}", "", translated))  # not the {placeholders}
    return found


def latin_words(text: str, user_data: list[str], allowed: set[str]) -> set[str]:
    for item in sorted(user_data, key=len, reverse=True):
        text = text.replace(item, " ")
    return _words(text) - allowed


def user_data(run: dict[str, Any]) -> list[str]:
    """What the lab typed: the run's id, operator, title, specimen and the words of its plan."""
    found = [run["id"], run["operator"], run.get("title") or ""]
    for mapping in (run.get("specimen") or {}, run.get("test_plan") or {}):
        found += [v for v in mapping.values() if isinstance(v, str)]
    return [item for item in found if item]


def test_russian_pages_speak_russian(server: Server, tmp_path: Path) -> None:
    with httpx.Client(base_url=server.url, timeout=30) as client:
        ids = {kind: post(client, simulated(kind).sim, WRITER) for kind in StandKind}  # type: ignore[arg-type]
        opened = post(client, simulated(StandKind.SLIDE_BEARING).sim, WRITER, finish=False)  # type: ignore[arg-type]
        headers = {"Authorization": f"Bearer {READER}"}
        runs = [client.get(f"/api/v1/runs/{i}", headers=headers).json() for i in ids.values()]
        runs.append(client.get(f"/api/v1/runs/{opened}", headers=headers).json())
    typed = [item for run in runs for item in user_data(run)]
    allowed = ALLOWED | symbols()
    pages = {f"run-{kind.value}": f"/runs/{i}" for kind, i in ids.items()}
    pages["run-open"] = f"/runs/{opened}"
    pages["runs"] = "/"
    profile = tmp_path / "chromium-profile"
    with signed_in(server.url, READER, profile, login="/login?lang=ru") as (page, _):
        for lang in ("ru", "en"):
            for name, path in pages.items():
                page.goto(f"{server.url}{path}?lang={lang}")
                if name.startswith("run-"):
                    page.wait_for_selector("#results table")
                page.screenshot(path=str(tmp_path / f"{name}-{lang}.png"), full_page=True)
                if lang != "ru":
                    continue
                text = page.inner_text("body")
                left = latin_words(text, typed, allowed)
                (tmp_path / f"{name}.txt").write_text(text)
                assert not left, (name, left)
                if name.startswith("run-") and name != "run-open":
                    assert "Пока испытание идёт" not in text
                    assert "Результаты измерений" in text
