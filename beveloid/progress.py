"""The one progress protocol of the library, and its two displays (a bar on a terminal, a line a step).

A long computation that reports progress takes ``progress`` (a :class:`Progress`, or None for none) and
calls ``progress(done, total, what)`` after each step: ``done`` units finished so far out of ``total``
(None: not known ahead), ``what`` the units or a few words on the step ("error sets", "FE tooth pinion:
meshing").  The sweep's error sets, the loaded tolerance box, explore's designs, optimize's candidates,
the FE tooth's stages and the FE check's steps all report this way.
"""
from __future__ import annotations

import sys
import time
import typing

__all__ = ["Bar", "Lines", "Progress", "for_terminal"]


class Progress(typing.Protocol):
    """``progress(done, total, what)``: ``done`` of ``total`` units (None: unknown) finished, ``what`` they are."""

    def __call__(self, done: int, total: int | None, what: str) -> None: ...


class Bar:
    """A one-line bar: ``done``/``total`` ``what``, elapsed and remaining seconds since it was made; its own
    line ends when the work does.  At most ~4 redraws a second (``every`` s), the last one always."""

    def __init__(self, stream=None, width: int = 30, every: float = 0.0):
        self.stream = stream or sys.stderr
        self.width, self.every = width, every
        self.t0 = self.last = time.perf_counter()

    def __call__(self, done: int, total: int | None, what: str) -> None:
        now = time.perf_counter()
        finished = total is not None and done >= total
        if now - self.last < self.every and not finished:
            return
        self.last = now
        el = now - self.t0
        if total:
            frac = min(done / total, 1.0)
            bar = "#" * int(self.width * frac) + "-" * (self.width - int(self.width * frac))
            eta = el / frac - el if frac > 0 else float("nan")
            self.stream.write(f"\r  [{bar}] {done}/{total} {what}  {el:5.1f} s  eta {eta:5.1f} s")
        else:
            self.stream.write(f"\r  {done} {what}  {el:5.1f} s")
        if finished:
            self.stream.write("\n")
        self.stream.flush()


class Lines:
    """A line a step on ``stream``: ``prefix`` and ``what`` (with ``done/total`` when a total is known and
    ``counts``)."""

    def __init__(self, stream=None, prefix: str = "", counts: bool = False):
        self.stream = stream or sys.stderr
        self.prefix, self.counts = prefix, counts

    def __call__(self, done: int, total: int | None, what: str) -> None:
        count = f"[{done}/{total}] " if self.counts and total else ""
        print(f"{self.prefix}{count}{what}", file=self.stream, flush=True)


def for_terminal(stream=None, every: float = 0.0) -> Bar | None:
    """A :class:`Bar` when ``stream`` (default stderr) is a terminal, else None."""
    stream = stream or sys.stderr
    return Bar(stream, every=every) if getattr(stream, "isatty", lambda: False)() else None
