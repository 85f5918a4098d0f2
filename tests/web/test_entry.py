"""At the stand, in headless Chromium: a run opened from ``/runs/new``, the manual's tables
typed into the run page's forms (decimal commas, Enter from cell to cell), each cell
checked as typed against the limits the API applies, the rows kept in the browser while the
server is away and delivered once, the run finished with its button.

One ``rigserver serve`` for the module and one browser profile (its IndexedDB is what keeps
the rows a closed page left); the readings come from rigsim, posted through the API by
rigsim's lab-PC client for the reference runs.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Iterator
from dataclasses import replace
from typing import Any

import httpx
import numpy as np
import pytest

from rigsim.batches import SimulatedRun
from rigsim.client import LabClient
from rigsim.simulators import mtos, slide_bearing
from tests.api.conftest import KEYS, READER, WRITER, Server, auth, read_columns
from tests.web.test_browser import CHROMIUM, chromium, until

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(not CHROMIUM.exists(), reason="needs Debian's chromium"),
]

API = "/api/v1"
MTOS_READER = "mtos-reader-writer-000000"
"""A key that reads and writes MTOS runs only."""
SCREENSHOTS = os.environ.get("RIG_SCREENSHOTS")
"""A directory for the README's screenshots of the entry form (``docs/images``), if set."""


@pytest.fixture(scope="module")
def stand_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    base = tmp_path_factory.mktemp("entry")
    keys_file = base / "keys.json"
    keys = [*KEYS, {"key": MTOS_READER, "scopes": ["read", "write:mtos"], "name": "MTOS PC"}]
    keys_file.write_text(json.dumps(keys))
    server = Server(base / "data", keys_file)
    server.start()
    try:
        yield server
    finally:
        server.stop()


@pytest.fixture(scope="module")
def browser(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Any]:
    """One Chromium profile for the module, signed in with the writer's key."""
    from playwright.sync_api import sync_playwright

    playwright = sync_playwright().start()
    context = chromium(playwright, tmp_path_factory.mktemp("chromium") / "profile")
    try:
        yield context
    finally:
        context.close()
        playwright.stop()


def sign_in(context: Any, url: str, key: str = WRITER) -> Any:
    page = context.new_page()
    page.goto(f"{url}/login")
    page.fill("input[name=key]", key)
    page.press("input[name=key]", "Enter")
    page.wait_for_url(f"{url}/")
    return page


def typed(value: float) -> str:
    """A reading as a Russian lab writes it: the shortest exact digits, a decimal comma."""
    return repr(float(value)).replace(".", ",")


def type_row(page: Any, group: str, values: dict[str, float]) -> None:
    """Type a row from the keyboard into the group's form: the first cell focused, each
    value followed by Enter (the next cell; on the last, the row is sent)."""
    names = page.eval_on_selector_all(f"#entry-{group} tfoot input", "e => e.map(i => i.name)")
    page.focus(f"#entry-{group} tfoot input")
    for name in names:
        page.keyboard.type(typed(values[name]) if name in values else "")
        page.keyboard.press("Enter")


def run_of(url: str, run_id: str) -> dict[str, Any]:
    answer = httpx.get(f"{url}{API}/runs/{run_id}", headers=auth(READER), timeout=30)
    answer.raise_for_status()
    found: dict[str, Any] = answer.json()
    return found


def results_of(url: str, run_id: str) -> dict[str, Any]:
    answer = httpx.get(f"{url}{API}/runs/{run_id}/results", headers=auth(READER), timeout=60)
    answer.raise_for_status()
    found: dict[str, Any] = answer.json()["values"]
    return found


def page_run_id(page: Any) -> str:
    return str(page.url.split("/runs/")[1].split("?")[0])


def open_from_form(page: Any, url: str, stand: str, operator: str, lang: str = "en") -> str:
    """Open a run from the runs list's "New run" link and the form, by keyboard; its id."""
    page.goto(f"{url}/?lang={lang}")
    page.click(f"p.new-run a[href*='stand={stand}']")
    page.wait_for_selector("form#new-run")
    page.focus("input[name=operator]")
    page.keyboard.type(operator)
    page.keyboard.press("Enter")  # submits the form
    page.wait_for_url(f"{url}/runs/2*")
    page.wait_for_selector("#entry-status")
    return page_run_id(page)


