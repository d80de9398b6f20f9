"""Which of many designs are clear of the undercut and pointed-tip statuses, all at once.

``clear(geometry)`` takes the designs of an exploration as one PairGeometry of arrays and evaluates
the same generated sections on the same scan grids as the checks themselves (``undercut.flank_undercut``:
``undercut.SCAN_POINTS`` sections per flank; ``tip.tip_thickness``: ``tip.SCAN_POINTS``), for every
design in one call per member.  Those checks report an undercut range only where a scanned section's
undercut depth is > 0, and a pointed range only where a scanned tip thickness is <= 0 (their ranges
are refined between scanned sections of different classes, ``sections.segments``).  A design whose
every scanned depth is below ``-MARGIN_MM`` and every scanned tip thickness above ``+MARGIN_MM``
therefore has neither status, whatever the last bits of the arithmetic: its checks need not run.
Any other design (flagged, within the margin of a flag, or with a section that cannot be computed)
is left to the checks themselves (``undercut.undercut``, ``tip.tip_thicknesses``), which give its
statuses and their messages.  ``beveloid explore`` runs it over each chunk's designs.
"""
from __future__ import annotations

import numpy as np

from ..names import FLANKS, MEMBERS
from . import sections, tip, undercut

__all__ = ["MARGIN_MM", "clear"]

#: how far (mm) from a flag's threshold every scanned value must be: far above the last-bit differences
#: between the arithmetic over many designs and over one (~1e-13 mm at these sizes)
MARGIN_MM = 1e-9


def clear(geometry) -> np.ndarray:
    """(n,) bool: design i of the PairGeometry of arrays has no undercut flank and no pointed tip."""
    ok = np.ones(np.shape(geometry.normal_module_mm), dtype=bool)
    for member in MEMBERS:
        s = sections.section(geometry, member, sections.face_grid(geometry, member, undercut.SCAN_POINTS))
        for flank in FLANKS:
            ok &= np.all(getattr(s, f"undercut_depth_{flank}") < -MARGIN_MM, axis=-1)  # NaN: not clear
        thickness = tip.thickness(geometry, member, sections.face_grid(geometry, member, tip.SCAN_POINTS))
        ok &= np.all(thickness > MARGIN_MM, axis=-1)
    return ok
