"""The real service over HTTP: uvicorn in a subprocess, HDF5 storage on disk, httpx."""

from __future__ import annotations

import math
import threading
import time
from pathlib import Path

import h5py
import httpx
import pytest

from rigserver.analysis import analyse
from schemas.runs import Run
from tests.analysis.conftest import FakeReadings
from tests.api.conftest import MTOS_STEPS, READER, WRITER, Server, auth

API = "/api/v1"


def post_run(url: str, stand: str) -> str:
    r = httpx.post(
        f"{url}{API}/runs", json={"stand": stand, "operator": "Sidorov"}, headers=auth(WRITER)
    )
    assert r.status_code == 201, r.text
    return str(r.json()["id"])


def post(
    url: str, run_id: str, seq: int, group: str, columns: dict[str, list[float]]
) -> httpx.Response:
    return httpx.post(
        f"{url}{API}/runs/{run_id}/readings",
        json={"seq": seq, "group": group, "columns": columns},
        headers=auth(WRITER),
        timeout=10,
    )


def test_mtos_run_over_http_and_the_hdf5_file(server: Server) -> None:
    run_id = post_run(server.url, "mtos")
    steps = MTOS_STEPS
    assert (
        post(server.url, run_id, 0, "measurements", {"x_zero": [0.0], "y_zero": [0.0]}).status_code
        == 201
    )
    assert post(server.url, run_id, 1, "steps", steps).status_code == 201
    r = httpx.post(f"{server.url}{API}/runs/{run_id}/finish", headers=auth(WRITER), timeout=30)
    assert r.status_code == 200, r.text
    res = httpx.get(f"{server.url}{API}/runs/{run_id}/results", headers=auth(READER)).json()
    # (4.13)-(4.16) with the default calibration k = 20 N/mm, l1 = 0.2 m, l2 = 0.025 m
    f = [
        20.0 * dl * 0.2 / 0.025 / n for dl, n in zip(steps["indicator"], steps["load"], strict=True)
    ]
    assert [s["friction_measured"] for s in res["values"]["steps"]] == pytest.approx(f, rel=1e-12)
    # (4.11): e_x = h0·cos45° - |X_уст - X| with h0 = 100 μm
    e_x = [100e-6 * math.cos(math.pi / 4) - abs(x) * 1e-6 for x in steps["x"]]
    chi = [math.hypot(ex, ex) / 100e-6 for ex in e_x]
    assert [s["chi"] for s in res["values"]["steps"]] == pytest.approx(chi, rel=1e-9)
    assert res["units"]["steps[].friction_measured"] == "1"
    h5 = httpx.get(f"{server.url}{API}/runs/{run_id}/readings?format=hdf5", headers=auth(READER))
    assert h5.status_code == 200
    path = server.data_dir / "download.h5"
    path.write_bytes(h5.content)
    with h5py.File(path, "r") as f5:
        entry = f5["entry"]
        assert entry.attrs["NX_class"] in ("NXentry", b"NXentry")
        datasets: list[h5py.Dataset] = []
        entry.visititems(
            lambda name, obj: datasets.append(obj) if isinstance(obj, h5py.Dataset) else None
        )
        channels = [d for d in datasets if "results" not in d.name and d.name.count("/") == 3]
        assert channels, "no channel datasets"
        for d in channels:
            assert "units" in d.attrs, d.name
            assert "long_name" in d.attrs, d.name
        assert list(entry["steps"]["load"][()]) == steps["load"]


def test_kill_9_while_clients_post_loses_no_acknowledged_batch(server: Server) -> None:
    """Clients post while the server is killed with SIGKILL; after a restart every
    acknowledged batch is there exactly once and every run file opens."""
    runs = [post_run(server.url, "smts2") for _ in range(3)]
    acked: dict[str, list[int]] = {r: [] for r in runs}
    stop = threading.Event()
    n = 50

    def client(run_id: str) -> None:
        seq = 0
        with httpx.Client(timeout=5) as http:
            while not stop.is_set():
                cols = {
                    "time": [seq * n + i for i in range(n)],
                    "load": [300.0] * n,
                    "speed": [1000.0] * n,
                    "friction_moment": [3.0] * n,
                    "revolutions": [float(seq)] * n,
                }
                try:
                    r = http.post(
                        f"{server.url}{API}/runs/{run_id}/readings",
                        json={"seq": seq, "group": "friction", "columns": cols},
                        headers=auth(WRITER),
                    )
                except httpx.TransportError:
                    time.sleep(0.05)
                    continue
                if r.status_code in (200, 201):
                    acked[run_id].append(seq)
                    seq += 1

    threads = [threading.Thread(target=client, args=(r,)) for r in runs]
    for t in threads:
        t.start()
    for _ in range(3):
        time.sleep(0.6)
        server.kill()
        time.sleep(0.2)
        server.start()
    time.sleep(0.5)
    stop.set()
    for t in threads:
        t.join()
    for run_id in runs:
        run = httpx.get(f"{server.url}{API}/runs/{run_id}", headers=auth(READER)).json()
        got = sorted(set(acked[run_id]))
        assert got == list(range(len(got))), "a client skipped a seq"
        assert run["rows"]["friction"] >= len(got) * n
        data = httpx.get(
            f"{server.url}{API}/runs/{run_id}/readings?group=friction", headers=auth(READER)
        ).json()["friction"]["columns"]
        times = data["time"]
        assert len(times) == len(set(times)), "a batch was stored twice"
        assert set(range(len(got) * n)) <= set(int(t) for t in times)
    server.stop()
    for path in Path(server.data_dir, "runs").glob("*.h5"):
        with h5py.File(path, "r") as f5:
            assert "entry" in f5