def reference(url: str, sim: SimulatedRun[Any]) -> str:
    """The simulated run posted through the API by rigsim's lab-PC client, finished."""
    with LabClient(url, WRITER) as client:
        return client.run(sim).run.id


def same(a: Any, b: Any) -> bool:
    """Results equal to the last bit but for the arithmetic's order (the same readings
    through the same pipeline): numbers within 1e-12, NaN as NaN, the rest as equal."""
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float) and isinstance(b, float):
        return (math.isnan(a) and math.isnan(b)) or math.isclose(a, b, rel_tol=1e-12)
    return bool(a == b)


def wait_sent(page: Any, seconds: float = 30.0) -> None:
    until(lambda: page.get_attribute("#entry-status", "data-waiting") == "0", seconds)


def test_table_3_1_typed_with_decimal_commas_gives_the_results_of_the_api(
    stand_server: Server, browser: Any
) -> None:
    url = stand_server.url
    sim = slide_bearing.simulate(seed=5)
    expected = reference(url, sim)
    page = sign_in(browser, url)
    run_id = open_from_form(page, url, "slide_bearing", "Ivanova")
    # the form opened the run with the stand's passport, as rigsim's opening did
    assert run_of(url, run_id)["configuration"] == run_of(url, expected)["configuration"]
    sent: list[str] = []
    page.on("request", lambda r: sent.append(r.url) if "/rows" in r.url else None)
    for batch in sim.batches:
        rows = len(next(iter(batch.columns.values())))
        for i in range(rows):
            type_row(page, batch.group, {k: float(v[i]) for k, v in batch.columns.items()})
    wait_sent(page)
    assert len(sent) == len(sim.batches)  # one post a row, none again
    got = run_of(url, run_id)
    assert got["rows"] == run_of(url, expected)["rows"]
    # the computed columns of table 3.1 filled in on the page as the rows were acknowledged
    table = page.locator("#results table.rows").first.locator("tbody tr")
    until(lambda: table.count() == got["rows"]["rows"])
    if SCREENSHOTS:
        page.locator("#entry").screenshot(path=f"{SCREENSHOTS}/entry-en.png")
    page.on("dialog", lambda dialog: dialog.accept())
    page.click("#finish button")
    until(lambda: run_of(url, run_id)["state"] == "finished")
    mine = httpx.get(f"{url}{API}/runs/{run_id}/readings", headers=auth(READER)).json()
    assert mine == httpx.get(f"{url}{API}/runs/{expected}/readings", headers=auth(READER)).json()
    assert same(results_of(url, run_id), results_of(url, expected))
    page.close()


def test_a_cell_beyond_its_gauge_is_refused_as_typed_and_nothing_is_sent(
    stand_server: Server, browser: Any
) -> None:
    url = stand_server.url
    page = sign_in(browser, url)
    run_id = open_from_form(page, url, "slide_bearing", "Petrov")
    sent: list[str] = []
    page.on("request", lambda r: sent.append(r.url) if "/rows" in r.url else None)
    row = {"limb_angle": 142.0, "p1": 0.0, "p2": 0.0, "p3": 150.0, "p4": 0.05, "p5": -0.05}
    row |= {"x": 337.0, "y": 272.0, "t1": 22.0, "t2": 30.1}
    type_row(page, "rows", row)
    cell = "#entry-rows input[name=p3]"
    assert page.get_attribute(cell, "aria-invalid") == "true"
    # which limit, which value (the stand's declaration: manometers -1 .. 100 at)
    assert page.text_content("#err-rows-p3") == "p₃ = 150 at is above the limit 100 at"
    assert page.evaluate("document.activeElement.name") == "p3"  # back to the refused cell
    page.wait_for_timeout(300)
    assert sent == [] and run_of(url, run_id)["batches"] == 0
    # a comma, not a number, and a fixed cell
    page.fill(cell, "1,2,3")
    assert page.text_content("#err-rows-p3") == "“1,2,3” is not a number"
    page.fill(cell, "7,25")
    assert page.get_attribute(cell, "aria-invalid") is None
    page.focus("#entry-rows input[name=t2]")
    page.keyboard.press("Enter")
    wait_sent(page)
    stored = read_columns(url, run_id, "rows")
    assert stored["p3"] == [7.25] and stored["limb_angle"] == [142.0]
    # the row just sent carries its index from the receipt: corrected without a reload
    sent_row = page.locator("#rows-rows tbody tr[data-index='0']")
    edit_row(page, sent_row, "correct", {"p3": "7,5"}, "7,25 typed for 7,5")
    until(lambda: page.locator("tr.correcting").count() == 0)
    assert sent_row.locator("td[data-channel=p3] s.typed").text_content() == "7.25"
    assert read_columns(url, run_id, "rows")["p3"] == [7.5]
    page.close()


