"""The names the package speaks in: the members of a pair and the flanks of a tooth.

Both are :class:`enum.StrEnum`, so a member compares equal to its string (``Member.PINION ==
"pinion"``), formats as it (``f"{Member.GEAR}.teeth"`` is ``"gear.teeth"``) and serves as a dict
key or JSON value where the string did: code that still passes ``"pinion"`` or ``"left"`` keeps
working while the modules adopt the enums.
"""
from __future__ import annotations

import enum

__all__ = ["Member", "Flank", "MEMBERS", "FLANKS"]


class Member(enum.StrEnum):
    """A member of the pair: the pinion (1 in the paper's subscripts) or the gear (2)."""

    PINION = "pinion"
    GEAR = "gear"

    @property
    def index(self) -> int:
        """The paper's subscript: 1 for the pinion, 2 for the gear."""
        return 1 if self is Member.PINION else 2


class Flank(enum.StrEnum):
    """A flank of a tooth: left or right (the paper's sigma = +1 and -1 of the tilted rack)."""

    LEFT = "left"
    RIGHT = "right"

    @property
    def sigma(self) -> int:
        """+1 for the left flank, -1 for the right (tan alpha_P = (tan alpha_n cos gamma + sigma sin beta
        sin gamma) / cos beta)."""
        return 1 if self is Flank.LEFT else -1


#: the members and flanks in the package's order
MEMBERS = tuple(Member)
FLANKS = tuple(Flank)
