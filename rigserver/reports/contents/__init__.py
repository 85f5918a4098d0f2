"""Each lab's report list as data: the manual's items ("Оформление отчета") with their
numbers, and what each asks the report to hold: a heading, the formulas by their numbers,
the tables and the plots by their captions, the students' own part.

The report is built from it where the list decides (the tasks, the students' sections);
``tests/reports/test_contents.py`` reads the rendered PDF and finds every item of every
list, so an item added here that the report does not produce fails there.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from schemas.messages import N_


class Students(StrEnum):
    """What the students put into an item themselves, and where the report takes it from:
    a frame to draw in on paper, or the field of their notes of that name
    (:class:`schemas.student_notes.StudentNotes`), printed as written or as ruled lines."""

    SKETCH = "sketch"
    ANALYSIS = "analysis"
    MISMATCH = "mismatch"
    OBSERVATIONS = "observations"
    CONCLUSIONS = "conclusions"


@dataclass(frozen=True, slots=True)
class Item:
    """One item of a lab's report list.

    ``number`` is its place in the manual's list (the bulleted lists counted from 1);
    ``manual`` the manual's words (Russian, as printed). The rest is what the report holds
    for it: ``heading`` (an English message id, printed translated), ``formulas`` (numbers
    of :data:`rigserver.reports.equations.EQUATIONS`, each written out with its number),
    ``tables`` and ``figures`` (message keys of their captions in
    :data:`rigserver.reports.i18n.MESSAGES`; ``"a|b"`` when either is right, as a plot whose
    caption says what it holds), a bare number (``"4.1"``) for the manual's table of that
    number, ``words`` (message ids the report prints,
    such as a configuration field's name), ``students`` (a section of the students' own
    part under ``heading``). ``part`` is the manual's part of the lab work the item belongs
    to (lab 2: 1 the wear test, 2 the adhesive against the oxidative test).
    """

    number: int
    manual: str
    heading: str = ""
    formulas: tuple[str, ...] = ()
    tables: tuple[str, ...] = ()
    figures: tuple[str, ...] = ()
    words: tuple[str, ...] = ()
    students: Students | None = None
    part: int = 1


@dataclass(frozen=True, slots=True)
class Contents:
    """A lab's report list and the main tasks of the work (printed under its aim)."""

    items: tuple[Item, ...]
    tasks: tuple[str, ...] = ()

    def of_part(self, part: int) -> tuple[Item, ...]:
        return tuple(i for i in self.items if i.part == part)

    def students(self, parts: tuple[int, ...] = (1,)) -> tuple[Item, ...]:
        """The items the students fill in, in the list's order."""
        return tuple(i for i in self.items if i.students is not None and i.part in parts)

    def sketches(self) -> tuple[Item, ...]:
        """The items that take a sketch (an image uploaded, or a frame drawn in on paper),
        of every part of the work."""
        return tuple(i for i in self.items if i.students is Students.SKETCH)

    def words(self) -> list[tuple[Students, str]]:
        """The fields of their notes the students write for a run of this lab, each with
        the heading it is printed under (the first item's of that field; observations, which
        lab 2 prints once per mode, under :data:`OBSERVED`)."""
        found: dict[Students, str] = {}
        for item in self.students(parts=(1, 2)):
            field = item.students
            if field is not None and field is not Students.SKETCH and field not in found:
                found[field] = OBSERVED if field is Students.OBSERVATIONS else item.heading
        return list(found.items())


OBSERVED = N_("Observations of the wear in this run")