def mtos_step() -> dict[str, dict[str, float]]:
    """One load step of a simulated MTOS run and its zero readings (rigsim, seed 2)."""
    sim = mtos.simulate(seed=2)
    zero = next(b for b in sim.batches if b.group == "measurements")
    step = next(b for b in sim.batches if b.group == "steps")
    return {
        "measurements": {k: float(v[0]) for k, v in zero.columns.items()},
        "steps": {k: float(v[0]) for k, v in step.columns.items()},
    }


def test_rows_typed_offline_and_left_by_a_closed_page_are_delivered_once(
    stand_server: Server, browser: Any
) -> None:
    url = stand_server.url
    readings = mtos_step()
    page = sign_in(browser, url, MTOS_READER)
    run_id = open_from_form(page, url, "mtos", "Sidorova")
    # the lab PC's network gone (the whole profile offline: a request the page makes as it
    # closes must not get through, as a routed one could when the page closed meanwhile)
    browser.set_offline(True)
    type_row(page, "measurements", readings["measurements"])
    type_row(page, "steps", readings["steps"])
    until(lambda: page.get_attribute("#entry-status", "data-waiting") == "2")
    assert page.text_content("#entry-status").startswith("2 rows wait to be sent")
    # the row is drawn as waiting once the store of the page has it (a step after the count)
    until(lambda: page.locator("#rows-steps tbody tr.waiting").count() == 1)
    page.close()  # the rows stay in the browser's IndexedDB
    assert run_of(url, run_id)["batches"] == 0
    browser.set_offline(False)

    again = browser.new_page()
    posts: list[str] = []
    again.on("request", lambda r: posts.append(r.url) if "/rows" in r.url else None)
    again.goto(f"{url}/runs/{run_id}")
    wait_sent(again)
    assert len(posts) == 2
    got = run_of(url, run_id)
    assert got["rows"] == {"steps": 1, "measurements": 1} and got["batches"] == 2
    for group in ("steps", "measurements"):
        assert read_columns(url, run_id, group) == {k: [v] for k, v in readings[group].items()}

    # a row the server stored but whose answer was lost: kept, and sent again after a
    # reload with its seq, which the server applies once
    cookie = "; ".join(f"{c['name']}={c['value']}" for c in browser.cookies(url))

    def lost_answer(route: Any) -> None:
        headers = {**route.request.headers, "cookie": cookie}
        # the server stores the row (201; a retry of the page, every 2 s, finds it: 200)
        assert route.fetch(headers=headers).status in (200, 201)
        route.abort("connectionreset")

    again.route("**/rows?*", lost_answer)
    step = readings["steps"] | {"load": readings["steps"]["load"] + 500.0}
    type_row(again, "steps", step)
    # the route's handler runs while Playwright is called: the page waits a little each poll
    until(lambda: again.wait_for_timeout(50) or run_of(url, run_id)["rows"]["steps"] == 2)
    assert again.get_attribute("#entry-status", "data-waiting") == "1"
    again.unroute("**/rows?*")
    again.reload()
    wait_sent(again)
    assert run_of(url, run_id)["rows"]["steps"] == 2  # not 3
    assert run_of(url, run_id)["batches"] == 3
    # the results of the load steps (tables 4.4-4.6) fill in on the page
    table = again.locator("#results table.rows").first.locator("tbody tr")
    until(lambda: table.count() == 2)
    again.close()


