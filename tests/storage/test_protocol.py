"""The RunStore protocol, checked on both stores (MemoryStore and HDF5Store)."""

from __future__ import annotations

import json
import threading
from datetime import datetime, timedelta
from typing import Any

import h5py
import numpy as np
import pytest

from rigserver.storage import (
    KeyReused,
    RunExists,
    RunNotFound,
    RunNotOpen,
    RunStore,
    SequenceConflict,
)
from schemas.runs import RunQuery, RunState
from schemas.stands import StandKind, default_stands
from tests.storage.conftest import T0, friction, make_run

SMTS2_FRICTION = [c.name for c in default_stands()[StandKind.SMTS2].group("friction").channels]


def test_create_and_get(store: RunStore) -> None:
    run = make_run(title="Wear of St3sp on R9")
    created = store.create_run(run)
    assert created.rows == {"friction": 0, "measurements": 0}
    assert created.batches == 0
    assert store.get_run(run.id) == created
    assert created.model_dump(exclude={"rows"}) == run.model_dump(exclude={"rows"})


def test_create_twice_raises(store: RunStore) -> None:
    run = make_run()
    store.create_run(run)
    with pytest.raises(RunExists, match=run.id):
        store.create_run(run)


def test_create_needs_an_open_run(store: RunStore) -> None:
    with pytest.raises(ValueError, match="must be open"):
        store.create_run(make_run(state=RunState.FINISHED))


def test_list_runs_filters_and_pages(store: RunStore) -> None:
    # six runs an hour apart: stands alternate, operators A, B, A, B, ...
    runs = [
        make_run(
            stand=(StandKind.SMTS2, StandKind.MTOS)[k % 2],
            operator="AB"[k % 2],
            created=T0 + timedelta(hours=k),
        )
        for k in range(6)
    ]
    for run in runs:
        store.create_run(run)
    store.end_run(runs[0].id, RunState.FINISHED)
    newest_first = [r.id for r in reversed(runs)]

    page = store.list_runs(RunQuery())
    assert page.total == 6
    assert [r.id for r in page.runs] == newest_first
    assert [r.id for r in store.list_runs(RunQuery(stand=StandKind.MTOS)).runs] == [
        runs[5].id,
        runs[3].id,
        runs[1].id,
    ]
    assert store.list_runs(RunQuery(operator="A")).total == 3
    finished = store.list_runs(RunQuery(state=RunState.FINISHED))
    assert [r.id for r in finished.runs] == [runs[0].id]
    assert finished.runs[0].state is RunState.FINISHED
    # since <= created < until: hours 1, 2, 3
    window = store.list_runs(RunQuery(since=T0 + timedelta(hours=1), until=T0 + timedelta(hours=4)))
    assert [r.id for r in window.runs] == [runs[3].id, runs[2].id, runs[1].id]
    # a naive time is UTC
    naive = store.list_runs(RunQuery(since=datetime(2024, 3, 1, 14, 0)))
    assert [r.id for r in naive.runs] == [runs[5].id]
    paged = store.list_runs(RunQuery(limit=2, offset=2))
    assert paged.total == 6
    assert [r.id for r in paged.runs] == newest_first[2:4]
    combined = store.list_runs(RunQuery(stand=StandKind.SMTS2, operator="A", limit=1, offset=1))
    assert combined.total == 3
    assert [r.id for r in combined.runs] == [runs[2].id]


def test_append_and_read_round_trip(store: RunStore) -> None:
    run = store.create_run(make_run())
    sizes = [3, 1, 250, 7]
    starts = np.cumsum([0, *sizes])
    receipts = [
        store.append(run.id, seq, "friction", friction(int(starts[seq]), n))
        for seq, n in enumerate(sizes)
    ]
    assert [r.rows for r in receipts] == sizes
    assert [r.group_rows for r in receipts] == list(starts[1:])
    assert not any(r.duplicate for r in receipts)
    stored = store.get_run(run.id)
    assert stored.batches == 4
    assert stored.rows == {"friction": 261, "measurements": 0}

    everything = store.read(run.id, "friction")
    assert list(everything) == SMTS2_FRICTION
    expected = friction(0, 261)
    for name in SMTS2_FRICTION:
        np.testing.assert_array_equal(everything[name], expected[name])
    part = store.read(run.id, "friction", ["speed", "time"], 10, 20)
    assert list(part) == ["speed", "time"]
    np.testing.assert_array_equal(part["time"], expected["time"][10:20])
    np.testing.assert_array_equal(
        store.read(run.id, "friction", ["time"], 255)["time"], expected["time"][255:]
    )
    assert store.read(run.id, "friction", ["time"], 300)["time"].size == 0
    assert store.last_values(run.id, "friction") == {
        name: float(values[-1]) for name, values in expected.items()
    }


