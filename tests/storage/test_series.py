"""The series store, embedded (SQLite) and in the cluster's PostgreSQL: the same behaviour."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from rigserver.storage.cluster.series_postgres import PostgresSeries
from rigserver.storage.errors import MemberExists, MemberNotFound, SeriesNotFound
from rigserver.storage.series import SeriesStore, SqliteSeries
from schemas.series import SeriesCreate, SeriesPurpose
from tests.postgres import postgres_server, postgres_url, sqlite_or_postgres  # noqa: F401 (fixtures)

RUN_A = "20261125T120000Z-0000000a"
RUN_B = "20261125T120000Z-0000000b"


@pytest.fixture(params=["sqlite", "postgres"])
def series(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[SeriesStore]:
    yield from sqlite_or_postgres(
        request,
        lambda: SqliteSeries(tmp_path / "series.sqlite"),
        PostgresSeries,
        "rig_series_members, rig_series",
    )


def test_a_series_keeps_its_runs_in_the_order_they_joined(series: SeriesStore) -> None:
    made = series.create(SeriesCreate(name="oils", purpose=SeriesPurpose.COMPARISON, factor="oil"))
    series.add(made.id, RUN_B, "I-40A", stand="smts2")
    got = series.add(made.id, RUN_A, "I-20A", stand="smts2")
    assert [(m.run_id, m.level) for m in got.members] == [(RUN_B, "I-40A"), (RUN_A, "I-20A")]
    assert series.get(made.id) == got
    assert got.factor == "oil" and got.created == made.created
    with pytest.raises(MemberExists):
        series.add(made.id, RUN_A, "I-20A", stand="smts2")
    assert [m.run_id for m in series.remove(made.id, RUN_B).members] == [RUN_A]
    with pytest.raises(MemberNotFound):
        series.remove(made.id, RUN_B)


def test_a_run_in_two_series_and_the_list_newest_first(series: SeriesStore) -> None:
    first = series.create(SeriesCreate(name="1", purpose=SeriesPurpose.REPEATABILITY))
    second = series.create(SeriesCreate(name="2", purpose=SeriesPurpose.REPEATABILITY))
    series.add(first.id, RUN_A, None, stand="smts2")
    series.add(second.id, RUN_A, None, stand="smts2")
    assert [s.id for s in series.list()] == [second.id, first.id]
    with pytest.raises(SeriesNotFound):
        series.get("s-000000000000")
    with pytest.raises(SeriesNotFound):
        series.add("s-000000000000", RUN_A, None, stand="smts2")


def test_the_series_survive_reopening(tmp_path: Path) -> None:
    store = SqliteSeries(tmp_path / "series.sqlite")
    made = store.create(SeriesCreate(name="kept", purpose=SeriesPurpose.REPEATABILITY))
    store.add(made.id, RUN_A, None, stand="smts2")
    store.close()
    again = SqliteSeries(tmp_path / "series.sqlite")
    assert again.get(made.id).members[0].run_id == RUN_A
    again.close()
