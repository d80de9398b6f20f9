"""User-facing error type.

Raise :class:`UserError` for problems the user can fix (bad input, missing file,
impossible design request).  The command line prints ``beveloid: error: <message>``
(one line, no traceback) and exits with status 2.  ``beveloid.spec.SpecError`` is
handled the same way but deliberately does not derive from this class (``spec``
stays self-contained); the CLI catches both.
"""
from __future__ import annotations

__all__ = ["UserError"]


class UserError(ValueError):
    """A one-line error message meant for the user, not a bug."""
