"""Strength rating of a crossed beveloid pair (``beveloid rating``, docs/rating.md): the ISO 6336
yardstick on the virtual cylindrical gear of each transverse section (``iso6336``, ``virtual``) and
the local stresses of the loaded contact, with permissible stresses and safety factors (``factors``,
``analysis``, ``report``)."""
from __future__ import annotations

from .analysis import (BOX_PERCENTILE, MAX_TOLERANCE_SAMPLES, POSITIONS, LoadedContact, MemberRating, Options,
                       SectionRating, analyze)
from .report import RatingResult
from .verdict import EXIT_STATUS, verdict

__all__ = ["BOX_PERCENTILE", "EXIT_STATUS", "MAX_TOLERANCE_SAMPLES", "LoadedContact", "MemberRating", "Options",
           "POSITIONS", "RatingResult", "SectionRating", "analyze", "verdict"]
