"""Strength rating of a crossed beveloid pair (``beveloid rating``, docs/rating.md): the ISO 6336
yardstick on the virtual cylindrical gear of each transverse section (``iso6336``, ``virtual``) and
the local stresses of the loaded contact, with permissible stresses and safety factors (``factors``,
``analysis``, ``report``).

The names of ``analysis`` and ``report`` are imported on first use: the spec's check of a material
(``rating.materials``, every command) then imports no more of the rating (nor the tooth and TCA it needs).
"""
from __future__ import annotations

from .verdict import EXIT_STATUS, verdict

__all__ = ["BOX_PERCENTILE", "EXIT_STATUS", "LoadedContact", "MAX_TOLERANCE_SAMPLES", "MemberRating", "Options",
           "POSITIONS", "RatingResult", "SectionRating", "analyze", "ltca_case", "verdict"]


def __getattr__(name):
    if name == "RatingResult":
        from . import report as module
    elif name in __all__:
        from . import analysis as module
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(module, name)
