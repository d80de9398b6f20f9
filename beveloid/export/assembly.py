"""Where the members sit when the pair is assembled as designed (``beveloid export --assembled``).

The pinion is turned to the TCA's reference pinion angle (the aligned contact at the pitch point, on
the left flanks) and the gear to the angle at which its left flank touches the pinion's there, under
the spec's ``[misalignment]``; both frames are then placed in the fixed frame S_f by the generated
placement kernels (generated/placement.py, Eqs 30-35 with the five assembly errors).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import tca
from ..solver import Solver
from ..status import Status
from ..tooth.sampling import ExportGeometryError


def assembly_angles(pair):
    """(pinion angle, gear angle) (rad) of the pair in mesh: the left flanks touch at the reference
    pinion angle (the TCA's aligned pitch-point contact), under the spec's [misalignment]."""
    geometry = pair.geometry
    ref = tca.reference_contact(geometry, "left")
    errors = np.asarray(pair.errors, dtype=float)
    if not np.any(errors):
        return ref.pinion_angle, float(tca.unknowns(ref.x).gear_angle_rad)
    sol = tca.solve_grid(geometry, "left", errors.reshape(1, -1), np.array([ref.pinion_angle]),
                         solver=Solver("numpy"))
    if Status(int(sol.status[0, 0])) == Status.FAILED:
        raise ExportGeometryError("misalignment: no contact of the left flanks found at the reference pinion angle"
                                  " under the file's [misalignment]; --assembled needs one to place the gear")
    return ref.pinion_angle, float(tca.unknowns(sol.x[0, 0]).gear_angle_rad)


@dataclass(frozen=True)
class Placement:
    """Where a member sits in the fixed frame S_f: p_f = rotation @ p_i + translation (mm)."""

    rotation: np.ndarray
    translation: np.ndarray

    @property
    def matrix(self):
        return self.rotation, self.translation

    @property
    def trsf(self):
        """The same transform for OpenCASCADE (imports OCP)."""
        from . import occ

        return occ.placement(self.rotation, self.translation)


def assembly_placements(pair) -> dict:
    """{member: :class:`Placement`} of the pair in mesh, from the generated placement (Eqs 30-35)."""
    from ..generated import placement

    phi1, phi2 = assembly_angles(pair)
    layout = pair.geometry.placement()
    p = placement.pinion_placement(phi1, layout)
    g = placement.gear_placement(phi2, np.asarray(pair.errors, dtype=float), layout)
    return {"pinion": Placement(p.rotation, p.translation), "gear": Placement(g.rotation, g.translation)}
