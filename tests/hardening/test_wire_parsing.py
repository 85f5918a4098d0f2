"""Wire and parsing (issue 22, item 10): JSON nested hundreds of levels deep is refused
naming the depth limit (it answered 500, a RecursionError); a flag is never taken for a
number (``configuration.spring_rate: true`` was stored as 1.0, the calculators took it, a
boolean npz array was stored as 0 and 1); an npz member whose bytes do not match its
CRC-32 is refused naming the member (a flipped bit stored 1.5 as 1.5625). Each is
answered 4xx with a problem, and nothing of it is stored."""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient

from rigserver.api.npz import parse_npz
from rigserver.api.problems import ApiProblem
from schemas.readings import NPZ_MEDIA_TYPE
from schemas.strict_json import MAX_DEPTH, JsonRefused, strict_loads
from tests.api.conftest import READER, WRITER, auth
from tests.hardening.conftest import API, friction, is_problem, npz_body, open_run
from tests.hardening.test_hostile_values import _stored_runs

JSON = {**auth(WRITER), "content-type": "application/json"}
NPZ = {**auth(WRITER), "content-type": NPZ_MEDIA_TYPE}


def _rows(client: TestClient, run_id: str) -> int:
    run = client.get(f"{API}/runs/{run_id}", headers=auth(READER)).json()
    return sum(run["rows"].values())


def _nested(depth: int, inner: str = "1") -> str:
    """``depth`` arrays, one in another, around ``inner``."""
    return "[" * depth + inner + "]" * depth


# --- nesting ---------------------------------------------------------------------------------


def test_the_limit_is_the_depth_of_arrays_and_objects() -> None:
    assert strict_loads(_nested(MAX_DEPTH)) is not None
    assert strict_loads('{"a":' * (MAX_DEPTH - 1) + _nested(1) + "}" * (MAX_DEPTH - 1))
    for text in (_nested(MAX_DEPTH + 1), '{"a":' * MAX_DEPTH + "[]" + "}" * MAX_DEPTH):
        with pytest.raises(JsonRefused, match=f"deeper than {MAX_DEPTH} levels"):
            strict_loads(text)


@pytest.mark.parametrize("depth", [MAX_DEPTH + 1, 300, 500, 999, 5000, 100_000])
def test_readings_nested_deep_are_refused_naming_the_limit(
    hdf5_client: TestClient, depth: int
) -> None:
    run_id = open_run(hdf5_client)
    body = '{"seq": 0, "group": "friction", "columns": {"time": ' + _nested(depth) + "}}"
    r = hdf5_client.post(f"{API}/runs/{run_id}/readings", content=body.encode(), headers=JSON)
    assert 400 <= r.status_code < 500, r.text
    assert is_problem(r)
    if depth > 200:  # the fast parser refuses what it cannot nest: the reason is the depth
        assert f"deeper than {MAX_DEPTH} levels" in r.json()["detail"], r.json()
    assert _rows(hdf5_client, run_id) == 0


@pytest.mark.parametrize("depth", [MAX_DEPTH + 1, 500, 5000])
@pytest.mark.parametrize(
    ("path", "template"),
    [
        (f"{API}/runs", '{{"stand": "smts2", "operator": "x", "configuration": {{"pin": {}}}}}'),
        (f"{API}/runs", '{{"stand": "smts2", "operator": "x", "notes": {}}}'),
        (f"{API}/models/wear/theoretical", '{{"load": {}}}'),
        (f"{API}/series", '{{"name": {}, "purpose": "repeatability"}}'),
    ],
)
def test_other_bodies_nested_deep_are_refused_naming_the_limit(
    hdf5_client: TestClient, tmp_path: Path, depth: int, path: str, template: str
) -> None:
    body = template.format(_nested(depth))
    r = hdf5_client.post(path, content=body.encode(), headers=JSON)
    assert r.status_code == 422, r.text
    assert is_problem(r)
    assert f"deeper than {MAX_DEPTH} levels" in r.json()["detail"], r.json()
    assert _stored_runs(tmp_path / "data") == 0