def test_the_smts2_masses_in_russian_and_a_key_of_another_stand(
    stand_server: Server, browser: Any
) -> None:
    url = stand_server.url
    page = sign_in(browser, url)
    run_id = open_from_form(page, url, "smts2", "Кузнецова", lang="ru")
    assert page.locator("#entry-measurements input").count() == 3
    label = page.text_content("#rows-measurements thead")
    assert "m1, г" in label and "m2, г" in label  # m<sub>1</sub>, the manual's symbol
    page.route("**/rows?*", lambda route: route.abort("internetdisconnected"))
    type_row(page, "measurements", {"pin_mass_before": 12.3456})
    type_row(page, "measurements", {"pin_mass_after": 12.3401})
    until(lambda: page.get_attribute("#entry-status", "data-waiting") == "2")
    assert page.text_content("#entry-status").startswith("2 строки ждут отправки")
    page.fill("#entry-measurements input[name=pin_mass_after]", "1500")
    assert page.text_content("#err-measurements-pin_mass_after") == (
        "m₂ = 1500 г выше предела 1000 г"
    )
    if SCREENSHOTS:
        page.locator("#entry").screenshot(path=f"{SCREENSHOTS}/entry-ru.png")
    page.fill("#entry-measurements input[name=pin_mass_after]", "")
    page.unroute("**/rows?*")
    wait_sent(page)
    values = read_columns(url, run_id, "measurements")
    assert values == {"pin_mass_before": [12.3456], "pin_mass_after": [12.3401]}
    # the masses corrected in Russian: one row of the latest values, each from its own row
    page.reload()
    masses = page.locator("#rows-measurements tbody tr").first
    assert masses.locator("button.correct").text_content() == "Исправить"
    assert masses.locator("button.strike").text_content() == "Вычеркнуть"
    edit_row(page, masses, "correct", {"pin_mass_after": "12,3402"}, "")
    assert page.text_content("#fix-err-measurements-reason") == (
        "укажите, почему показание исправлено"
    )
    page.focus("tr.correcting input[name=reason]")
    page.keyboard.type("перепутана цифра")
    page.keyboard.press("Enter")
    until(lambda: page.locator("tr.correcting").count() == 0)
    after = masses.locator("td[data-channel=pin_mass_after]")
    assert after.get_attribute("data-index") == "1"  # the second row posted holds it
    assert after.locator("s.typed").text_content() == "12,3401"
    assert after.locator("s.typed").get_attribute("title") == "Исправлено: перепутана цифра"
    assert after.locator("span.value").text_content() == "12,3402"
    values = read_columns(url, run_id, "measurements")
    assert values == {"pin_mass_before": [12.3456], "pin_mass_after": [12.3402]}
    page.close()

    # a key that writes MTOS only: no form on an SMTs-2 run, and no way in by the page
    mtos_page = sign_in(browser, url, MTOS_READER)
    mtos_page.goto(f"{url}/runs/{run_id}?lang=ru")
    assert mtos_page.locator("form.entry-row").count() == 0
    mtos_page.goto(f"{url}/runs/new?stand=smts2&lang=ru")
    assert mtos_page.locator("form#new-run").count() == 0
    assert mtos_page.text_content("#refusal") == (
        "У этого ключа нет права write:smts2: он не может записывать прогоны этого стенда."
    )
    mtos_page.close()


def posted_open(url: str, sim: SimulatedRun[Any]) -> str:
    """The simulated run opened and its batches posted through the API, left open."""
    with LabClient(url, WRITER) as client:
        run = client.create_run(sim.run_create)
        for seq, batch in enumerate(sim.batches):
            client.post_batch(run.id, seq, batch)
    return run.id


def edit_row(page: Any, row: Any, kind: str, cells: dict[str, str], reason: str) -> None:
    """Correct (or strike out) a row of the rows received by keyboard: its button, the
    cells typed over, the reason, Enter."""
    row.locator(f"button.{kind}").focus()
    page.keyboard.press("Enter")
    for name, text in cells.items():
        page.fill(f"tr.correcting input[name={name}]", text)
    page.focus("tr.correcting input[name=reason]")
    page.keyboard.type(reason)
    page.keyboard.press("Enter")


