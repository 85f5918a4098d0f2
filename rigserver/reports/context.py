"""What a stand's report is built from, and what it gives back."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from rigserver.analysis import Readings
from rigserver.reports import blocks
from rigserver.reports.document import Block, Section, Table, Text
from rigserver.reports.i18n import Messages
from schemas.channels import ChannelGroup
from schemas.runs import Run
from schemas.stands import MEASUREMENTS, Stand


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

    def units(self, group: str) -> dict[str, str]:
        """The declared unit of each channel of ``group``, by the channel's name."""
        return {c.name: c.unit for c in self.group(group).channels}

    def measurements(self, resolutions: Mapping[str, float] | None = None) -> Table:
        """The single measurements posted, their table (:func:`blocks.measurements`)."""
        values = self.readings.measurements()
        return blocks.measurements(self.t, self.group(MEASUREMENTS), values, resolutions)


@dataclass(frozen=True, slots=True)
class LabReport:
    """One stand's part of the report: its sections and its conclusions."""

    sections: Sequence[Section]
    conclusions: Sequence[Text]


def sections(t: Messages, measured: Sequence[Block], processed: Sequence[Block]) -> list[Section]:
    """A lab's sections: the results of the measurements, then their processing and the
    theory."""
    return [Section(t("sec.measured"), measured), Section(t("sec.processed"), processed)]
