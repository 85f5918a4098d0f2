"""The students' sketch in the report (issue 38 item 5): an uploaded image is printed in its
item's section in place of the frame to draw in, fitted within the page however tall or
wide it is; an item without one keeps its frame."""

from __future__ import annotations

import base64
import io
import re
import subprocess
from pathlib import Path

import pytest
from PIL import Image

from rigserver.reports import plots
from rigserver.reports.i18n import LANGS, Lang, Messages
from schemas.stands import StandKind
from tests.reports.rendered import POPPLER, laid_out, report_html, squeezed
from tests.reports.simulated import simulated

#: The SMTs-2 lab's sketch items (its report list): 4 the specimens, 5 the loading scheme.
SPECIMENS, LOADING = "Sketch of the specimens", "Loading scheme of the specimens (fig. 2.3)"


def data_uri(size: tuple[int, int]) -> str:
    out = io.BytesIO()
    Image.new("RGB", size, "navy").save(out, "PNG")
    return "data:image/png;base64," + base64.b64encode(out.getvalue()).decode("ascii")


def images_by_page(pdf: bytes, where: Path) -> list[tuple[int, int, int]]:
    """The raster images of the PDF (page, width, height in pixels), by poppler's pdfimages
    (the plots are vector drawings: a raster image is a sketch)."""
    path = where / "report.pdf"
    path.write_bytes(pdf)
    done = subprocess.run(["pdfimages", "-list", str(path)], capture_output=True, check=True)
    rows = done.stdout.decode().splitlines()[2:]
    return [(int(r.split()[0]), int(r.split()[3]), int(r.split()[4])) for r in rows if "image" in r]


def page_text(pdf: bytes, page: int) -> str:
    done = subprocess.run(
        [str(POPPLER), "-raw", "-f", str(page), "-l", str(page), "-enc", "UTF-8", "-", "-"],
        input=pdf,
        capture_output=True,
        check=True,
    )
    return squeezed(done.stdout.decode())


@pytest.mark.skipif(POPPLER is None, reason="poppler-utils missing (pdftotext, pdfimages)")
@pytest.mark.parametrize("lang", LANGS)
@pytest.mark.parametrize("size", [(300, 5000), (6000, 200)], ids=["tall", "wide"])
def test_the_uploaded_sketch_is_printed_in_its_section_within_the_page(
    lang: Lang, size: tuple[int, int], tmp_path: Path
) -> None:
    s = simulated(StandKind.SMTS2)
    with plots.recording() as drawn:
        html = report_html(s, lang, sketches={4: data_uri(size)})
    t = Messages(lang)
    specimens, loading = t.gettext(SPECIMENS), t.gettext(LOADING)
    sections = dict(re.findall(r"<h2>([^<]*)</h2>(.*?)</section>", html, re.S))
    assert '<img class="sketch" src="data:image/png;base64,' in sections[specimens]
    assert "space frame" not in sections[specimens]
    assert "space frame" in sections[loading]  # no upload: the frame to draw in stays
    rendered = laid_out(f"smts2 with a sketch ({lang})", html, drawn)
    assert rendered.outside == []  # nothing beyond the page, the image's box included
    (found,) = images_by_page(rendered.pdf, tmp_path)
    page, width, height = found
    assert (width, height) == size  # the image as uploaded, scaled on the page only
    assert squeezed(specimens) in page_text(rendered.pdf, page)
