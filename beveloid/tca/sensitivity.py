"""Exact first-order derivatives of the contact in the assembly errors (implicit function theorem)."""
from __future__ import annotations

import numpy as np

from ..geometry import PairGeometry
from ..solver import Solver
from ..status import Status
from .contact import ERROR_NAMES, errors_array, geometry_of, surface_jacobian, tangent, unknowns
from .grid import solve_grid
from .reference import reference_contact


def sensitivity(geom: PairGeometry, flank: str, errors=(0, 0, 0, 0, 0), pinion_angle=None, *,
                solver: Solver | None = None):
    """Exact first-order derivatives at one mesh position (implicit function theorem).

    ``geom``: a :class:`beveloid.pair.Pair` or its PairGeometry.  Returns dict with
    'unknowns_D_errors' (5x5: d(UNKNOWNS)/d(errors)), 'pinion_contact_D_errors' (3x5, mm per
    error unit), 'gear_contact_D_errors' (3x5) and 'gear_angle_D_errors' (5,), at the contact for
    the given errors and pinion angle (default: the reference pinion angle), solved by ``solver``
    (a :class:`beveloid.solver.Solver`; None: the default).  They are the
    derivatives of the surface contact (Eq 38): 'converged' is False unless the point is a
    surface contact ('ok'), 'status' says what it is.
    """
    geom = geometry_of(geom)
    solver = Solver.of(solver)
    e = errors_array(errors).reshape(1, len(ERROR_NAMES))
    ref = reference_contact(geom, flank, solver.options)
    phi1 = ref.pinion_angle if pinion_angle is None else pinion_angle
    sol = solve_grid(geom, flank, e, np.array([phi1]), solver=solver)
    x = sol.x[0, 0]
    _, derr = tangent(geom, flank, x[None], np.array([phi1]), e)
    derr = derr[0]
    u = unknowns(x)
    J1 = surface_jacobian(geom, "pinion", flank, u.pinion_l_mm, u.pinion_u_mm)
    J2 = surface_jacobian(geom, "gear", flank, u.gear_l_mm, u.gear_u_mm)
    d = unknowns(derr.T)  # rows of d(unknowns)/d(errors), by name
    return {
        "x": x, "pinion_angle": phi1, "converged": bool(sol.status[0, 0] == Status.OK),
        "status": Status(int(sol.status[0, 0])).label,
        "unknowns_D_errors": derr,
        "pinion_contact_D_errors": J1 @ np.stack([d.pinion_l_mm, d.pinion_u_mm]),
        "gear_contact_D_errors": J2 @ np.stack([d.gear_l_mm, d.gear_u_mm]),
        "gear_angle_D_errors": d.gear_angle_rad,
    }