def test_duplicate_seq_gets_the_first_receipt_and_is_stored_once(store: RunStore) -> None:
    run = store.create_run(make_run())
    first = store.append(run.id, 7, "friction", friction(0, 5))
    again = store.append(run.id, 7, "friction", friction(0, 5))
    assert again == first.model_copy(update={"duplicate": True})
    assert store.receipt(run.id, 7) == again
    assert store.receipt(run.id, 8) is None
    assert store.get_run(run.id).rows["friction"] == 5
    assert store.get_run(run.id).batches == 1
    assert store.read(run.id, "friction", ["time"])["time"].size == 5


def test_reused_seq_with_other_content_conflicts(store: RunStore) -> None:
    run = store.create_run(make_run())
    store.append(run.id, 0, "friction", friction(0, 5))
    with pytest.raises(SequenceConflict, match="seq 0"):
        store.append(run.id, 0, "friction", friction(1, 5))
    with pytest.raises(SequenceConflict, match="seq 0"):
        store.append(run.id, 0, "measurements", {"pin_mass_before": [12.0]})
    assert store.get_run(run.id).rows["friction"] == 5


def test_ended_run_takes_no_readings_but_answers_retries(store: RunStore) -> None:
    run = store.create_run(make_run())
    first = store.append(run.id, 0, "friction", friction(0, 5))
    ended = store.end_run(run.id, RunState.ABORTED)
    assert ended.state is RunState.ABORTED
    assert ended.ended is not None
    with pytest.raises(RunNotOpen, match="aborted"):
        store.append(run.id, 1, "friction", friction(5, 5))
    assert store.append(run.id, 0, "friction", friction(0, 5)) == first.model_copy(
        update={"duplicate": True}
    )
    with pytest.raises(RunNotOpen, match="already aborted"):
        store.end_run(run.id, RunState.FINISHED)
    with pytest.raises(ValueError, match="not open"):
        store.end_run(store.create_run(make_run()).id, RunState.OPEN)


def test_unknown_run_is_not_found(store: RunStore) -> None:
    missing = make_run().id
    calls = [
        lambda: store.get_run(missing),
        lambda: store.append(missing, 0, "friction", friction(0, 1)),
        lambda: store.receipt(missing, 0),
        lambda: store.read(missing, "friction"),
        lambda: store.iter_chunks(missing, "friction"),
        lambda: store.last_values(missing, "friction"),
        lambda: store.set_results(missing, {}, {}),
        lambda: store.results(missing),
        lambda: store.end_run(missing, RunState.FINISHED),
        lambda: store.run_file(missing),
    ]
    for call in calls:
        with pytest.raises(RunNotFound, match=missing):
            call()


@pytest.mark.parametrize(
    ("seq", "group", "columns", "message"),
    [
        (0, "wear", {"time": [1.0]}, "no channel group 'wear'"),
        (0, "friction", {**friction(0, 2), "torque": [1.0, 2.0]}, "no channel 'torque'"),
        (0, "friction", {"time": [1.0]}, "'load' is missing"),
        (0, "friction", {**friction(0, 2), "time": [1.0]}, "differ in length"),
        (0, "measurements", {}, "carries no channel"),
        (0, "measurements", {"pin_mass_before": [[1.0]]}, "flat list"),
        (-1, "friction", friction(0, 2), "seq must be >= 0"),
    ],
)
def test_batch_that_does_not_fit_is_refused(
    store: RunStore, seq: int, group: str, columns: dict[str, object], message: str
) -> None:
    run = store.create_run(make_run())
    with pytest.raises(ValueError, match=message):
        store.append(run.id, seq, group, columns)  # type: ignore[arg-type]
    assert store.get_run(run.id).batches == 0
    assert store.receipt(run.id, max(seq, 0)) is None