def test_two_corrections_of_a_cell_and_a_row_struck_out_after_the_finish_on_the_page(
    stand_server: Server, browser: Any
) -> None:
    url = stand_server.url
    sim = slide_bearing.simulate(seed=5)
    run_id = posted_open(url, sim)
    rows = [b for b in sim.batches if b.group == "rows"]
    typed_p3 = float(rows[2].columns["p3"][0])
    first, second = typed_p3 + 0.25, typed_p3 + 0.5  # within the manometer's -1 .. 100 at
    page = sign_in(browser, url)
    page.goto(f"{url}/runs/{run_id}?lang=en")
    row = page.locator("#rows-rows tbody tr[data-index='2']")
    sent: list[str] = []
    page.on("request", lambda r: sent.append(r.url) if "/readings/" in r.url else None)

    # beyond the gauge's range: refused beside the cell, nothing sent, nothing stored
    edit_row(page, row, "correct", {"p3": "150"}, "misread")
    assert page.text_content("#fix-err-rows-p3") == "p₃ = 150 at is above the limit 100 at"
    assert page.get_attribute("#fix-rows-p3", "aria-invalid") == "true"
    page.keyboard.press("Escape")
    assert page.locator("tr.correcting").count() == 0
    assert sent == [] and run_of(url, run_id)["corrections"] == 0

    # an empty reason is refused too
    edit_row(page, row, "correct", {"p3": typed(first)}, "")
    assert page.text_content("#fix-err-rows-reason") == "say why the reading is corrected"
    page.keyboard.press("Escape")
    assert sent == []

    edit_row(page, row, "correct", {"p3": typed(first)}, "a digit misread")
    until(lambda: page.locator("tr.correcting").count() == 0)
    edit_row(page, row, "correct", {"p3": typed(second)}, "the instructor read it again")
    until(lambda: page.locator("tr.correcting").count() == 0)
    # the corrected value shown, the typed one struck through with the reasons
    cell = row.locator("td[data-channel=p3]")
    assert cell.locator("span.value").text_content() == repr(second)
    was = cell.locator("s.typed")
    assert was.text_content() == repr(typed_p3)
    assert was.get_attribute("title") == (
        "Corrected: a digit misread; the instructor read it again"
    )
    # finished, the run is corrected still: a row struck out on its page
    page.on("dialog", lambda dialog: dialog.accept())
    page.click("#finish button")
    until(lambda: run_of(url, run_id)["state"] == "finished")
    page.wait_for_selector("#rows-rows tbody tr[data-index='5'] button.strike")
    assert page.locator("#entry-rows tfoot").is_hidden()  # it takes no more rows
    table = page.locator("#results table.rows").first.locator("tbody tr")
    assert table.count() == len(rows)
    struck = page.locator("#rows-rows tbody tr[data-index='5']")
    edit_row(page, struck, "strike", {}, "typed twice")
    until(lambda: "struck" in (struck.get_attribute("class") or ""))
    assert struck.get_attribute("title") == "Struck out: typed twice"
    # the results refresh: the struck row is left out of table 3.1's computed columns
    until(lambda: table.count() == len(rows) - 1)
    assert len(sent) == 3
    assert run_of(url, run_id)["corrected_after_finish"] is True

    fixes = httpx.get(f"{url}{API}/runs/{run_id}/corrections", headers=auth(READER)).json()
    cells = [
        (c["row"], c["channel"], c["was"], c["now"], c["reason"]) for c in fixes["corrections"]
    ]
    assert cells == [
        (2, "p3", typed_p3, first, "a digit misread"),
        (2, "p3", first, second, "the instructor read it again"),
        (5, None, None, None, "typed twice"),
    ]
    original = httpx.get(
        f"{url}{API}/runs/{run_id}/readings",
        params={"group": "rows", "original": "true"},
        headers=auth(READER),
    ).json()["rows"]["columns"]
    assert original["p3"][2] == typed_p3 and len(original["p3"]) == len(rows)
    # the page after a reload reads the same from the server
    page.reload()
    cell = page.locator("#rows-rows tbody tr[data-index='2'] td[data-channel=p3]")
    assert cell.locator("span.value").text_content() == repr(second)
    assert cell.locator("s.typed").text_content() == repr(typed_p3)
    assert "struck" in (page.get_attribute("#rows-rows tbody tr[data-index='5']", "class") or "")
    page.close()
    # the same run posted with the corrected value and without the struck row
    fixed = replace(rows[2], columns={**rows[2].columns, "p3": np.array([second])})
    batches = tuple(fixed if b is rows[2] else b for b in sim.batches if b is not rows[5])
    expected = reference(url, replace(sim, batches=batches))
    assert same(results_of(url, run_id), results_of(url, expected))
    report = httpx.get(
        f"{url}{API}/runs/{run_id}/report.html", headers=auth(READER), timeout=120
    ).text
    for words in ("Corrections", "a digit misread", "the instructor read it again"):
        assert words in report, words


