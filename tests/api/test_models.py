"""The calculators under /models: wired to core, errors as problems."""

from __future__ import annotations

import math
import re

import pytest
from fastapi.testclient import TestClient

from tests.api.conftest import READER, auth

API = "/api/v1/models"


def test_bearing_friction_at_zero_eccentricity_is_petroff(client: TestClient) -> None:
    body = {
        "chi": 0.0,
        "omega": 100.0,
        "viscosity": 0.05,
        "bearing_radius": 0.025,
        "width": 0.04,
        "clearance": 1e-4,
        "load": 1000.0,
    }
    r = client.post(f"{API}/bearing/friction", json=body, headers=auth(READER))
    assert r.status_code == 200, r.text
    r1 = 0.025 - 1e-4
    petroff = 2 * math.pi * 0.05 * 100.0 * r1**3 * 0.04 / 1e-4  # (4.1) at e = 0: shear only
    assert r.json()["friction_moment"] == pytest.approx(petroff, rel=1e-9)
    assert r.json()["friction_coefficient"] == pytest.approx(petroff / (1000.0 * r1), rel=1e-9)


def test_chi_at_one_is_a_problem_naming_the_field(client: TestClient) -> None:
    r = client.post(f"{API}/bearing/friction", json={"chi": 1.0}, headers=auth(READER))
    assert r.status_code == 422
    assert r.json()["errors"][0]["field"] == "chi"


def test_undefined_plastic_wear_is_422_with_the_reason(client: TestClient) -> None:
    # p_c = N/(π r1²) > HB makes the contact plastic; σ_T <= 2f·HB leaves k_f^n undefined
    body = {"load": 5000.0, "pin_radius": 0.0005, "friction_coefficient": 0.4, "fatigue_t": 1.3}
    r = client.post(f"{API}/wear/theoretical", json=body, headers=auth(READER))
    assert r.status_code == 422
    assert "2f" in r.json()["detail"] or "σ_T" in r.json()["detail"]


def test_equilibrium_roughness_item_13(client: TestClient) -> None:
    r = client.post(f"{API}/roughness/equilibrium", json={}, headers=auth(READER))
    assert r.status_code == 200
    # lab 1 item 13 (models.md §1): sensible values lie in 1e-3..1e-1
    assert 1e-3 < r.json()["complex_parameter"] < 1e-1


def test_mechanism_dynamic_errors_and_report(client: TestClient) -> None:
    body = {"move": {"duration": 0.6}, "settle": 0.0, "samples": 40}
    r = client.post(f"{API}/mechanism/dynamic-errors", json=body, headers=auth(READER))
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["success"] is True
    assert len(out["t"]) == 40 and len(out["xi"]) == 3
    # max_abs is the largest modulus of each ξ_k over the output times
    assert out["max_abs"] == pytest.approx([max(abs(v) for v in row) for row in out["xi"]])
    # the programme starts at q_start and ends at q_end (defaults of the request)
    assert [row[0] for row in out["q"]] == pytest.approx([0.3, 0.6, 0.0])
    assert [row[-1] for row in out["q"]] == pytest.approx([0.8, 1.0, 0.5])
    page = client.post(f"{API}/mechanism/report.html", json=body, headers=auth(READER))
    assert page.status_code == 200
    assert page.text.count("<svg") == 2
    assert "arcmin" in page.text
    # the corrections to the article's printed formulas the computation uses (docs/models.md)
    assert all(f"<li>E{n} (the article" in page.text for n in (6, 7, 8))
    assert "seed" not in page.text and page.headers["content-language"] == "en"
    russian = client.post(f"{API}/mechanism/report.html?lang=ru", json=body, headers=auth(READER))
    assert russian.status_code == 200 and russian.headers["content-language"] == "ru"
    assert '<html lang="ru">' in russian.text and "угл. мин" in russian.text
    assert all(f"<li>E{n} (статья" in russian.text for n in (6, 7, 8))
    assert "Динамические ошибки рычажного механизма" in russian.text
    words = re.sub(r"<(svg|style)\b.*?</\1>|<[^>]+>", " ", russian.text, flags=re.S)
    # no English word on the Russian page but the solver's name and the maths (arcsin, max,
    # the indices mlk of the article's γ_mlk)
    assert set(re.findall(r"\b[A-Za-z]{3,}\b", words)) <= {"LSODA", "arcsin", "max", "mlk"}


def test_mechanism_bad_input_names_the_field(client: TestClient) -> None:
    r = client.post(
        f"{API}/mechanism/dynamic-errors",
        json={"move": {"duration": -1}, "arm": {"m1": 0}},
        headers=auth(READER),
    )
    assert r.status_code == 422
    fields = {e["field"] for e in r.json()["errors"]}
    assert {"move.duration", "arm.m1"} <= fields
