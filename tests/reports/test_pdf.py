"""The PDF of each stand's report: A4 pages (from the template's @page rule), the plots drawn
as vector graphics (no raster image in the file), page 1 rendered by poppler's pdftoppm."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from schemas.stands import StandKind
from tests.reports.rendered import run_report

A4 = (0.0, 0.0, 210 / 25.4 * 72, 297 / 25.4 * 72)  # 595.28 x 841.89 pt

POPPLER = ("pdfinfo", "pdfimages", "pdftoppm")
missing = [tool for tool in POPPLER if shutil.which(tool) is None]
if missing:  # a system package, as chromium is: make test installs it
    raise RuntimeError(
        f"poppler-utils missing ({', '.join(missing)}): apt-get install poppler-utils"
    )


def pdf(kind: StandKind) -> bytes:
    return run_report(kind, "en").pdf  # laid out once, shared with tests/reports/test_layout.py


def run(*args: str | Path) -> str:
    return subprocess.run([str(a) for a in args], check=True, capture_output=True, text=True).stdout


@pytest.mark.parametrize("kind", list(StandKind))
def test_pdf_pages_are_a4_with_vector_plots(kind: StandKind, tmp_path: Path) -> None:
    path = tmp_path / f"{kind.value}.pdf"
    path.write_bytes(pdf(kind))
    assert path.read_bytes().startswith(b"%PDF-")
    info = run("pdfinfo", "-box", "-f", "1", "-l", "1000", path)
    pages = int(re.search(r"^Pages:\s+(\d+)", info, re.M).group(1))  # type: ignore[union-attr]
    boxes = re.findall(r"^Page\s+\d+\s+MediaBox:\s+([\d.\s]+)$", info, re.M)
    assert pages >= 2 and len(boxes) == pages
    for box in boxes:
        assert [float(x) for x in box.split()] == pytest.approx(A4, abs=0.01)
    listed = run("pdfimages", "-list", path).strip().splitlines()
    assert len(listed) == 2, listed  # the header only: no raster image, the plots are vectors
    run("pdftoppm", "-png", "-r", "50", path, tmp_path / "page")
    shots = sorted(tmp_path.glob("page-*.png"))
    assert len(shots) == pages
    with Image.open(shots[0]) as first:
        assert first.height / first.width == pytest.approx(297 / 210, rel=0.01)
    assert sum(_blue(shot) for shot in shots) > 100  # the plots are drawn on the pages


def _blue(png: Path) -> int:
    """Pixels of matplotlib's blues (C0 lines and markers, which every stand's plots have);
    the text and the tables are black and grey."""
    with Image.open(png) as image:
        rgb = np.asarray(image.convert("RGB"), dtype=int)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    return int(((b - r > 60) & (b - g > 20)).sum())
