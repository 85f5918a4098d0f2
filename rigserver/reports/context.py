"""What a stand's report is built from, and what it gives back."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from rigserver.analysis import Readings
from rigserver.reports.document import Section, Text
from rigserver.reports.i18n import Messages
from schemas.channels import ChannelGroup
from schemas.runs import Run
from schemas.stands import Stand


@dataclass(frozen=True, slots=True)
class Context:
    """The run, its stand's declaration, its readings (for the measured tables and the long
    traces drawn) and the language."""

    run: Run
    stand: Stand
    readings: Readings
    t: Messages

    def group(self, name: str) -> ChannelGroup:
        found = self.stand.group(name)
        if found is None:
            raise KeyError(f"stand {self.stand.kind.value} declares no group {name!r}")
        return found


@dataclass(frozen=True, slots=True)
class LabReport:
    """One stand's part of the report: its sections and its conclusions."""

    sections: Sequence[Section]
    conclusions: Sequence[Text]
