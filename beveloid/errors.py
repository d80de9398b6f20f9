"""User-facing error types, each with a code.

Raise :class:`UserError` for problems the user can fix (bad input, missing file, impossible design
request).  The command line prints ``beveloid: error: <message>`` (one line, no traceback) and exits
with status 2.  ``beveloid.spec.SpecError`` is handled the same way but deliberately does not derive
from this class (``spec`` stays self-contained); the CLI catches both.

Code decides by the error's type or its ``code`` (an :class:`ErrorCode`), never by the text of its
message: the message is for the user and may change.
"""
from __future__ import annotations

import enum

__all__ = ["ErrorCode", "UserError", "OptionError", "StopReason"]


class ErrorCode(enum.StrEnum):
    """What kind of problem a :class:`UserError` reports."""

    BAD_INPUT = "bad_input"  #: a value out of range or malformed
    OUT_OF_RANGE = "out_of_range"  #: an option's value outside its range
    DESIGN_REFUSED = "design_refused"  #: the design request has no physical solution
    OUTPUT = "output"  #: an output place that cannot be written
    STALE_RESULTS = "stale_results"  #: results on disk from another request or version


class UserError(ValueError):
    """A one-line error message meant for the user, not a bug; ``code`` says which kind."""

    code: ErrorCode = ErrorCode.BAD_INPUT

    def __init__(self, message: str = "", *, code: ErrorCode | None = None):
        super().__init__(message)
        if code is not None:
            self.code = ErrorCode(code)


class OptionError(UserError):
    """An analysis option out of its range: ``key``, ``value`` and ``requirement`` (what is valid).

    The message is ``"{key} = {value!r}: {requirement}"``; a caller that names the option otherwise
    (a command-line flag) rebuilds it from the fields with :meth:`for_flag`, never from the text."""

    code = ErrorCode.OUT_OF_RANGE

    def __init__(self, key, value, requirement):
        self.key, self.value, self.requirement = key, value, requirement
        super().__init__(f"{key} = {value!r}: {requirement}")

    def for_flag(self, flag: str, shown=None) -> str:
        """The message with the command-line flag in place of the key (and ``shown``, the value as the
        user typed it, when given)."""
        return f"{flag} = {self.value if shown is None else shown}: {self.requirement}"


class StopReason(enum.StrEnum):
    """Why a run of chunks stopped before it was complete."""

    INTERRUPTED = "interrupted (Ctrl-C)"
    WORK_LOST = "work lost"