# --- a flag is no number -----------------------------------------------------------------------

_FLAGS_FOR_NUMBERS = [
    ("mtos", {"spring_rate": True}, "configuration.spring_rate"),
    ("mtos", {"spring_rate": "20"}, "configuration.spring_rate"),
    ("mtos", {"accuracy": {"arms": False}}, "configuration.accuracy.arms"),
    ("smts2", {"pin": {"hardness": True}}, "configuration.pin.hardness"),
    ("slide_bearing", {"manometer_z": [True, -0.2, 0, 0.2, 0.4]}, "configuration.manometer_z.0"),
    ("profilometer", {"levels": True}, "configuration.levels"),
    ("profilometer", {"levels": 10.0}, "configuration.levels"),
    ("mtos", {"signed_sensors": 1}, "configuration.signed_sensors"),
]


@pytest.mark.parametrize(("stand", "configuration", "field"), _FLAGS_FOR_NUMBERS)
def test_a_flag_or_text_for_a_configured_number_is_refused_naming_the_field(
    hdf5_client: TestClient,
    tmp_path: Path,
    stand: str,
    configuration: dict[str, object],
    field: str,
) -> None:
    body = {"stand": stand, "operator": "x", "configuration": configuration}
    r = hdf5_client.post(f"{API}/runs", json=body, headers=auth(WRITER))
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["field"] == field, r.json()
    assert _stored_runs(tmp_path / "data") == 0


def test_whole_numbers_and_arrays_are_still_taken_for_configured_numbers(
    hdf5_client: TestClient,
) -> None:
    body = {
        "stand": "slide_bearing",
        "operator": "x",
        "configuration": {"omega0": 329, "manometer_z": [-0.4, -0.2, 0, 0.2, 0.4]},
    }
    r = hdf5_client.post(f"{API}/runs", json=body, headers=auth(WRITER))
    assert r.status_code == 201, r.text
    configuration = r.json()["configuration"]
    assert configuration["omega0"] == 329.0
    assert configuration["manometer_z"] == [-0.4, -0.2, 0.0, 0.2, 0.4]


@pytest.mark.parametrize(
    ("path", "body", "field"),
    [
        ("/models/wear/theoretical", {"load": True}, "load"),
        ("/models/wear/theoretical", {"load": "300"}, "load"),
        ("/models/bearing/friction", {"chi": False}, "chi"),
        ("/models/roughness/equilibrium", {"nu": True}, "nu"),
        ("/models/mechanism/dynamic-errors", {"settle": True}, "settle"),
        ("/models/mechanism/dynamic-errors", {"samples": True}, "samples"),
        ("/models/mechanism/dynamic-errors", {"move": {"duration": True}}, "move.duration"),
        ("/models/mechanism/dynamic-errors", {"move": {"q_end": [1, True, 0]}}, "move.q_end.1"),
        ("/models/mechanism/dynamic-errors", {"arm": {"m1": True}}, "arm.m1"),
    ],
)
def test_a_flag_for_a_calculators_input_is_refused_naming_the_field(
    hdf5_client: TestClient, path: str, body: dict[str, object], field: str
) -> None:
    r = hdf5_client.post(f"{API}{path}", json=body, headers=auth(READER))
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["field"] == field, r.json()


def test_a_calculators_whole_numbers_are_still_numbers(hdf5_client: TestClient) -> None:
    r = hdf5_client.post(f"{API}/models/wear/theoretical", json={"load": 300}, headers=auth(READER))
    assert r.status_code == 200, r.text


def test_a_boolean_npz_array_is_refused_naming_the_member(hdf5_client: TestClient) -> None:
    run_id = open_run(hdf5_client)
    columns: dict[str, object] = dict(friction(0, 3))
    columns["revolutions"] = np.array([False, True, True])
    r = hdf5_client.post(
        f"{API}/runs/{run_id}/readings?seq=0&group=friction",
        content=npz_body(columns),
        headers=NPZ,
    )
    assert r.status_code == 422, r.text
    assert r.json()["errors"][0]["field"] == "columns.revolutions", r.json()
    assert "'|b1' is not a real number type" in r.json()["detail"]
    assert _rows(hdf5_client, run_id) == 0


