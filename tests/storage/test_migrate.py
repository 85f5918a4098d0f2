"""``rigserver migrate``: an embedded data directory into PostgreSQL, resumable, verified."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import psycopg
import pytest

from rigserver.cli import main
from rigserver.commands.migrate import MigrationMismatch, migrate
from rigserver.storage import HDF5Store, PostgresStore
from schemas.runs import RunQuery, RunState
from tests.storage.conftest import T0, friction, make_run

KEY = "migrate-key-0001"


def _data_dir(path: Path) -> dict[str, list[int]]:
    """Three runs: finished with results, aborted, open with a key; seq -> what was posted."""
    seqs: dict[str, list[int]] = {}
    with HDF5Store(path) as store:
        finished = store.create_run(make_run(created=T0))
        for seq, start in ((2, 0), (0, 5), (7, 10)):  # out of order, as a retrying client
            store.append(finished.id, seq, "friction", friction(start, 5))
        store.append(finished.id, 3, "measurements", {"pin_mass_before": np.array([1.5])})
        store.set_results(finished.id, {"values": {"f": 0.12}, "units": {"f": "1"}}, {"f": 0.12})
        store.end_run(finished.id, RunState.FINISHED)
        store.correct_reading(finished.id, "friction", 2, {"load": 310.0}, "misread", "lab PC")
        aborted = store.create_run(make_run(operator="B"))
        store.append(aborted.id, 0, "friction", friction(0, 3))
        store.end_run(aborted.id, RunState.ABORTED)
        opened = store.create_run(make_run(operator="C"), key=KEY)
        store.append(opened.id, 0, "friction", friction(0, 4))
        seqs = {finished.id: [0, 2, 3, 7], aborted.id: [0], opened.id: [0]}
    return seqs


def test_every_run_moves_with_its_receipts_readings_results_and_key(
    tmp_path: Path, postgres_url: str
) -> None:
    seqs = _data_dir(tmp_path / "data")
    with PostgresStore(postgres_url, files_dir=tmp_path / "files") as target:
        assert migrate(tmp_path / "data", target).copied == 3
        with HDF5Store(tmp_path / "data") as source:
            assert target.list_runs(RunQuery()) == source.list_runs(RunQuery())
            for run_id, posted in seqs.items():
                for seq in posted:
                    assert target.receipt(run_id, seq) == source.receipt(run_id, seq)
                for group in ("friction", "measurements"):
                    want, got = source.read(run_id, group), target.read(run_id, group)
                    assert want.keys() == got.keys()
                    for name in want:
                        np.testing.assert_array_equal(got[name], want[name])
                    assert target.last_values(run_id, group) == source.last_values(run_id, group)
                assert target.results(run_id) == source.results(run_id)
                assert target.corrections(run_id) == source.corrections(run_id)
        assert len(target.corrections(next(iter(seqs)))) == 1
        opened = next(r for r in target.list_runs(RunQuery(state=RunState.OPEN)).runs)
        # the lab PC goes on: its retry is a duplicate, its next batch is taken
        assert target.append(opened.id, 0, "friction", friction(0, 4)).duplicate
        assert target.append(opened.id, 1, "friction", friction(4, 4)).group_rows == 8
        assert target.create_run(make_run(operator="C"), key=KEY).id == opened.id


def test_a_stopped_migration_resumes_and_a_difference_is_found(
    tmp_path: Path, postgres_url: str
) -> None:
    _data_dir(tmp_path / "data")

    def stop_after_first(line: str) -> None:
        raise KeyboardInterrupt(line)

    with PostgresStore(postgres_url, files_dir=tmp_path / "files") as target:
        with pytest.raises(KeyboardInterrupt):
            migrate(tmp_path / "data", target, progress=stop_after_first)
        done = migrate(tmp_path / "data", target)
        assert (done.copied, done.verified) == (2, 1)
    # a batch's readings changed in the cluster (same rows): the digests tell
    with psycopg.connect(postgres_url, autocommit=True) as conn:
        conn.execute(
            "UPDATE rig_batches SET payload = (SELECT payload FROM rig_batches b "
            "WHERE b.seq = 0 AND b.run_id = rig_batches.run_id) WHERE seq = 2"
        )
    with (
        PostgresStore(postgres_url, files_dir=tmp_path / "files") as target,
        pytest.raises(MigrationMismatch, match="readings in the cluster differ"),
    ):
        migrate(tmp_path / "data", target)


def test_the_command(tmp_path: Path, postgres_url: str, capsys: pytest.CaptureFixture[str]) -> None:
    _data_dir(tmp_path / "data")
    assert main(["migrate", "--from", str(tmp_path / "data"), "--to", postgres_url]) == 0
    assert main(["migrate", "--from", str(tmp_path / "data"), "--to", postgres_url]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out == [
        "rigserver: 3 runs copied, 0 there already; all verified",
        "rigserver: 0 runs copied, 3 there already; all verified",
    ]
    with pytest.raises(SystemExit, match="not a data directory"):
        main(["migrate", "--from", str(tmp_path / "nowhere"), "--to", postgres_url])