def test_the_page_corrections_take_this_sessions_form_only(stand_server: Server) -> None:
    url = stand_server.url
    run_id = posted_open(url, slide_bearing.simulate(seed=5))
    target = f"{url}/runs/{run_id}/readings/rows/2?lang=en"
    body = {"values": {"p3": 1.0}, "reason": "misread"}
    host = {"origin": url}
    stale = "This form is not of this page's session: reload the page."

    def signed_in(client: httpx.Client, key: str, stand: str) -> str:
        """The form token of the client's new session (on the new-run form of ``stand``)."""
        client.post("/login", data={"key": key, "next": "/"}, headers=host)
        found = re.search(
            r'name="form_token" value="([^"]+)"', client.get(f"/runs/new?stand={stand}").text
        )
        assert found is not None
        return found[1]

    with (
        httpx.Client(base_url=url, timeout=30) as writer,
        httpx.Client(base_url=url, timeout=30) as mtos_writer,
    ):
        token = signed_in(writer, WRITER, "slide_bearing")
        # no form token, a made-up one, another site's page: refused, nothing stored
        for headers, message in (
            (host, stale),
            ({**host, "x-rig-form": "x" * 32}, stale),
            ({"origin": "http://evil.example", "x-rig-form": token}, None),
        ):
            answer = writer.post(target, json=body, headers=headers)
            assert answer.status_code == 403
            if message is not None:
                assert answer.json()["message"] == message
        # a key that writes MTOS runs only, with its own session's token
        mtos_token = signed_in(mtos_writer, MTOS_READER, "mtos")
        answer = mtos_writer.post(target, json=body, headers={**host, "x-rig-form": mtos_token})
        assert answer.status_code == 403
        assert answer.json()["message"] == (
            "This key lacks the scope write:slide_bearing: it may not write runs of this stand."
        )
        assert run_of(url, run_id)["corrections"] == 0
        # the server's own checks, in the page's words, naming the cell
        mine = {**host, "x-rig-form": token}
        beyond = writer.post(target, json={"values": {"p3": 150.0}, "reason": "x"}, headers=mine)
        assert beyond.status_code == 422
        assert beyond.json() == {
            "status": 422,
            "message": "Refused: p₃ = 150 at is above the limit 100 at",
            "channel": "p3",
        }
        empty = writer.post(target, json={"values": {"p3": 1.0}, "reason": " "}, headers=mine)
        assert empty.status_code == 422
        assert empty.json()["message"] == (
            "Say why the reading is corrected: the reason is required."
        )
        # not JSON, a number that is none, a NUL in the reason, not said to be JSON
        json_type = {**mine, "content-type": "application/json"}
        for bad, status in (
            (b'{"values": {"p3": 1.0}, "reason": "x"', 422),
            (b'{"values": {"p3": NaN}, "reason": "x"}', 422),
            (b'{"values": {"p3": 1.0}, "reason": "a\\u0000b"}', 422),
        ):
            assert writer.post(target, content=bad, headers=json_type).status_code == status
        text_type = {**mine, "content-type": "text/plain"}
        assert writer.post(target, content=b"{}", headers=text_type).status_code == 415
        assert run_of(url, run_id)["corrections"] == 0
        # this session's token: stored, the row as it now reads
        answer = writer.post(target, json=body, headers=mine)
        assert answer.status_code == 200 and answer.json()["values"]["p3"] == 1.0
        assert run_of(url, run_id)["corrections"] == 1
