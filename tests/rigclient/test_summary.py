"""The results as the lab PC's summary prints them (``rigclient import``, ``rigsim run``)."""

from __future__ import annotations

from rich.console import Console

from rigclient.summary import results_tables


def _printed(results: dict[str, object]) -> str:
    console = Console(width=200, record=True)
    for table in results_tables(results):
        console.print(table)
    return console.export_text()


def test_a_value_below_its_resolution_is_printed_as_zero() -> None:
    # χ_mean's resolution is 1e-4 (schemas.labels): -2.7e-17 is the arithmetic's noise about
    # a centred journal, printed 0 to the places of its uncertainty (0.010), as the report
    # prints it, not "-0.000"
    results = {
        "stand": "slide_bearing",
        "values": {"stand": "slide_bearing", "chi_mean": -2.7e-17, "chi_mean_uncertainty": 0.01},
        "units": {"chi_mean": "1", "chi_mean_uncertainty": "1"},
    }
    row = next(line for line in _printed(results).splitlines() if "│ mean eccentricity" in line)
    assert " 0.000 " in row and "-0" not in row
