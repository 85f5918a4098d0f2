"""The SMTs-2's pin is the material its specimen names (issue 37, item 5): a brass pin is
computed with brass's properties from the materials table, a pin the table does not hold
borrows St3sp's nothing and is asked for, a configuration that gives the pin wins; the
simulator's adhesive run (a brass pin) comes out with brass."""

from __future__ import annotations

import math
from typing import Any

import pytest
from fastapi.testclient import TestClient

from rigserver.analysis.specimens import SMTS2
from rigsim.simulators import simulate
from rigsim.simulators.smts2 import Smts2Settings
from schemas.stands import PinMaterial, StandKind
from tests.api.conftest import READER, WRITER, auth
from tests.reports.simulated import post

#: LS59-1 (CuZn40Pb2) as the table's comment sources it: E 1.05·10⁵ MPa, μ 0.34, σ_B 400
#: MPa, ρ 8500 kg/m³ (typed here from the sources, not read from the table).
BRASS = {"E": 1.05e11, "mu": 0.34, "sigma_b": 4.0e8, "rho": 8500.0}
#: 200 N on the 10 mm pin, the disc's r2 22.5 mm, 20 hundreds of revolutions.
LOAD, ROWS = 200.0, 100
MASS_BEFORE, MASS_AFTER = 12.2500, 12.2430  # g
RA = 0.5  # μm


def _results(client: TestClient, named: str, **configuration: Any) -> dict[str, Any]:
    headers = auth(WRITER)
    body = {"stand": "smts2", "operator": "Orlova", "specimen": {"pin": named, "disc": "R9"}}
    opened = client.post(
        "/api/v1/runs", json=body | {"configuration": configuration}, headers=headers
    )
    assert opened.status_code == 201, opened.text
    run_id = opened.json()["id"]
    record = {
        "time": [float(i) for i in range(ROWS)],
        "load": [LOAD] * ROWS,
        "speed": [980.0] * ROWS,
        "friction_moment": [0.55 * LOAD * 0.0225] * ROWS,
        "revolutions": [float(i // 5) for i in range(ROWS)],
    }
    weighed = {"pin_mass_before": [MASS_BEFORE], "pin_mass_after": [MASS_AFTER], "disc_ra": [RA]}
    for seq, (group, columns) in enumerate((("measurements", weighed), ("friction", record))):
        batch = {"seq": seq, "group": group, "columns": columns}
        sent = client.post(f"/api/v1/runs/{run_id}/readings", json=batch, headers=headers)
        assert sent.is_success, sent.text
    assert client.post(f"/api/v1/runs/{run_id}/finish", headers=headers).is_success
    answer = client.get(f"/api/v1/runs/{run_id}/results", headers=auth(READER))
    assert answer.status_code == 200, answer.text
    values: dict[str, Any] = answer.json()["values"]
    return values


def _volume(density: float) -> float:
    # (2.9)-(2.10): V = (m1 - m2)/ρ, the masses in g
    return (MASS_BEFORE - MASS_AFTER) * 1e-3 / density


def _elastic(theory: dict[str, Any], e: float, mu: float, sigma_b: float) -> float:
    """I_h^y of (2.1) with the pin's E, μ, σ_B and the run's material-free figures."""
    t, beta = theory["fatigue_t"], theory["beta"]
    theta = (1.0 - mu**2) / e
    return float(
        theory["C"]
        * (theory["contour_pressure"] * theta / theory["k_nu"]) ** (1.0 + beta * t)
        * (theory["k_f"] / (sigma_b * theta)) ** t
        * theory["rmax_over_r"] ** (t * (1.0 + beta) / 2.0)
        * (theory["eta_c"] * 2.0) ** (-beta * t)  # b_ν = 2, the stand's default
    )


def test_a_brass_pin_is_computed_with_brass(client: TestClient) -> None:
    v = _results(client, "ЛС59-1")
    assert v["experimental"]["volume"] == pytest.approx(_volume(BRASS["rho"]), rel=1e-12)
    theory = v["theoretical"]
    assert theory["contact"] == "elastic"  # p_c = 200 N/(π·25 mm²) = 2.5 MPa < HB
    assert theory["intensity"] == pytest.approx(
        _elastic(theory, BRASS["E"], BRASS["mu"], BRASS["sigma_b"]), rel=1e-9
    )
    steel = PinMaterial()  # St3sp, the stand's default pin
    st3sp = _elastic(theory, steel.youngs_modulus, steel.poisson, steel.tensile_strength)
    assert not math.isclose(theory["intensity"], st3sp, rel_tol=1e-3)
    assert SMTS2.note in v["notes"] and SMTS2.pending not in v["pending"]


def test_an_unknown_pin_asks_for_its_properties(client: TestClient) -> None:
    v = _results(client, "unobtainium 7")
    assert SMTS2.pending in v["pending"]
    for key in ("pin.youngs_modulus", "pin.hardness", "pin.yield_strength", "pin.density"):
        assert key in SMTS2.pending
    # no number of St3sp's: neither the wear by mass (ρ) nor (2.1)
    assert v["experimental"] is None and v["theoretical"] is None
    assert v["sensitivity"] == [] and v["validity"] is None and v["verdict"] is None
    assert v["friction_steady"] == pytest.approx(0.55, rel=1e-9)  # (2.8) needs no material


def test_a_configuration_that_gives_the_pin_keeps_it(client: TestClient) -> None:
    own = PinMaterial(name="brass, certificate 17", density=8450.0, tensile_strength=3.8e8)
    v = _results(client, "brass", pin=own.model_dump())
    assert v["experimental"]["volume"] == pytest.approx(_volume(8450.0), rel=1e-12)
    assert v["theoretical"]["intensity"] == pytest.approx(
        _elastic(v["theoretical"], own.youngs_modulus, own.poisson, 3.8e8), rel=1e-9
    )
    assert SMTS2.note not in v["notes"]


def test_the_simulators_adhesive_run_wears_a_brass_pin(client: TestClient) -> None:
    run = simulate(StandKind.SMTS2, Smts2Settings.for_mode("adhesive"), seed=5)
    assert run.run_create.specimen["pin"] == "brass"
    assert "pin" not in run.run_create.configuration  # named, not typed in
    run_id = post(client, run, WRITER)
    v = client.get(f"/api/v1/runs/{run_id}/results", headers=auth(READER)).json()["values"]
    m = run.truth
    # the simulated weighing lost V·ρ of brass, read back through the balance (0.1 mg)
    assert m.mass_loss == pytest.approx(m.volume * BRASS["rho"], rel=1e-12)
    assert v["experimental"]["volume"] == pytest.approx(m.volume, rel=0.05)
    assert v["theoretical"]["intensity"] == pytest.approx(
        _elastic(v["theoretical"], BRASS["E"], BRASS["mu"], BRASS["sigma_b"]), rel=1e-9
    )
