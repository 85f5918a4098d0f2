"""The exceptions of rigclient.

::

    Exception
     └── RigclientError              anything rigclient reports
          ├── ServerError            the server did not take what the lab PC sent
          │    ├── ServerRefused     the API's own problem document with a 4xx status other
          │    │                     than 408/425/429: the request itself is wrong (its title,
          │    │                     detail, fields, and the method and URL asked)
          │    └── ServerUnavailable the server stayed unreachable or overloaded past the
          │                          retry budget (the last cause is chained)
          ├── SpoolError             the local spool could not keep a batch (nothing of it
          │    │                     was acknowledged to the caller)
          │    ├── SpoolFull         the disk is full, or the spool reached its size or age
          │    │                     bound (names the setting and its value)
          │    ├── SpoolBusy         another process holds the spool (names its pid, command
          │    │                     and the spool)
          │    ├── SpoolDamaged      what the spool holds no longer matches the checksum
          │    │                     written with it (names the run, the batch, the file)
          │    ├── SpoolUnreadable   SQLite cannot read the spool's file: the spool is
          │    │                     damaged (names the command that saves what is left)
          │    └── UnknownRun        no run with this local or server id in the spool
          └── InputError (also ValueError)
                                     a file, a map or a column the agent cannot read; names
                                     the file, the line and the column

Transport errors of httpx and sqlite3 errors are translated at rigclient's boundary and
chained with ``raise ... from``; they never leave rigclient bare.
"""

from __future__ import annotations

from schemas.problems import Problem


class RigclientError(Exception):
    """Base of every error rigclient raises."""


class ServerError(RigclientError):
    """The server did not take a request."""


def problem_text(problem: Problem) -> str:
    """The API's problem in a line: status, title, detail, and the first offending fields."""
    fields = "; ".join(e.message for e in problem.errors[:3] if e.message)
    text = f"{problem.status} {problem.title}: {problem.detail}"
    return f"{text} ({fields})" if fields and fields not in text else text


class ServerRefused(ServerError):
    """The API answered that the request itself is wrong (its problem document, 4xx).

    Whether that stops anything is the caller's choice: the spool's sender refuses a batch
    only on a 422 and tries every other answer again (:mod:`rigclient.sender`).
    """

    def __init__(self, problem: Problem, *, method: str = "", url: str = "") -> None:
        text = problem_text(problem)
        if url:
            text += f" [{method} {url}]"
        super().__init__(text)
        self.problem = problem
        self.method, self.url = method, url


class ServerUnavailable(ServerError):
    """The server stayed unreachable or overloaded after every retry."""


class SpoolError(RigclientError):
    """The spool could not take or give back what was asked."""


class SpoolFull(SpoolError):
    """No room for a batch: the disk is full or a bound of the spool is reached."""


class SpoolBusy(SpoolError):
    """Another process holds the spool's lock: one agent per spool."""


class SpoolDamaged(SpoolError):
    """The spool's file was damaged: a batch or an opening no longer matches its checksum."""


class SpoolUnreadable(SpoolError):
    """SQLite cannot read the spool's file (``database disk image is malformed``): the
    message names ``rigclient salvage``, which keeps what can still be read."""


class UnknownRun(SpoolError, KeyError):
    """A run id (local or the server's) the spool does not hold."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class InputError(RigclientError, ValueError):
    """A file, map or value the agent cannot read, named by file, line and column."""

    def __init__(
        self, message: str, *, file: str = "", line: int | None = None, column: str = ""
    ) -> None:
        where = file
        if line is not None:
            where += f":{line}"
        if column:
            where += f", column {column!r}"
        super().__init__(f"{where}: {message}" if where else message)
        self.file, self.line, self.column = file, line, column
