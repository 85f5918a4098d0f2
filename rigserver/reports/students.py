"""The students' part of a report: the sections of their lab's report list they fill in
themselves (:mod:`rigserver.reports.contents`), each headed as the manual heads it, holding
what they wrote or the sketch they uploaded on the run's page, else room for it on paper (a
frame to draw in, ruled lines to write on): an empty section is printed, never left out."""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence

from markupsafe import Markup, escape

from rigserver.reports.contents import Item, Students
from rigserver.reports.document import Section, Space
from rigserver.reports.i18n import Messages
from schemas.student_notes import StudentNotes

#: Lines of room on paper: a frame to draw a sketch in, ruled lines for the words.
FRAME_LINES = 10
RULED_LINES = {Students.CONCLUSIONS: 8}
DEFAULT_LINES = 6


def written(words: str) -> Markup:
    """The students' words as they wrote them: escaped, blank lines parting paragraphs, line
    breaks kept."""
    parts = re.split(r"\n\s*\n", words.strip())
    return Markup("").join(
        Markup("<p>{}</p>").format(Markup("<br>").join(escape(line) for line in p.splitlines()))
        for p in parts
    )


def section(t: Messages, item: Item, words: str = "", sketch: str = "") -> Section:
    """The section of one students' item: what they wrote or the ``sketch`` they uploaded
    (a ``data:`` URI), else its room on paper."""
    assert item.students is not None
    if item.students is Students.SKETCH:
        space = Space(image=sketch) if sketch else Space(frame=True, lines=FRAME_LINES)
    elif words.strip():
        space = Space(text=written(words))
    else:
        space = Space(lines=RULED_LINES.get(item.students, DEFAULT_LINES))
    return Section(t.gettext(item.heading), [space])


def students_part(
    t: Messages, items: Sequence[Item], notes: StudentNotes, sketches: Mapping[int, str] = {}
) -> list[Section]:
    """The sections of ``items`` (the students' items of a list), with the words of
    ``notes`` and the ``sketches`` uploaded (item number -> the image as a ``data:`` URI)."""
    return [section(t, item, _words(notes, item), sketches.get(item.number, "")) for item in items]


def _words(notes: StudentNotes, item: Item) -> str:
    """What the students wrote for ``item``: the field of their notes it names (a sketch is
    drawn on paper, never written)."""
    field = item.students
    return "" if field is None or field is Students.SKETCH else str(getattr(notes, field.value))
