"""The PDF of a report: WeasyPrint lays out the same HTML (A4 from its ``@page`` rule), with
the inline SVG plots kept as vector graphics."""

from __future__ import annotations


def html_to_pdf(html: str) -> bytes:
    """The PDF of a standalone HTML page (no external resources)."""
    # Imported here: WeasyPrint takes about half a second to import, and only PDFs need it.
    from weasyprint import HTML  # type: ignore[import-untyped]

    pdf: bytes = HTML(string=html).write_pdf()
    return pdf