def test_measurements_are_padded_and_the_latest_value_counts(store: RunStore) -> None:
    run = store.create_run(make_run())
    store.append(run.id, 0, "measurements", {"pin_mass_before": [12.5]})
    receipt = store.append(
        run.id, 1, "measurements", {"pin_mass_after": [12.4, 12.3], "disc_ra": [0.8]}
    )
    assert (receipt.rows, receipt.group_rows) == (2, 3)
    got = store.read(run.id, "measurements")
    nan = np.nan
    np.testing.assert_array_equal(got["pin_mass_before"], [12.5, nan, nan])
    np.testing.assert_array_equal(got["pin_mass_after"], [nan, 12.4, 12.3])
    np.testing.assert_array_equal(got["disc_ra"], [nan, 0.8, nan])
    latest = {"pin_mass_before": 12.5, "pin_mass_after": 12.3, "disc_ra": 0.8}
    assert store.last_values(run.id, "measurements") == latest
    assert store.last_values(run.id, "friction") == {}
    store.end_run(run.id, RunState.FINISHED)
    assert store.last_values(run.id, "measurements") == latest


def test_iter_chunks_covers_every_row_once(store: RunStore) -> None:
    run = store.create_run(make_run())
    for seq in range(7):
        store.append(run.id, seq, "friction", friction(143 * seq, 143))  # 1001 rows
    for ended in (False, True):
        if ended:
            store.end_run(run.id, RunState.FINISHED)
        chunks = list(store.iter_chunks(run.id, "friction", ["time", "load"], rows=64))
        assert [len(c["time"]) for c in chunks] == [64] * 15 + [1001 - 15 * 64]
        assert all(list(c) == ["time", "load"] for c in chunks)
        np.testing.assert_array_equal(
            np.concatenate([c["time"] for c in chunks]), friction(0, 1001)["time"]
        )
    with pytest.raises(ValueError, match="rows must be >= 1"):
        store.iter_chunks(run.id, "friction", rows=0)
    with pytest.raises(ValueError, match="no channel 'torque'"):
        store.iter_chunks(run.id, "friction", ["torque"])
    assert list(store.iter_chunks(run.id, "measurements")) == []


RESULTS = {
    "stand": "smts2",
    "values": {
        "friction_steady": 0.0131,
        "experimental": {"intensity": 2.5e-9, "wear_depth": 1.2e-6},
        "rows": [{"chi": 0.5, "phi": 10.0}, {"chi": None, "phi": 20.0}],
        "adequate": True,
        "contact": "elastic",
    },
    "units": {
        "friction_steady": "1",
        "experimental.intensity": "1",
        "experimental.wear_depth": "m",
        "rows[].chi": "1",
        "rows[].phi": "deg",
    },
}
KEY_RESULTS = {"friction_steady": 0.0131, "experimental.intensity": 2.5e-9}


def test_results_and_the_finished_file_read_with_bare_h5py(store: RunStore) -> None:
    run = store.create_run(make_run(title="Wear test"))
    store.append(run.id, 0, "friction", friction(0, 100))
    store.append(run.id, 1, "measurements", {"pin_mass_before": [12.5]})
    store.set_results(run.id, RESULTS, KEY_RESULTS)
    assert store.results(run.id) == RESULTS
    finished = store.end_run(run.id, RunState.FINISHED)
    assert finished.key_results == KEY_RESULTS
    assert store.list_runs(RunQuery()).runs[0].key_results == KEY_RESULTS

    declared = {g.name: g for g in default_stands()[StandKind.SMTS2].groups}
    with h5py.File(store.run_file(run.id), "r") as f:
        entry = f["entry"]
        assert entry.attrs["NX_class"] == "NXentry"
        assert f.attrs["default"] == "entry"
        assert bool(entry.attrs["finalized"])
        start = datetime.fromisoformat(entry["start_time"].asstr()[()])
        end = datetime.fromisoformat(entry["end_time"].asstr()[()])
        assert start == run.created
        assert end == finished.ended
        assert json.loads(entry.attrs["configuration"]) == run.configuration
        assert entry.attrs["operator"] == "Ivanova"
        stored_run = json.loads(entry.attrs["run"])
        assert stored_run["state"] == "finished"
        assert stored_run["rows"] == {"friction": 100, "measurements": 1}
        assert entry["friction"].attrs["NX_class"] == "NXdata"
        assert entry["friction"].attrs["axes"] == "time"
        assert entry["measurements"].attrs["NX_class"] == "NXcollection"

        numeric: list[str] = []
        entry.visititems(
            lambda name, obj: (
                numeric.append(name)
                if isinstance(obj, h5py.Dataset) and obj.dtype == np.float64
                else None
            )
        )
        for name in numeric:  # every numeric dataset says what it is and in what unit
            assert "units" in entry[name].attrs, name
            assert "long_name" in entry[name].attrs, name
        for group, decl in declared.items():
            for ch in decl.channels:
                ds = entry[group][ch.name]
                assert ds.attrs["units"] == ch.unit
                assert ds.attrs["long_name"] == ch.long_name
                assert ds.maxshape == (None,)
                assert ds.chunks is not None
        np.testing.assert_array_equal(entry["friction/load"][:], friction(0, 100)["load"])
        assert json.loads(entry["results/json"].asstr()[()]) == RESULTS
        assert entry["results/values/experimental/wear_depth"].attrs["units"] == "m"
        assert entry["results/values/experimental/wear_depth"][()] == 1.2e-6
        np.testing.assert_array_equal(entry["results/values/rows/chi"][:], [0.5, np.nan])
        assert entry["results/values/rows/phi"].attrs["long_name"] == "rows[].phi"
        assert "results/values/adequate" not in entry  # no unit: in the JSON only


