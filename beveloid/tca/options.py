"""What a TCA computes: the one range table that the CLI and the JSON read."""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

from ..errors import OptionError
from ..contact_ellipse import DEFAULT_APPROACH_MM, check_approach
from .contact import ERROR_NAMES, FLANKS

#: (smallest, largest) of each integer option; pairs must also be odd (pair 0 in the middle)
POSITIONS = (1, 100_000)
PAIRS = (1, 9)


def _integer(key, value, lo, hi, odd=False):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or not lo <= value <= hi or (
            odd and value % 2 == 0):
        raise OptionError(key, value, f"must be {'an odd' if odd else 'an'} integer from {lo} to {hi}")


@dataclass(frozen=True)
class Options:
    """A mesh study: ``positions`` pinion angles over ``window_pitches`` pinion pitches (default
    ``pairs``; one position: the reference angle, where TE statistics are not available), ``pairs``
    neighbouring tooth pairs (odd), the ``flanks`` solved (both: also the backlash), the
    contact ellipses at the elastic approach ``approach_mm`` (None: no ellipses), and the assembly
    ``errors`` (tca.ERROR_NAMES: mm and rad; None: the pair's [misalignment], zero for a
    PairGeometry)."""

    flanks: tuple = FLANKS
    positions: int = 200
    pairs: int = 3
    approach_mm: float | None = DEFAULT_APPROACH_MM
    window_pitches: float | None = None
    errors: tuple | None = None

    def __post_init__(self):
        flanks = (self.flanks,) if isinstance(self.flanks, str) else tuple(self.flanks)
        if not flanks or any(f not in FLANKS for f in flanks) or len(set(flanks)) != len(flanks):
            raise OptionError("flanks", self.flanks, f"must be one or both of {', '.join(FLANKS)}")
        object.__setattr__(self, "flanks", flanks)
        _integer("positions", self.positions, *POSITIONS)
        _integer("pairs", self.pairs, *PAIRS, odd=True)
        if self.approach_mm is not None:
            check_approach(self.approach_mm)
        if self.window_pitches is not None and not (isinstance(self.window_pitches, numbers.Real)
                                                    and 0 < self.window_pitches <= 100):
            raise OptionError("window_pitches", self.window_pitches, "must be a number > 0 and <= 100, or None")
        if self.errors is not None:
            try:
                errors = tuple(float(v) for v in self.errors)
            except (TypeError, ValueError):
                errors = ()
            if len(errors) != len(ERROR_NAMES) or not all(math.isfinite(v) for v in errors):
                raise OptionError("errors", self.errors, f"must be {len(ERROR_NAMES)} finite numbers "
                                  f"({', '.join(ERROR_NAMES)}), or None")
            object.__setattr__(self, "errors", errors)
