"""Ctrl-C that is never lost.

Python turns SIGINT into a ``KeyboardInterrupt`` raised in whatever code runs at that moment.  When
that code is a ctypes callback (numba's LLVM compiles call back into Python: the object-cache
notifications), the exception cannot propagate: Python prints "Exception ignored on calling ctypes
callback function ... KeyboardInterrupt" and carries on, and the run that the user asked to stop
runs to its end (seen: `beveloid explore` interrupted during its first compile exited 0), or fails
later on the half-made state (numba: "RuntimeError: no compiled object yet for <Library ...>").

:func:`install` (the CLI calls it) makes the interrupt leave a mark as well as raise; once it has,
"Exception ignored" reports are not printed: they are the swallowed interrupt itself, or finalizers
of work abandoned half-way (CI saw llvmlite's ``ObjectRef.__del__`` fail at the exit after a Ctrl-C
during a compile).  Before any Ctrl-C every unraisable exception is reported as usual.  Long runs call :func:`check` between pieces of work and before they write their
results, and run pieces of work under :func:`guard`: an interrupt swallowed inside a callback stops
the run there, as if it had propagated, and an error that follows it counts as the interrupt.
Without :func:`install` (the library used from Python) :func:`check` does nothing.
"""
from __future__ import annotations

import contextlib
import signal
import sys
import threading

#: whether a SIGINT arrived since install(); a dict, so that the hook below still reads it while the
#: interpreter clears this module's globals at its exit (when the finalizers report)
_state = {"seen": False}


def _on_sigint(signum, frame):
    _state["seen"] = True
    raise KeyboardInterrupt


def _unraisable(hook, state=_state):
    def quiet(unraisable):
        if state["seen"]:
            return  # the CLI says "interrupted" in its one line
        hook(unraisable)
    return quiet


def install() -> None:
    """Mark every SIGINT (and raise KeyboardInterrupt, as Python's default handler does); from the main
    thread only (elsewhere signals cannot be handled); a SIGINT set to be ignored stays ignored."""
    _state["seen"] = False
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
    return _state["seen"]


def check() -> None:
    """Raise KeyboardInterrupt if a SIGINT arrived (and was swallowed on its way)."""
    if _state["seen"]:
        raise KeyboardInterrupt


@contextlib.contextmanager
def guard():
    """Run a piece of work: after a SIGINT, an exception from it (the state a swallowed interrupt left
    half-made) and its normal end alike raise KeyboardInterrupt."""
    try:
        yield
    except Exception:
        if _state["seen"]:
            raise KeyboardInterrupt from None
        raise
    check()
