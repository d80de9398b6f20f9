"""Tolerances and limits of the contact solver: the one place they are set."""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SolverOptions:
    """Tolerances and limits of the contact solver (the one place they are set)."""

    tol_mm: float = 1e-12  #: Newton tolerance on Eq 38 (normal rows times r_w2), or the round-off floor
    max_iter: int = 25  #: Newton iterations per point
    homotopy_steps: int = 3  #: equal steps from the aligned contact to the errors (x4, x16 on a lost set)
    #: a point lies on a flank patch when none of its margins is below -patch_tol_mm (round-off of
    #: the boundary equations; core.on_patch); a tangency further off is replaced by the edge or
    #: corner contact
    patch_tol_mm: float = 1e-9

    def __post_init__(self):
        for name in ("tol_mm", "patch_tol_mm"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and 0 < value < 1e-3):
                raise ValueError(f"SolverOptions.{name} = {value!r}: must be a number > 0 and < 1e-3 (mm)")
        for name, low in (("max_iter", 1), ("homotopy_steps", 1)):
            value = getattr(self, name)
            if not (isinstance(value, int) and low <= value <= 1000):
                raise ValueError(f"SolverOptions.{name} = {value!r}: must be an integer from {low} to 1000")


DEFAULT_OPTIONS = SolverOptions()
