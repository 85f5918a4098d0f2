"""The students' words on a run, written by a key with the run's stand's write scope and
kept with who wrote them (:mod:`rigserver.storage.notes`)."""

from __future__ import annotations

from rigserver.api.auth import ApiKey
from rigserver.api.cases.found import load_run
from rigserver.api.deps import Services, require_write
from schemas.student_notes import StudentNotes, StudentNotesWrite


def author(key: ApiKey) -> str:
    """Who wrote the words, as the store keeps it: the key's name, else its fingerprint."""
    return key.name or f"key {key.fingerprint[:12]}"


def write_notes(
    services: Services, run_id: str, body: StudentNotesWrite, caller: ApiKey | None
) -> StudentNotes:
    """Store the words on the run for a key with the run's stand's write scope (403 else)."""
    run = load_run(services, run_id)
    key = require_write(caller, run.stand)
    return services.notes.put(run.id, body, by=author(key))