# --- CRC-32 ------------------------------------------------------------------------------------


def _damaged(value: float, becomes: float, *, deflate: bool) -> bytes:
    """An npz of the friction record whose ``load`` holds ``value`` once, that value's bytes
    then overwritten by ``becomes``'s: the CRC-32 is the original's."""
    columns = friction(0, 3)
    columns["load"] = np.array([300.0, value, 300.0])
    buffer = io.BytesIO()
    (np.savez_compressed if deflate else np.savez)(buffer, **columns)
    body = buffer.getvalue()
    if not deflate:
        old, new = np.float64(value).tobytes(), np.float64(becomes).tobytes()
        assert body.count(old) == 1
        return body.replace(old, new)
    # deflated: the member stored again, its data deflated from the damaged values, its
    # CRC-32 from the sound ones
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(body)) as src, zipfile.ZipFile(out, "w") as dst:
        for info in src.infolist():
            data = src.read(info)
            if info.filename == "load.npy":
                data = data.replace(np.float64(value).tobytes(), np.float64(becomes).tobytes())
                dst.writestr(info, data, compress_type=zipfile.ZIP_DEFLATED)
                continue
            dst.writestr(info, data, compress_type=zipfile.ZIP_DEFLATED)
    packed = out.getvalue()
    sound = zipfile.ZipFile(io.BytesIO(body)).getinfo("load.npy").CRC
    damaged = zipfile.ZipFile(io.BytesIO(packed)).getinfo("load.npy").CRC
    assert packed.count(damaged.to_bytes(4, "little")) == 2  # local header, directory
    return packed.replace(damaged.to_bytes(4, "little"), sound.to_bytes(4, "little"))


def test_the_damage_is_one_bit() -> None:
    # 1.5 = 0x3FF8 0000 0000 0000, 1.5625 = 0x3FF9 0000 0000 0000 (IEEE 754): one bit apart
    a = int.from_bytes(np.float64(1.5).tobytes(), "little")
    b = int.from_bytes(np.float64(1.5625).tobytes(), "little")
    assert bin(a ^ b).count("1") == 1


@pytest.mark.parametrize("deflate", [False, True], ids=["stored", "deflated"])
def test_a_member_that_fails_its_crc_is_refused_naming_it(deflate: bool) -> None:
    with pytest.raises(ApiProblem) as refused:
        parse_npz(_damaged(1.5, 1.5625, deflate=deflate), 1 << 20)
    problem = refused.value.problem
    assert problem.status == 422
    assert "member 'load.npy': CRC-32" in problem.detail, problem.detail
    assert problem.errors[0].field == "columns.load"


@pytest.mark.parametrize("deflate", [False, True], ids=["stored", "deflated"])
def test_a_damaged_npz_batch_is_not_stored(hdf5_client: TestClient, deflate: bool) -> None:
    run_id = open_run(hdf5_client)
    r = hdf5_client.post(
        f"{API}/runs/{run_id}/readings?seq=0&group=friction",
        content=_damaged(301.5, 301.5625, deflate=deflate),
        headers=NPZ,
    )
    assert r.status_code == 422, r.text
    assert is_problem(r)
    assert r.json()["errors"][0]["field"] == "columns.load"
    assert _rows(hdf5_client, run_id) == 0
    sound = npz_body({**friction(0, 3), "load": np.array([300.0, 301.5, 300.0])})
    r = hdf5_client.post(
        f"{API}/runs/{run_id}/readings?seq=0&group=friction", content=sound, headers=NPZ
    )
    assert r.status_code == 201, r.text
    stored = hdf5_client.get(
        f"{API}/runs/{run_id}/readings?group=friction", headers=auth(READER)
    ).json()
    assert stored["friction"]["columns"]["load"] == [300.0, 301.5, 300.0]
