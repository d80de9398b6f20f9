"""A one-line progress bar on a terminal (the sweep's error sets, ...)."""
from __future__ import annotations

import sys
import time


def progress_bar(done, total, t0, stream=None, width=30, what="error sets"):
    """Draw ``done`` of ``total`` with elapsed and remaining seconds since ``t0`` (perf_counter)."""
    stream = stream or sys.stderr
    frac = done / total
    bar = "#" * int(width * frac) + "-" * (width - int(width * frac))
    el = time.perf_counter() - t0
    eta = el / frac - el if frac > 0 else float("nan")
    stream.write(f"\r  [{bar}] {done}/{total} {what}  {el:5.1f} s  eta {eta:5.1f} s")
    stream.flush()
    if done == total:
        stream.write("\n")


def for_terminal(stream=None):
    """progress_bar when ``stream`` (default stderr) is a terminal, else None."""
    stream = stream or sys.stderr
    return progress_bar if getattr(stream, "isatty", lambda: False)() else None
