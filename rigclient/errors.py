"""The exceptions of rigclient.

::

    Exception
     └── RigclientError              anything rigclient reports
          ├── ServerError            the server did not take what the lab PC sent
          │    ├── ServerRefused     an answer that a retry would not change (4xx other than
          │    │                     408/429, 500): the problem's title, detail and fields
          │    └── ServerUnavailable the server stayed unreachable or overloaded past the
          │                          retry budget (the last cause is chained)
          ├── SpoolError             the local spool could not keep a batch (nothing of it
          │    │                     was acknowledged to the caller)
          │    ├── SpoolFull         the disk is full, or the spool reached its size or age
          │    │                     bound (names the setting and its value)
          │    └── UnknownRun        no run with this local id in the spool
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


class ServerRefused(ServerError):
    """The server answered with a problem that retrying the same request will not change."""

    def __init__(self, problem: Problem) -> None:
        fields = "; ".join(e.message for e in problem.errors[:3] if e.message)
        text = f"{problem.status} {problem.title}: {problem.detail}"
        super().__init__(f"{text} ({fields})" if fields and fields not in text else text)
        self.problem = problem


class ServerUnavailable(ServerError):
    """The server stayed unreachable or overloaded after every retry."""


class SpoolError(RigclientError):
    """The spool could not take or give back what was asked."""


class SpoolFull(SpoolError):
    """No room for a batch: the disk is full or a bound of the spool is reached."""


class UnknownRun(SpoolError, KeyError):
    """A local run id the spool does not hold."""


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