def _cases() -> dict[str, tuple[dict[str, dict[str, list[float]]], dict[str, float]]]:
    """Manual-shaped readings of each stand (groups, measurements)."""
    n = 400
    limbs = [float(a) for a in range(0, 181, 10)]
    x_prof = [i * 0.5e-3 for i in range(4001)]  # mm, 0.5 μm step over 2 mm
    return {
        "smts2": (
            {
                "friction": {
                    "time": [0.1 * i for i in range(n)],
                    "load": [300.0] * n,
                    "speed": [1000.0] * n,
                    "friction_moment": [4.0 - 1.3 * (1 - math.exp(-i / 50)) for i in range(n)],
                    "revolutions": [i * 150 / (n - 1) for i in range(n)],
                }
            },
            {"pin_mass_before": 12.5, "pin_mass_after": 12.47, "disc_ra": 0.78},
        ),
        "slide_bearing": (
            {
                "rows": {
                    "limb_angle": limbs,
                    **{
                        f"p{k}": [
                            max(0.0, math.sin(math.radians(a))) * (1.0 - 0.3 * abs(k - 3))
                            for a in limbs
                        ]
                        for k in range(1, 6)
                    },
                    "x": [420.0 - 0.1 * a for a in limbs],
                    "y": [330.0 + 0.1 * a for a in limbs],
                    "t1": [30.0] * len(limbs),
                    "t2": [38.0] * len(limbs),
                }
            },
            {"x_zero": 500.0, "y_zero": 400.0, "load_zone_end": 180.0, "loader_scale": 12.0},
        ),
        "mtos": (
            {
                "steps": {
                    "load": [500.0, 1500.0, 2500.0],
                    "indicator": [0.03, 0.05, 0.20],
                    "x": [-30.0, -20.0, -10.0],
                    "y": [-35.0, -25.0, -12.0],
                    "t1": [30.0] * 3,
                    "t2": [34.0, 36.0, 40.0],
                    "t3": [38.0, 42.0, 50.0],
                    "t4": [38.5, 42.5, 51.0],
                    "t5": [39.0, 43.0, 52.0],
                    "regime": [1.0, 2.0, 3.0],
                }
            },
            {"x_zero": 0.0, "y_zero": 0.0},
        ),
        "profilometer": (
            {
                "profile": {
                    "x": x_prof,
                    "y": [
                        0.8 * math.cos(2 * math.pi * x / 0.05)
                        + 0.3 * math.cos(2 * math.pi * x / 0.013)
                        for x in x_prof
                    ],
                }
            },
            {"base_length": 2.0, "subrange": 3.2},
        ),
    }


@pytest.mark.parametrize("stand", ["smts2", "slide_bearing", "mtos", "profilometer"])
def test_each_stand_over_http_gives_the_pipeline_results(server: Server, stand: str) -> None:
    """Post manual-shaped readings over HTTP, finish, fetch: the results equal the stand's
    pipeline run in this process on the same numbers (checked by hand in tests/analysis)."""
    groups, measurements = _cases()[stand]
    run_id = post_run(server.url, stand)
    seq = 0
    for group, cols in groups.items():
        assert post(server.url, run_id, seq, group, cols).status_code == 201
        seq += 1
    m_cols = {k: [v] for k, v in measurements.items()}
    assert post(server.url, run_id, seq, "measurements", m_cols).status_code == 201
    finished = httpx.post(
        f"{server.url}{API}/runs/{run_id}/finish", headers=auth(WRITER), timeout=60
    )
    assert finished.status_code == 200, finished.text
    got = httpx.get(f"{server.url}{API}/runs/{run_id}/results", headers=auth(READER)).json()
    run = Run.model_validate(finished.json())
    expected = analyse(run, FakeReadings(groups, measurements)).payload
    assert got["units"] == expected["units"]
    assert _close(got["values"], expected["values"])
    assert not got["values"].get("pending"), got["values"]["pending"]


def _close(a: object, b: object) -> bool:
    if isinstance(a, dict) and isinstance(b, dict):
        assert a.keys() == b.keys()
        return all(_close(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        assert len(a) == len(b)
        return all(_close(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float) and isinstance(b, float):
        assert a == pytest.approx(b, rel=1e-12, abs=1e-300)
        return True
    assert a == b
    return True
