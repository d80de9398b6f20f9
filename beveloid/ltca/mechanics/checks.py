"""One-line ValueErrors for arguments a user can get wrong (name, value, what is valid)."""
from __future__ import annotations

import math

import numpy as np


def positive(name: str, value: float) -> float:
    """A finite number > 0, returned as float."""
    v = float(value)
    if not (math.isfinite(v) and v > 0.0):
        raise ValueError(f"{name} = {value!r}: must be a finite number > 0")
    return v


def poisson(name: str, value: float) -> float:
    """A Poisson ratio: finite, in (-1, 0.5)."""
    v = float(value)
    if not (math.isfinite(v) and -1.0 < v < 0.5):
        raise ValueError(f"{name} = {value!r}: must be a number > -1 and < 0.5")
    return v


def finite_array(name: str, value, size: int | None = None, positive_only: bool = False) -> np.ndarray:
    """A 1-D float array of finite entries (optionally of a given size, optionally all > 0)."""
    a = np.asarray(value, dtype=float)
    if a.ndim != 1:
        raise ValueError(f"{name} has shape {a.shape}: must be a 1-D array")
    if size is not None and a.size != size:
        raise ValueError(f"{name} has {a.size} entries: must have {size} (one per cell)")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} contains non-finite values: every entry must be finite")
    if positive_only and a.size and not np.all(a > 0.0):
        raise ValueError(f"{name} has minimum {float(a.min())!r}: every entry must be > 0")
    return a