def test_results_of_a_finished_run_can_be_replaced(store: RunStore) -> None:
    run = store.create_run(make_run())
    store.append(run.id, 0, "friction", friction(0, 10))
    store.end_run(run.id, RunState.FINISHED)
    assert store.results(run.id) is None
    store.set_results(run.id, RESULTS, KEY_RESULTS)
    assert store.results(run.id) == RESULTS
    assert store.get_run(run.id).key_results == KEY_RESULTS
    with h5py.File(store.run_file(run.id), "r") as f:
        assert bool(f["entry"].attrs["finalized"])
        assert json.loads(f["entry/results/json"].asstr()[()]) == RESULTS
        np.testing.assert_array_equal(f["entry/friction/time"][:], friction(0, 10)["time"])


def test_run_file_of_an_open_run_is_a_consistent_snapshot(store: RunStore) -> None:
    run = store.create_run(make_run())
    store.append(run.id, 0, "friction", friction(0, 10))
    with h5py.File(store.run_file(run.id), "r") as f:
        assert "finalized" not in f["entry"].attrs
        np.testing.assert_array_equal(f["entry/friction/time"][:], friction(0, 10)["time"])
    store.append(run.id, 1, "friction", friction(10, 5))
    with h5py.File(store.run_file(run.id), "r") as f:
        assert f["entry/friction/time"].shape == (15,)


def test_results_must_be_json_and_key_results_finite(store: RunStore) -> None:
    run = store.create_run(make_run())
    with pytest.raises(ValueError, match="JSON-able"):
        store.set_results(run.id, {"values": {1j: 1}}, {})
    with pytest.raises(ValueError, match="'h' = nan"):
        store.set_results(run.id, {}, {"h": float("nan")})
    assert store.results(run.id) is None


def test_concurrent_appends_from_threads(store: RunStore) -> None:
    runs = [store.create_run(make_run()).id for _ in range(2)]
    errors: list[BaseException] = []

    def post(run_id: str, first_seq: int) -> None:
        try:
            for seq in range(first_seq, first_seq + 50):
                store.append(run_id, seq, "friction", friction(seq * 4, 4))
        except BaseException as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=post, args=(r, s)) for r in runs for s in (0, 50)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    for run_id in runs:
        assert store.get_run(run_id).rows["friction"] == 400
        times = np.sort(store.read(run_id, "friction", ["time"])["time"])
        np.testing.assert_array_equal(times, friction(0, 400)["time"])


def test_seqs_out_of_order_are_stored_and_their_retries_recognised(store: RunStore) -> None:
    # a store looks a seq up only at or below the largest stored (a larger one is new):
    # seqs below it that were never stored must still be taken, and retries recognised
    run = store.create_run(make_run())
    store.append(run.id, 5, "measurements", {"pin_mass_before": [12.5]})
    store.append(run.id, 2, "measurements", {"pin_mass_after": [12.4]})
    again = store.append(run.id, 2, "measurements", {"pin_mass_after": [12.4]})
    assert again.duplicate
    assert store.append(run.id, 5, "measurements", {"pin_mass_before": [12.5]}).duplicate
    assert store.get_run(run.id).batches == 2


