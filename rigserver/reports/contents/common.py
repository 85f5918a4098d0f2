"""The headings every lab's list shares: the work's number and title, its aim, its tasks."""

from __future__ import annotations

from rigserver.reports.contents import Item
from rigserver.reports.i18n import MESSAGES
from schemas.messages import N_

TASKS = N_("Main tasks of the work")


def opening(kind: str, *, joint: bool = False) -> tuple[Item, Item, Item]:
    """The first items of every list: the number and title, the aim, the main tasks (one
    item, 2, where the list is ``joint``: "цель и основные задачи работы")."""
    return (
        Item(1, "номер и название работы", heading=MESSAGES["title." + kind]),
        Item(2, "цель работы", heading=MESSAGES["aim"]),
        Item(2 if joint else 3, "основные задачи работы", heading=TASKS),
    )
