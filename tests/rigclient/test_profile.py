"""A profile read from CSV, TXT, X3P and SDF (ASCII and binary) gives one Ra, the closed
form's; and ``rigclient profile`` posts it as a profilometer run whose Ra the server agrees
with."""

from __future__ import annotations

from pathlib import Path

import httpx
import numpy as np
import pytest
import sdfio
import x3pio

from rigclient.errors import InputError
from rigclient.profile import read_profile, roughness_lines
from rigserver.core.roughness import profile_parameters
from schemas.stands import StandKind
from tests.api.conftest import READER, WRITER, Server, auth
from tests.reports.simulated import simulated
from tests.rigclient.conftest import AgentProcess

A_UM = 1.5  # amplitude, µm
WAVE_MM = 0.1  # wavelength, mm
STEP_MM = 0.0005  # sampling step, mm (0.5 µm, the ABRIS-PM7 default)
POINTS = 8001  # 4 mm: 40 whole periods


def sine() -> tuple[np.ndarray, np.ndarray]:
    x = np.arange(POINTS) * STEP_MM
    return x, A_UM * np.sin(2 * np.pi * x / WAVE_MM)


def ra_um(x_mm: np.ndarray, y_um: np.ndarray) -> float:
    return profile_parameters(x=x_mm * 1e-3, y=y_um * 1e-6).ra * 1e6


def write_all(directory: Path) -> dict[str, Path]:
    x, y = sine()
    files = {
        "csv": directory / "trace.csv",
        "txt": directory / "trace.txt",
        "x3p": directory / "trace.x3p",
        "sdf-ascii": directory / "trace-ascii.sdf",
        "sdf-binary": directory / "trace-binary.sdf",
    }
    with files["csv"].open("w", encoding="utf-8") as f:  # a header with units, decimal comma
        f.write("x [mm];y [um]\n")
        f.writelines(f"{a:.6f};{b:.9f}\n".replace(".", ",") for a, b in zip(x, y, strict=True))
    with files["txt"].open("w", encoding="utf-8") as f:  # no header: x in mm, y in µm
        f.write("# ABRIS-PM7 trace\n")
        f.writelines(f"{a:.6f}  {b:.9f}\n" for a, b in zip(x, y, strict=True))
    x3pio.write(files["x3p"], y * 1e-6, x_scale=STEP_MM * 1e-3)
    for name, fmt in (
        ("sdf-ascii", sdfio.FileFormat.ASCII),
        ("sdf-binary", sdfio.FileFormat.BINARY),
    ):
        sdfio.write(
            files[name],
            (y * 1e-6).reshape(1, -1),
            x_scale=STEP_MM * 1e-3,
            y_scale=STEP_MM * 1e-3,
            format=fmt,
        )
    return files


def test_every_format_reads_back_to_the_same_ra(tmp_path: Path) -> None:
    files = write_all(tmp_path)
    traces = {name: read_profile(path) for name, path in files.items()}
    reference = ra_um(traces["csv"].x, traces["csv"].y)
    # closed form: a sine of amplitude A over whole periods has Ra = 2A/π
    assert reference == pytest.approx(2 * A_UM / np.pi, rel=1e-3)
    for name, trace in traces.items():
        assert trace.x.size == POINTS, name
        np.testing.assert_allclose(trace.x, traces["csv"].x, atol=1e-9, err_msg=name)
        assert ra_um(trace.x, trace.y) == pytest.approx(reference, rel=1e-6), name


def test_an_areal_row_out_of_range_and_a_damaged_file_are_named(tmp_path: Path) -> None:
    files = write_all(tmp_path)
    with pytest.raises(InputError, match=r"trace\.x3p: row 3 asked, the file has rows 0 to 0"):
        read_profile(files["x3p"], row=3)
    damaged = tmp_path / "damaged.x3p"
    damaged.write_bytes(files["x3p"].read_bytes()[:200])
    with pytest.raises(InputError, match=r"damaged\.x3p: not a readable X3P file"):
        read_profile(damaged)


@pytest.mark.slow
def test_the_profile_command_posts_a_profilometer_run(
    server: Server, agents: list[AgentProcess], tmp_path: Path
) -> None:
    files = write_all(tmp_path)
    args = ["profile", str(files["x3p"]), "--url", server.url, "--key", WRITER]
    args += ["--spool", str(tmp_path / "spool"), "--operator", "Orlova", "--rows", "3000"]
    agents.append(AgentProcess(args, tmp_path / "agent.log"))
    lines = agents[-1].output(120)
    assert agents[-1].proc.returncode == 0, (tmp_path / "agent.log").read_text()
    results = httpx.get(
        f"{server.url}/api/v1/runs/{lines[0]}/results", headers=auth(READER), timeout=60
    ).json()
    x, y = sine()
    assert results["values"]["ra"] == pytest.approx(ra_um(x, y) * 1e-6, rel=1e-6)
    # the server's ISO roughness beside the manual's, as the command printed them: the
    # sine (λ = 0.1 mm) of Ra 0.95 µm picks λc = 0.8 mm, which passes it whole
    iso = results["values"]["iso"]
    assert (iso["lambda_c"], iso["lambda_s"]) == (0.8e-3, 2.5e-6)
    assert iso["ra"] == pytest.approx(2 * A_UM / np.pi * 1e-6, rel=2e-3)
    said = (tmp_path / "agent.log").read_text(encoding="utf-8")
    assert roughness_lines(results)[1] in said and "manual (lab work 1): Ra = " in said


def test_the_roughness_lines_name_the_filter() -> None:
    payload = simulated(StandKind.PROFILOMETER).result.payload
    v = payload["values"]
    manual, iso = roughness_lines(payload)
    assert manual.startswith(f"manual (lab work 1): Ra = {v['ra'] * 1e6:.3g} µm, Rq = ")
    assert iso.startswith(
        "ISO 21920-2 (λc = 0.8 mm; λs = 2.5 µm; by Ra, table of ISO 21920-3; kept, corrected "
        f"by renormalised weights (ISO 16610-28)): Ra = {v['iso']['ra'] * 1e6:.3g} µm, "
    )
    assert ", Rk = " in iso and ", Rpk = " in iso and ", RSm = " in iso