def test_the_callers_arrays_may_change_after_they_are_stored(store: RunStore) -> None:
    run = store.create_run(make_run())
    columns = friction(0, 5)
    expected = {name: values.copy() for name, values in columns.items()}
    store.append(run.id, 0, "friction", columns)
    for values in columns.values():
        values[:] = -1.0  # the lab PC's buffer, reused for the next batch
    stored = store.read(run.id, "friction")
    for name, values in expected.items():
        np.testing.assert_array_equal(stored[name], values)


def test_a_key_opens_one_run_however_often_it_is_sent(store: RunStore) -> None:
    first = store.create_run(make_run(), key="9b2c6a0e-lab-pc-3")
    again = store.create_run(make_run(), key="9b2c6a0e-lab-pc-3")  # another id proposed
    assert again == first
    assert store.list_runs(RunQuery()).total == 1
    other = store.create_run(make_run(), key="another key")
    assert other.id != first.id
    with pytest.raises(KeyReused, match="9b2c6a0e-lab-pc-3"):
        store.create_run(make_run(operator="Petrov"), key="9b2c6a0e-lab-pc-3")
    assert store.list_runs(RunQuery()).total == 2


def test_the_readings_version_grows_with_every_batch_stored(store: RunStore) -> None:
    run = store.create_run(make_run())
    assert store.readings_version(run.id) == 0
    store.append(run.id, 0, "friction", friction(0, 3))
    store.append(run.id, 1, "measurements", {"pin_mass_before": np.array([1.0])})
    assert store.readings_version(run.id) == 2
    store.append(run.id, 0, "friction", friction(0, 3))  # a retry stores nothing
    assert store.readings_version(run.id) == 2
    store.end_run(run.id, RunState.FINISHED)
    assert store.readings_version(run.id) == 2
    with pytest.raises(RunNotFound):
        store.readings_version("no-such-run")


def _imported_batches(run_id: str, rows: int = 10) -> list[tuple[int, Any, dict[str, Any]]]:
    from rigserver.storage._checks import StoredBatch, padded, prepare

    decl = default_stands()[StandKind.SMTS2].group("measurements")
    assert decl is not None
    friction_batch = prepare("friction", friction(0, rows))
    weighing = prepare("measurements", {"pin_mass_before": [12.5]})
    return [
        (0, StoredBatch("friction", rows, rows, friction_batch.digest), friction(0, rows)),
        (1, StoredBatch("measurements", 1, 1, weighing.digest), padded(decl, weighing.columns, 1)),
    ]


def test_import_run_stores_it_whole(store: RunStore) -> None:
    run = make_run(
        state=RunState.FINISHED,
        ended=T0 + timedelta(hours=1),
        batches=2,
        rows={"friction": 10, "measurements": 1},
        key_results={"friction_steady": 0.3},
    )
    results = {"values": {"friction_steady": 0.3}, "units": {"friction_steady": "1"}}
    assert store.import_run(run, None, results, _imported_batches(run.id))
    got = store.get_run(run.id)
    assert (got.state, got.rows, got.batches, got.ended) == (
        RunState.FINISHED,
        {"friction": 10, "measurements": 1},
        2,
        run.ended,
    )
    assert store.results(run.id) == results
    np.testing.assert_array_equal(store.read(run.id, "friction")["load"], friction(0, 10)["load"])
    assert store.last_values(run.id, "measurements") == {"pin_mass_before": 12.5}
    # the id taken: nothing changes
    assert not store.import_run(run, None, None, _imported_batches(run.id, rows=3))
    assert store.get_run(run.id).rows["friction"] == 10
    with pytest.raises(RunNotOpen):
        store.append(run.id, 5, "friction", friction(10, 1))


def test_import_run_stores_nothing_when_its_batches_fail(store: RunStore) -> None:
    run = make_run(state=RunState.ABORTED, ended=T0, batches=2, rows={"friction": 10})

    def failing() -> Any:
        yield from _imported_batches(run.id)[:1]
        raise ValueError("a reading refused half way")

    with pytest.raises(ValueError, match="half way"):
        store.import_run(run, None, None, failing())
    with pytest.raises(RunNotFound):
        store.get_run(run.id)
    assert store.list_runs(RunQuery()).total == 0
