"""Status of a computed contact point: the one vocabulary of the solver, the analyses and the JSON."""
from __future__ import annotations

import enum


class Status(enum.IntEnum):
    """What a solved point is.  Only OK and EDGE points carry numbers."""

    OK = 0  #: surface contact inside both flanks
    EDGE = 1  #: edge or corner contact: a boundary curve (tip, toe, heel, form limit) bears on the mating flank
    OUTSIDE = 2  #: the two bounded flank patches cannot touch at this position: no numbers
    FAILED = 3  #: the solver did not converge: no number

    @property
    def label(self) -> str:
        """The name used in JSON, tables and plots: "ok", "edge", "outside", "failed"."""
        return self.name.lower()

    @classmethod
    def labels(cls, codes) -> list[str]:
        """Labels of a sequence of codes (one lookup per code: a mesh study has ~1200)."""
        table = {int(s): s.label for s in cls}
        return [table[c] if c in table else cls(c).label for c in map(int, codes)]  # cls(c): the enum's error


def carries_numbers(codes):
    """Boolean mask (array-like codes): points with a contact (OK or EDGE)."""
    import numpy as np

    return np.asarray(codes) <= Status.EDGE
