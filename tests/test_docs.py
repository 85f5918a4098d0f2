"""The README and docs/: every relative link names a file of the repository, none points
outside it, and every correction docs/models.md lists (E1, E2, ...) is pinned by a test
that names it."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")


def test_every_link_names_a_file_of_the_repository() -> None:
    broken = []
    for page in PAGES:
        for target in LINK.findall(page.read_text(encoding="utf-8")):
            if re.match(r"[a-z]+://", target):
                continue
            path = (page.parent / target).resolve()
            if not path.is_relative_to(ROOT) or not path.exists():
                broken.append(f"{page.relative_to(ROOT)}: {target}")
    assert broken == []


def test_the_readme_links_the_formulas_and_the_notes() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    for page in ("docs/models.md", "docs/source-notes.md", "docs/reynolds.md", "docs/speed.md"):
        assert f"]({page})" in readme, page


def test_every_correction_is_pinned_by_a_test() -> None:
    models = (ROOT / "docs" / "models.md").read_text(encoding="utf-8")
    listed = sorted(set(re.findall(r"\*\*(E\d+) \(", models)), key=lambda e: int(e[1:]))
    assert listed == [f"E{k}" for k in range(1, 11)]
    tests = "\n".join(p.read_text(encoding="utf-8") for p in (ROOT / "tests").rglob("test_*.py"))
    # named in a comment ("E4") or a test's name ("test_asperity_radius_e5"), not a number
    unpinned = [e for e in listed if not re.search(rf"(?<![a-z0-9]){e}(?!\d)", tests, re.I)]
    assert unpinned == []
