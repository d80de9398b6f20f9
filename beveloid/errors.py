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
import os

__all__ = ["ErrorCode", "UserError", "UserCodeError", "OptionError", "StopReason"]


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


class UserCodeError(UserError):
    """An exception raised by the user's own code (a tooth-surface model of theirs), told as theirs.

    The message is ``FILE:LINE: ExceptionType: message (while ...)``; ``frames`` holds the lines the
    command line prints below it: the traceback's frames in the user's files only (none of
    beveloid's), or for a syntax error the offending line and its caret."""

    def __init__(self, message: str, frames=()):
        super().__init__(message)
        self.frames = tuple(frames)

    @classmethod
    def from_exception(cls, exc: BaseException, files, doing: str) -> UserCodeError | None:
        """The error for ``exc`` raised while ``doing`` (e.g. "importing the model") by code in
        ``files`` (paths); None when neither ``exc`` (a syntax error) nor a frame of its traceback
        is in them: then the failure is not in the user's code."""
        import traceback

        mine = {os.path.realpath(f) for f in files}

        def theirs(filename):
            return filename is not None and os.path.realpath(filename) in mine

        if isinstance(exc, SyntaxError) and theirs(exc.filename):
            # format_exception_only: '  File "...", line N', the line, the caret, 'SyntaxError: ...'
            shown = "".join(traceback.format_exception_only(exc)).rstrip("\n").splitlines()[1:-1]
            return cls(f"{exc.filename}:{exc.lineno}: {type(exc).__name__}: {exc.msg} ({doing})", shown)
        frames = traceback.StackSummary.from_list(
            [f for f in traceback.extract_tb(exc.__traceback__) if theirs(f.filename)])
        if not frames:
            return None
        last = frames[-1]
        return cls(f"{last.filename}:{last.lineno}: {type(exc).__name__}: {exc} ({doing})",
                   "".join(frames.format()).rstrip("\n").splitlines())


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
