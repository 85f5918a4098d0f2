"""The run page of a speed sweep (issue 37, item 2): the steps' table and μ against the
sliding speed (a Stribeck curve), in both languages."""

from __future__ import annotations

from html import unescape

import pytest
from fastapi.testclient import TestClient

from rigsim.simulators.tribometer import simulate_sweep
from tests.api.conftest import READER, WRITER, auth
from tests.reports.simulated import post


@pytest.mark.parametrize(
    ("lang", "caption", "figure"),
    [
        ("en", "The recipe's steps", "Friction coefficient against the sliding speed"),
        ("ru", "Шаги программы испытания", "Коэффициент трения в зависимости от скорости"),
    ],
)
def test_the_run_page_tabulates_and_draws_the_steps(
    client: TestClient, lang: str, caption: str, figure: str
) -> None:
    run_id = post(client, simulate_sweep(seed=2), WRITER)
    page = client.get(f"/runs/{run_id}?lang={lang}", headers=auth(READER))
    assert page.status_code == 200, page.text
    text = unescape(page.text)
    assert caption in text
    assert 'data-table="steps"' in text
    assert text.count("<tr><td") >= 4  # a row a step at least
    assert 'data-figure="stribeck"' in text and "<svg" in text and figure in text
