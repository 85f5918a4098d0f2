"""Many stands at once and clients racing on one run: no loss, no duplicate, no deadlock."""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest

from rigsim.client import LabClient, RunOutcome
from rigsim.simulators import simulate
from tests.api.conftest import WRITER, auth, read_columns
from tests.hardening.conftest import API, friction, npz_body, open_run, serve

DEADLINE = 120.0  # s: a thread still running then is a deadlock


@pytest.mark.slow
def test_eight_simulated_stands_post_to_eight_runs_at_once(tmp_path: Path) -> None:
    """Two of each stand kind, as fast as the server takes them, half of them binary: every
    run holds exactly its simulated readings, in order, and is finished with results."""
    server = serve(tmp_path)
    stands = [
        (kind, seed)
        for kind in ("smts2", "slide_bearing", "mtos", "profilometer")
        for seed in (1, 2)
    ]
    sims = [simulate(kind, seed=seed) for kind, seed in stands]
    outcomes: list[RunOutcome | BaseException | None] = [None] * len(sims)

    def stand(i: int) -> None:
        try:
            with LabClient(server.url, WRITER, seed=i) as client:
                outcomes[i] = client.run(sims[i], binary=i % 2 == 1)
        except BaseException as exc:  # reported below
            outcomes[i] = exc

    threads = [threading.Thread(target=stand, args=(i,)) for i in range(len(sims))]
    try:
        for t in threads:
            t.start()
        for t in threads:
            t.join(DEADLINE)
        assert not any(t.is_alive() for t in threads), "a stand is stuck"
        for sim, outcome in zip(sims, outcomes, strict=True):
            assert isinstance(outcome, RunOutcome), outcome
            assert outcome.run.state.value == "finished"
            assert outcome.run.batches == len(sim.batches)
            assert outcome.results["values"]
            for group in outcome.run.rows:
                stored = read_columns(server.url, outcome.run.id, group)
                expected = sim.columns(group)
                assert outcome.run.rows[group] == sim.rows(group)
                for name, values in expected.items():
                    got = np.asarray(stored[name], dtype=float)
                    if len(got) == len(values):
                        np.testing.assert_array_equal(got, values)
                    else:  # measurements: named single values, the latest posted
                        np.testing.assert_array_equal(got, values[~np.isnan(values)][-1:])
    finally:
        server.stop()


def test_two_clients_race_on_one_run_with_interleaved_and_repeated_seqs(tmp_path: Path) -> None:
    """Both clients post the same batches 0..N-1 (JSON and binary), each batch until it is
    acknowledged and some twice: every seq is stored once, each answer is the first receipt
    or a duplicate of it, and the rows are those of the N batches in order."""
    server = serve(tmp_path)
    n, rows = 60, 25
    try:
        with httpx.Client(base_url=server.url, timeout=30) as http:
            run_id = open_run(http)
        receipts: list[list[dict[str, Any]]] = [[], []]
        errors: list[BaseException] = []
        barrier = threading.Barrier(2)

        def client(k: int) -> None:
            url = f"{server.url}{API}/runs/{run_id}/readings"
            try:
                with httpx.Client(timeout=30) as http:
                    barrier.wait()
                    for seq in range(n):
                        columns = friction(seq * rows, rows)
                        for _ in range(2 if (seq + k) % 7 == 0 else 1):  # some repeated
                            if (seq + k) % 2:
                                r = http.post(
                                    url,
                                    params={"seq": seq, "group": "friction"},
                                    content=npz_body(columns),
                                    headers={**auth(WRITER), "content-type": "application/x-npz"},
                                )
                            else:
                                batch = {name: v.tolist() for name, v in columns.items()}
                                r = http.post(
                                    url,
                                    json={"seq": seq, "group": "friction", "columns": batch},
                                    headers=auth(WRITER),
                                )
                            assert r.status_code in (200, 201), r.text
                            assert r.json()["duplicate"] == (r.status_code == 200)
                            receipts[k].append(r.json())
            except BaseException as exc:
                errors.append(exc)

        threads = [threading.Thread(target=client, args=(k,)) for k in (0, 1)]
        for t in threads:
            t.start()
        for t in threads:
            t.join(DEADLINE)
        assert not any(t.is_alive() for t in threads), "a client is stuck"
        assert errors == []
        first = {}
        for receipt in receipts[0] + receipts[1]:
            key = receipt["seq"]
            got = {k: v for k, v in receipt.items() if k != "duplicate"}
            first.setdefault(key, got)
            assert got == first[key], "a seq has two different receipts"
        fresh = [r for r in receipts[0] + receipts[1] if not r["duplicate"]]
        assert sorted(r["seq"] for r in fresh) == list(range(n))  # stored once each
        assert [first[s]["group_rows"] for s in range(n)] == [(s + 1) * rows for s in range(n)]
        stored = read_columns(server.url, run_id, "friction")
        np.testing.assert_array_equal(stored["time"], np.arange(n * rows))
    finally:
        server.stop()
