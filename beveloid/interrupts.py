"""Ctrl-C that is never lost.

Python turns SIGINT into a ``KeyboardInterrupt`` raised in whatever code runs at that moment.  When
that code is a ctypes callback (numba's LLVM compiles call back into Python: the object-cache
notifications), the exception cannot propagate: Python prints "Exception ignored on calling ctypes
callback function ... KeyboardInterrupt" and carries on, and the run that the user asked to stop
runs to its end (seen: `beveloid explore` interrupted during its first compile exited 0), or fails
later on the half-made state (numba: "RuntimeError: no compiled object yet for <Library ...>").

:func:`install` (the CLI calls it) makes the interrupt leave a mark as well as raise, and hides the
"ignored" report of a KeyboardInterrupt (only that one: every other unraisable exception is reported
as before).  Long runs call :func:`check` between pieces of work and before they write their
results, and run pieces of work under :func:`guard`: an interrupt swallowed inside a callback stops
the run there, as if it had propagated, and an error that follows it counts as the interrupt.
Without :func:`install` (the library used from Python) :func:`check` does nothing.
"""
from __future__ import annotations

import contextlib
import signal
import sys
import threading

_seen = False


def _on_sigint(signum, frame):
    global _seen
    _seen = True
    raise KeyboardInterrupt


def _unraisable(hook):
    def quiet(unraisable):
        if _seen and isinstance(unraisable.exc_value, KeyboardInterrupt):
            return  # reported by the CLI's one line once the run stops at the next check()
        hook(unraisable)
    return quiet


def install() -> None:
    """Mark every SIGINT (and raise KeyboardInterrupt, as Python's default handler does); from the main
    thread only (elsewhere signals cannot be handled); a SIGINT set to be ignored stays ignored."""
    global _seen
    _seen = False
    if threading.current_thread() is not threading.main_thread():
        return
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        return
    signal.signal(signal.SIGINT, _on_sigint)
    if not getattr(sys.unraisablehook, "_beveloid_quiet", False):
        sys.unraisablehook = _unraisable(sys.unraisablehook)
        sys.unraisablehook._beveloid_quiet = True


def seen() -> bool:
    """Whether a SIGINT arrived since :func:`install`."""
    return _seen


def check() -> None:
    """Raise KeyboardInterrupt if a SIGINT arrived (and was swallowed on its way)."""
    if _seen:
        raise KeyboardInterrupt


@contextlib.contextmanager
def guard():
    """Run a piece of work: after a SIGINT, an exception from it (the state a swallowed interrupt left
    half-made) and its normal end alike raise KeyboardInterrupt."""
    try:
        yield
    except Exception:
        if _seen:
            raise KeyboardInterrupt from None
        raise
    check()
