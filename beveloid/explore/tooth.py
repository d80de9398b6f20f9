"""The whole-tooth checks of ``beveloid design`` on the rows of an exploration.

For each design that passes the design's checks, the tooth's own checks (``beveloid.tooth``: undercut
over the face, ``tooth.undercut.undercut``; tip thickness over the face, ``tooth.tip.tip_thicknesses``)
decide its whole-tooth statuses, as ``beveloid design`` runs them.  First ``tooth.screen.clear`` scans
the sections of all of a chunk's designs at once (the checks' own grids and generated sections): a
design clear of both flags by a margin has no whole-tooth status and is done; the others (flagged or
near a flag) run the checks themselves on the designed pair, which give the statuses and messages.  A pointed or undercut design is
not ``ok``: its ``status`` is ``pointed`` (first) or ``undercut``, it keeps its numbers (working data,
sensitivities) and it takes no part in the Pareto front.  ``tooth_status`` lists every whole-tooth
status of a row, ``reason`` says in words why a row is not ``ok`` (the tooth checks' own messages, or
what the design's check found).

The contact ratio and the tip-fillet interference of ``beveloid design`` (``tooth.contact``: the
aligned TCA over a mesh cycle, ~2 s a design) are not evaluated per row; run ``beveloid design`` on a
chosen row for them.  docs/explore.md gives the cost of the checks per row.
"""
from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from ..design import DesignError, Outcome
from ..names import Member
from ..status import DesignStatus, ExploreStatus, ToothStatus

__all__ = ["FLAGS", "REASONS", "Designs", "whole_tooth"]

#: whole-tooth statuses that take a design off ``ok``, the first one found naming its status
FLAGS = (ToothStatus.POINTED, ToothStatus.UNDERCUT)
#: the status of a row whose whole-tooth checks stopped with an error (a row, not the run)
FAILED = ExploreStatus.TOOTH_CHECK_FAILED

#: why the design's check refused a design, by outcome (``beveloid design`` on the row gives the full line)
REASONS = {
    Outcome.OK: "",
    Outcome.ZERO_CONE_ANGLE: "a cone angle is zero: the pitch cone's apex is at infinity",
    Outcome.NO_WORKING_PRESSURE_ANGLE: "no working normal pressure angle solves Eq 17 for this offset",
    Outcome.GEAR_HELIX_ANGLE_OUT_OF_RANGE: "the gear helix angle (Eq 26) is not real or |beta2| >= 80 deg",
    Outcome.TRANSVERSE_PRESSURE_ANGLE_NOT_POSITIVE: "a transverse pressure angle is <= 0 (the flank leans past"
                                                    " the radial direction)",
    Outcome.NON_FINITE_DESIGN: "the design equations give non-finite values",
    Outcome.NON_PHYSICAL_PITCH_RADIUS: "a pitch radius is not positive",
    Outcome.TIP_INSIDE_BASE_CIRCLE: "the tip circle lies inside a base circle in the reference section",
    Outcome.POINTED_TEETH: "the transverse tip thickness in the reference section is <= 0.2 m_n",
    Outcome.PITCH_POINT_OFF_ACTIVE_PROFILE: "the pitch point P lies off the active profile (below the form circle"
                                            " or above the tip)",
}


def statuses(geometry) -> list[tuple[str, str]]:
    """(status, message) of the undercut and tip checks of ``beveloid.tooth`` on a PairGeometry."""
    from ..tooth import tip, undercut

    cut = undercut.undercut(geometry)
    tips = tip.tip_thicknesses(geometry)
    out = []
    for member in Member:
        out += [(ToothStatus.UNDERCUT, u.message()) for u in cut[member].values() if u is not None]
        if tips[member].pointed:
            out.append((ToothStatus.POINTED, tips[member].message()))
    return out


class Designs(NamedTuple):
    """A chunk's designs as the checks take them: ``spec(j)`` the DesignSpec of row j, and ``groups`` the rows
    that pass the design's checks as [(row indices, their PairGeometry of arrays)] (explore.contact.geometry)."""

    spec: Callable
    groups: list


def whole_tooth(cols: dict, outcome: np.ndarray, designs: Designs, check: bool = True) -> None:
    """Add ``tooth_status`` and ``reason`` to a chunk's columns and take flagged designs off ``ok``.

    ``outcome``: the design's Outcome codes of the rows; ``designs``: the rows' specs and geometries
    (:class:`Designs`; a spec is built only for a row the screen does not clear); ``check=False`` leaves the
    tooth unchecked (``tooth_status`` "not checked": what the design and the sensitivities cost alone,
    for benchmarks/bench_explore.py)."""
    from ..pair import Pair
    from ..tooth import screen

    n = len(cols["status"])
    tooth_status = np.full(n, "" if check else ExploreStatus.NOT_CHECKED, dtype=object)
    reason = np.array([REASONS[Outcome(int(c))] for c in outcome], dtype=object)
    status = np.array(cols["status"], dtype=object)
    unclear = np.zeros(n, dtype=bool)
    for idx, geometry in designs.groups if check else ():
        unclear[idx] = ~screen.clear(geometry)
    for j in np.nonzero(unclear & (status == DesignStatus.OK))[0]:
        try:
            found = statuses(Pair.from_spec(designs.spec(j)).geometry)
        except DesignError as exc:  # design() of the one spec refuses what the chunk passed (a check's boundary)
            status[j] = exc.outcome.label if exc.outcome is not None else ExploreStatus.DESIGN_REFUSED
            reason[j] = exc.detail
            continue
        except ValueError as exc:  # a root bracket of the tooth's sections (beveloid.tooth) failed: this row only
            status[j] = FAILED
            reason[j] = f"the whole-tooth checks stopped: {type(exc).__name__}: {exc}"
            continue
        names = [s for s, _ in found]
        tooth_status[j] = " ".join(dict.fromkeys(names))
        flag = next((f for f in FLAGS if f in names), None)
        if flag is not None:
            status[j] = flag
            reason[j] = "; ".join(m for _, m in found)
    cols["status"] = status
    cols["tooth_status"] = tooth_status
    cols["reason"] = reason
