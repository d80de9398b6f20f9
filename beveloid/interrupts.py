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

A command that stops for a Ctrl-C and says so in its own line calls :func:`reported`, so that the
CLI adds no second "interrupted".  :class:`Deferred` lets the last, short piece of a run (writing the
outputs of what finished) go on through a first Ctrl-C; a second stops it at once.
"""
from __future__ import annotations

import contextlib
import signal
import sys
import threading

#: whether a SIGINT arrived since install(); a dict, so that the hook below still reads it while the
#: interpreter clears this module's globals at its exit (when the finalizers report)
_state = {"seen": False, "reported": False}


def _on_sigint(signum, frame):
    _mark()
    raise KeyboardInterrupt


def _mark():
    _state["seen"] = True
    _state["reported"] = False


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
    _state["reported"] = False
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


def _pending() -> bool:
    return _state["seen"] and not _state["reported"]


def check() -> None:
    """Raise KeyboardInterrupt if a SIGINT arrived (and was swallowed on its way), unless the command
    has :func:`reported` it."""
    if _pending():
        raise KeyboardInterrupt


def reported() -> None:
    """The command has stopped for the last Ctrl-C and said so in its own line: :func:`check` (and the
    CLI's guard, which would add "interrupted") no longer raises for it; a later Ctrl-C counts again."""
    _state["reported"] = True


class Deferred:
    """The last, short piece of a run (writing its outputs) that one Ctrl-C does not cut: between
    :meth:`start` and :meth:`stop` the first SIGINT is marked (``pressed``; ``on_first()`` says so at
    once) and the work goes on; a second raises KeyboardInterrupt at once.  In the main thread only
    (signals are handled there); a SIGINT set to be ignored stays ignored."""

    def __init__(self, on_first=None):
        self.on_first = on_first
        self.pressed = 0
        self._previous = None

    def start(self) -> None:
        if threading.current_thread() is not threading.main_thread():
            return
        previous = signal.getsignal(signal.SIGINT)
        if previous is signal.SIG_IGN or previous is None:  # ignored, or a handler not set from Python
            return
        self._previous = previous
        signal.signal(signal.SIGINT, self._on_sigint)

    def _on_sigint(self, signum, frame):
        _mark()
        self.pressed += 1
        if self.pressed > 1:
            raise KeyboardInterrupt
        if self.on_first is not None:
            self.on_first()

    def stop(self) -> None:
        """The handler from before :meth:`start` again."""
        if self._previous is not None:
            signal.signal(signal.SIGINT, self._previous)
            self._previous = None


@contextlib.contextmanager
def guard():
    """Run a piece of work: after a SIGINT, an exception from it (the state a swallowed interrupt left
    half-made) and its normal end alike raise KeyboardInterrupt."""
    try:
        yield
    except Exception:
        if _pending():
            raise KeyboardInterrupt from None
        raise
    check()
