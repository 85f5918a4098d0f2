"""The run page and rigclient's summary print the numbers as the report does (issue 37,
item 6): a count whole, a result to the place of its uncertainty (GUM 7.2.6), a table's
column with one number of decimals."""

from __future__ import annotations

import math
import re
from html import unescape
from io import StringIO

from rich.console import Console

from rigclient.summary import results_tables
from rigserver.web.pages import results_html
from schemas.results import ReciprocatingResults
from schemas.stands import StandKind
from tests.reports.simulated import simulated


def _place_of(expanded: float) -> int:
    """Decimals of a value stated with U: U's second significant digit (GUM 7.2.6)."""
    return 1 - math.floor(math.log10(expanded))


def test_the_run_page_prints_counts_whole_and_values_to_their_uncertainty() -> None:
    done = simulated(StandKind.RECIPROCATING)
    v = done.result.values
    assert isinstance(v, ReciprocatingResults) and v.friction_steady_expanded is not None
    assert not float(v.laps).is_integer()  # the record's 999.987 cycles
    for lang in ("en", "ru"):
        page = unescape(
            re.sub(r"\s+", " ", results_html(run=done.run, payload=done.result.payload, lang=lang))
        )  # type: ignore[arg-type]
        cells = re.findall(r"<td[^>]*>([^<]*)</td>", page)
        assert str(round(v.laps)) in cells
        mu = f"{v.friction_steady:.{_place_of(v.friction_steady_expanded)}f}"
        assert (mu if lang == "en" else mu.replace(".", ",")) in cells
        u = f"{v.friction_steady_expanded:.{_place_of(v.friction_steady_expanded)}f}"
        assert (u if lang == "en" else u.replace(".", ",")) in cells  # U: two digits


def test_the_console_summary_prints_them_alike() -> None:
    done = simulated(StandKind.RECIPROCATING)
    v = done.result.values
    assert isinstance(v, ReciprocatingResults) and v.friction_steady_expanded is not None
    out = StringIO()
    console = Console(file=out, width=200, color_system=None)
    for table in results_tables(done.result.payload):
        console.print(table)
    text = out.getvalue()
    assert re.search(rf"n_L\s*│\s*{round(v.laps)}\s*│", text), text
    mu = f"{v.friction_steady:.{_place_of(v.friction_steady_expanded)}f}"
    assert re.search(rf"│ μ\s*│\s*{re.escape(mu)}\s*│", text), text


def test_a_table_of_the_run_page_has_one_number_of_decimals_a_column() -> None:
    done = simulated(StandKind.RECIPROCATING)
    page = results_html(run=done.run, payload=done.result.payload, lang="ru")
    rows = [
        re.findall(r'<td class="num">([^<]*)</td>', row)
        for row in re.findall(r"<tr>(.*?)</tr>", page, flags=re.S)
    ]
    strokes = [r for r in rows if len(r) == 3]  # the strokes by blocks of cycles: n, μ_f, μ_b
    assert len(strokes) >= 20
    for column in zip(*strokes, strict=True):
        decimals = {len(cell.partition(",")[2]) for cell in column}
        assert len(decimals) == 1, column  # 0,549 and 0,55 were printed beside 0,5494
