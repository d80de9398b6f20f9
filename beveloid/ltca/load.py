"""The load case of a loaded analysis: what the pair carries, apart from how it is computed.

    from beveloid import ltca
    ltca.LoadCase(torque_nm=200.0)                        # one torque, the pair's own [misalignment]
    ltca.LoadCase(torque_nm=[50, 100, 200, 400])          # a torque map
    ltca.LoadCase(200.0, errors=(0.02, 0, 0, 0, 0))       # one assembly error set (dx, dy, dz mm; vertical,
                                                          # horizontal rad)
    ltca.LoadCase(200.0, errors=[(0, 0, 0, 0, 0), (0.02, 0, 0, 0, 0)])  # several error sets (a tolerance box)

The torque is the pinion's (N m, each > 0); the numerical options (grid, positions, pairs, tooth
model, refinement) are :class:`beveloid.ltca.Options`.  A bad value raises
:class:`beveloid.errors.OptionError` naming the key, the value and what is valid.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["LoadCase"]


@dataclass(frozen=True)
class LoadCase:
    """Torque(s) and assembly errors: ``torque_nm`` a number or a list (the torque map), ``errors``
    None (the pair's ``[misalignment]``), one set of 5 numbers or a list of sets."""

    torque_nm: float | tuple
    errors: tuple | None = None

    def __post_init__(self):
        from .options import check_torque
        from .results.batch import check_error_sets, check_torques

        if isinstance(self.torque_nm, (list, tuple, np.ndarray)):
            object.__setattr__(self, "torque_nm", tuple(float(t) for t in check_torques(self.torque_nm, "torque_nm")))
        else:
            object.__setattr__(self, "torque_nm", check_torque(self.torque_nm))
        if self.errors is not None:
            sets = check_error_sets(self.errors, "errors")
            one = np.ndim(self.errors) == 1
            object.__setattr__(self, "errors", tuple(float(v) for v in sets[0]) if one
                               else tuple(tuple(float(v) for v in s) for s in sets))

    @property
    def torques_nm(self) -> tuple:
        """(T,) the torques (one for a single torque)."""
        return self.torque_nm if isinstance(self.torque_nm, tuple) else (self.torque_nm,)

    @property
    def is_map(self) -> bool:
        """A torque list (even of one) or several error sets: :func:`beveloid.ltca.analyze` returns a Batch."""
        return isinstance(self.torque_nm, tuple) or (self.errors is not None and isinstance(self.errors[0], tuple))

    def error_sets(self, pair) -> np.ndarray:
        """(K, 5) the error sets: the load case's, else the pair's misalignment (zeros for a bare geometry)."""
        from .results.batch import check_error_sets

        errors = self.errors if self.errors is not None else getattr(pair, "errors", np.zeros(5))
        return check_error_sets(errors, "errors")

    def at(self, torque_nm=None, errors=None) -> "LoadCase":
        """This load case with another torque (or list) and/or errors."""
        return LoadCase(self.torque_nm if torque_nm is None else torque_nm, self.errors if errors is None else errors)
