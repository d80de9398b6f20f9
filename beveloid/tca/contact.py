"""The contact of one flank pair, from the generated kernels: unknowns by name, surface points,
the Eq 38 system and its Jacobians, the margins to the flank boundaries, the implicit tangent."""
from __future__ import annotations

import numpy as np

from ..errors import UserError
from ..generated import layouts, tca_kernels
from ..geometry import PairGeometry
from ..solver.options import DEFAULT_OPTIONS

FLANKS = tca_kernels.FLANKS
#: The five assembly errors, in the order of every (..., 5) error array (generated layout).
ERROR_NAMES = layouts.AssemblyErrors._fields
ERROR_UNITS = layouts.AssemblyErrors.UNITS


class NoContactError(UserError, RuntimeError):
    """The aligned pair has no contact on the flanks (an analysis cannot start from it).  A UserError too:
    a command that needs the contact says so in one line (exit 2); the design changes it."""


def geometry_of(pair) -> PairGeometry:
    """The PairGeometry of a :class:`beveloid.pair.Pair` or of a PairGeometry."""
    return getattr(pair, "geometry", pair)


def errors_array(errors) -> np.ndarray:
    """AssemblyErrors or (dx_mm, dy_mm, dz_mm, vertical_rad, horizontal_rad) -> array (..., 5)."""
    e = np.asarray(errors, dtype=float)
    if e.shape[-1:] != (len(ERROR_NAMES),):
        raise ValueError(f"errors must have {len(ERROR_NAMES)} components {ERROR_NAMES}, got shape {e.shape}")
    return e


def check_flank(flank):
    """The flank name, or ValueError naming what is valid."""
    if flank not in FLANKS:
        raise ValueError(f"flank = {flank!r}: must be one of {', '.join(FLANKS)}")
    return flank


def unknowns(x) -> layouts.ContactUnknowns:
    """Named views of solver unknowns x (..., 5): .pinion_l_mm, ..., .gear_angle_rad."""
    return layouts.ContactUnknowns(*np.moveaxis(np.asarray(x), -1, 0))


def surface(geom: PairGeometry, which, flank, l, u):
    """(point, normal, roll_angle) of a member's flank at (l, u)."""
    return geom.surface(which, check_flank(flank), l, u)


def surface_jacobian(geom, which, flank, l, u):
    """[dR/dl, dR/du] (..., 3, 2) of a member's flank."""
    return geom.surface_jet(which, check_flank(flank), l, u).point_D_lu


def contact_points(geom, flank, x):
    """(pinion point in S_1, gear point in S_2) of contacts x (..., 5)."""
    u = unknowns(x)
    return (surface(geom, "pinion", flank, u.pinion_l_mm, u.pinion_u_mm).point,
            surface(geom, "gear", flank, u.gear_l_mm, u.gear_u_mm).point)


def evaluate(geom: PairGeometry, flank, x, phi1, errors) -> tca_kernels.ContactSystem:
    """Eq 38 and its Jacobians at unknowns x (..., 5), pinion angles phi1 (...), errors (..., 5)."""
    check_flank(flank)
    return tca_kernels.contact_system(geom.pinion.tooth_surface, geom.gear.tooth_surface, flank, x, phi1,
                                      errors_array(errors), geom.surface_params("pinion"),
                                      geom.surface_params("gear"), geom.placement())


def contact_margins(geom, flank, x):
    """Margins (..., 8) in mm of contacts x (..., 5) to both blanks (tca_kernels.CONTACT_BOUNDARIES)."""
    x = np.asarray(x, dtype=float)
    p1, p2 = contact_points(geom, flank, x)
    return tca_kernels.contact_margins(x, p1, p2, geom.pinion.blank(), geom.gear.blank())


def boundary_margins(geom, flank, x):
    """(smallest margin in mm, name of that boundary) of contacts x (..., 5); > 0 is inside."""
    M = contact_margins(geom, flank, x)
    k = np.argmin(M, axis=-1)
    return np.take_along_axis(M, k[..., None], -1)[..., 0], np.asarray(tca_kernels.CONTACT_BOUNDARIES)[k]


def contact_boundary_names(active):
    """Names of the active boundaries (..., 2) of solved contacts: None for surface contact, else
    e.g. "pinion tip" (edge contact) or "corner: pinion tip / gear heel"."""
    names = tca_kernels.CONTACT_BOUNDARIES
    a = np.asarray(active).reshape(-1, 2)
    return [None if i < 0 else names[i] if j < 0 else f"corner: {names[i]} / {names[j]}" for i, j in a]


def newton_tolerance(geom, tol_mm=DEFAULT_OPTIONS.tol_mm):
    """tol_mm, or the round-off floor of the position residual for large coordinates."""
    scale = geom.gear.working_pitch_radius_mm
    return max(tol_mm, 64 * np.finfo(float).eps * (abs(geom.gear.axial_placement_mm) + geom.offset_mm + scale))


def tangent(geom, flank, x, phi1, errors):
    """dx/dphi1 and dx/derrors at solutions x (implicit function theorem, exact Jacobians)."""
    s = evaluate(geom, flank, x, phi1, errors)
    dphi = -np.linalg.solve(s.residual_D_unknowns, s.residual_D_pinion_angle[..., None])[..., 0]
    derr = -np.linalg.solve(s.residual_D_unknowns, s.residual_D_errors)
    return dphi, derr


def rotate_z(P, angle):
    """Points P (..., 3) turned about z by angle (...) rad."""
    c, s = np.cos(angle), np.sin(angle)
    out = P.copy()
    out[..., 0] = c * P[..., 0] - s * P[..., 1]
    out[..., 1] = s * P[..., 0] + c * P[..., 1]
    return out
