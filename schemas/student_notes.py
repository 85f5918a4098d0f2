"""The student's own words on a run: the group, the students' names, their conclusions,
analysis of the graphs, reasons for a mismatch and observations,
written on the run's page and printed in the report beside the computed verdicts (what
``/runs/{id}/notes`` takes and answers)."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, StringConstraints

from schemas.wire import Text

#: Students named on one run (a lab group's bench team).
STUDENTS_LIMIT = 12
#: Characters of the conclusions (about two printed pages).
CONCLUSIONS_LIMIT = 8000

#: A name as written, without the spaces around it (stripped before the length is checked).
Name = Annotated[Text, AfterValidator(str.strip), StringConstraints(min_length=1, max_length=100)]


class StudentNotesWrite(BaseModel):
    """What the operator writes: every field replaces what was there (empty clears it)."""

    model_config = ConfigDict(
        extra="forbid",
        json_schema_extra={
            "examples": [
                {
                    "group": "MT-31",
                    "students": ["A. Ivanova", "B. Petrov"],
                    "conclusions": "The wear rate grows with the load, as the table shows.",
                }
            ]
        },
    )

    group: Annotated[Text, AfterValidator(str.strip), StringConstraints(max_length=100)] = ""
    students: list[Name] = Field(default_factory=list, max_length=STUDENTS_LIMIT)
    conclusions: Annotated[Text, StringConstraints(max_length=CONCLUSIONS_LIMIT)] = ""
    analysis: Annotated[Text, StringConstraints(max_length=CONCLUSIONS_LIMIT)] = ""
    """Their analysis of the graphs (lab 4, item 6 of "Иллюстрация полученных результатов")."""
    mismatch: Annotated[Text, StringConstraints(max_length=CONCLUSIONS_LIMIT)] = ""
    """The reasons they see for a mismatch of theory and experiment (lab 3, item 8)."""
    observations: Annotated[Text, StringConstraints(max_length=CONCLUSIONS_LIMIT)] = ""
    """What they observed of the wear in the run (lab 2: adhesive, oxidative)."""


class StudentNotes(StudentNotesWrite):
    """The words as stored: who wrote them last (the API key's name) and when; ``version``
    counts the writes (0: never written)."""

    version: int = 0
    by: str | None = None
    written: datetime | None = None

    @property
    def empty(self) -> bool:
        words = (self.conclusions, self.analysis, self.mismatch, self.observations)
        return not (self.group or self.students or any(w.strip() for w in words))
