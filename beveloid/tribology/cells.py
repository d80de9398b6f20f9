"""The speed-independent data of every contact cell of a loaded analysis: where it is, its velocities
per unit pinion speed (generated/contact_kinematics.py), its line load and the relative radii in the
sum velocity's direction.  Built once per LTCA result; every speed scales it (the kinematics is linear
in the speed), so an efficiency map solves no contact again.
"""
from __future__ import annotations

import typing

import numpy as np

from ..generated import contact_kinematics, placement
from ..ltca.model.gaps import principal_frame
from ..ltca.model.grid import hertz_semi_axes

#: relative curvature (1/mm) below which a direction counts as straight (R_y taken as 1e6 mm)
STRAIGHT_CURVATURE = 1e-6


class Cells(typing.NamedTuple):
    """Arrays (N, P, C) (C = across x along cells, row-major) unless shaped otherwise; velocities in
    m/s per rad/s of the pinion, vectors in S_f."""

    loaded: np.ndarray  # bool: a converged position, a cell on both flanks with pressure > 0
    pressure_mpa: np.ndarray  # 0 where not loaded
    area_mm2: np.ndarray  # (N, P) one cell's area
    line_load_n_per_mm: np.ndarray  # the along-column's load per unit length of the line (sum of p dx across)
    point: np.ndarray  # (N, P, C, 3) mm
    normal: np.ndarray  # (N, P, C, 3)
    pinion_velocity: np.ndarray  # (N, P, C, 3) tangent part
    gear_velocity: np.ndarray  # (N, P, C, 3)
    sliding_velocity: np.ndarray  # (N, P, C, 3) pinion minus gear
    sum_velocity: np.ndarray  # (N, P, C, 3)
    approach_speed: np.ndarray  # (V_1 - V_2).n, a check of the point
    sliding_profile: np.ndarray  # sliding velocity's part across the contact line (profile direction)
    sliding_lengthwise: np.ndarray  # its part along the contact line
    radius_sum_mm: np.ndarray  # relative radius of curvature in the sum velocity's direction (R_x)
    radius_across_mm: np.ndarray  # ... across the contact line (the principal one: a helical pair's normal radius)
    sum_across: np.ndarray  # |sum velocity . across|: what entrains a line contact (its part along the line does not)
    pinion_across: np.ndarray  # |pinion velocity . across|: the speed at which its surface crosses the band
    gear_across: np.ndarray  # |gear velocity . across|
    radius_side_mm: np.ndarray  # ... perpendicular to it (R_y)
    entrainment_angle_deg: np.ndarray  # sum velocity to the contact ellipse's minor axis (0: across the line)
    pair_load_n: np.ndarray  # (N, P) broadcast to (N, P, C)
    line_contact: np.ndarray  # (N, P) the LTCA's rule: the pair's Hertz ellipse is longer than the contact line
    pinion_lu: np.ndarray  # (N, P, C, 2)


def scatter(values, mask):
    """``values`` (M, ...) of the cells where ``mask`` (N, P, C) holds, in an (N, P, C, ...) array, nan elsewhere."""
    values = np.asarray(values, dtype=float)
    out = np.full(mask.shape + values.shape[1:], np.nan)
    out[mask] = values
    return out


def line_length_mm(geom):
    """The contact line's length the LTCA sizes its grids with (ltca.analysis): face width / cos(helix)."""
    import math

    return geom.pinion.face_width_mm / max(math.cos(geom.pinion.helix_angle), 0.3)


def build(result, geom, errors, e_star_mpa) -> Cells:
    """The cells of an LTCAResult of ``geom`` (a PairGeometry) with assembly ``errors`` (5,)."""
    errors = np.asarray(errors, dtype=float)
    N, P, C = result.pressure_mpa.shape
    nx, ny = result.grid.across_cells, result.grid.along_cells
    ok = np.asarray(result.converged)[:, None, None]
    p = np.where(ok & result.gap.in_flank, np.nan_to_num(result.pressure_mpa), 0.0)
    loaded = p > 0
    lu = result.gap.pinion_lu
    # the kinematics of the loaded cells (the others get nan)
    surf = geom.surface("pinion", result.flank, lu[loaded][:, 0], lu[loaded][:, 1])
    phi = np.broadcast_to(result.pair_pinion_angle[:, :, None], (N, P, C))[loaded]
    compact = contact_kinematics.contact_velocities(
        result.gap.pinion_point[loaded], surf.normal, phi, 1.0, float(geom.pinion.teeth),
        float(geom.gear.teeth), errors, geom.placement())
    kin = type(compact)(*(scatter(a, loaded) for a in compact))
    # the along-column's line load: sum over the across cells of p dx (N/mm)
    dx = 2.0 * result.grid.across_half_mm / nx  # (N, P)
    line = (p.reshape(N, P, nx, ny).sum(axis=2) * dx[..., None])  # (N, P, ny)
    line = np.broadcast_to(line[:, :, None, :], (N, P, nx, ny)).reshape(N, P, C)
    # the pairs' relative curvature at their tangency (principal axes in S_1)
    fr = principal_frame(geom, result.flank, result.tangency_unknowns, result.pair_pinion_angle, errors)
    rot = placement.pinion_placement(result.pair_pinion_angle, geom.placement()).rotation  # (N, P, 3, 3) S_1 -> S_f
    axes_f = np.einsum("npij,npaj->npai", rot, fr.axes)  # (N, P, 2, 3) across, along in S_f
    across, along = axes_f[:, :, None, 0], axes_f[:, :, None, 1]
    s = kin.sum_velocity
    with np.errstate(invalid="ignore", divide="ignore"):
        e = s / np.linalg.norm(s, axis=-1, keepdims=True)
        ca, cl = np.einsum("...i,...i->...", e, across), np.einsum("...i,...i->...", e, along)
        ka, kl = fr.curvature_across[:, :, None], fr.curvature_along[:, :, None]
        k_sum = ka * ca ** 2 + kl * cl ** 2
        k_side = ka * cl ** 2 + kl * ca ** 2
        rx = 1.0 / k_sum
        ry = np.where(k_side > STRAIGHT_CURVATURE, 1.0 / k_side, 1.0 / STRAIGHT_CURVATURE)
        angle = np.degrees(np.arctan2(np.abs(cl), np.abs(ca)))
    with np.errstate(all="ignore"):
        _, a = hertz_semi_axes(fr.curvature_across, fr.curvature_along, np.nan_to_num(result.pair_load_n), e_star_mpa,
                               line_length_mm(geom))
    vs = kin.sliding_velocity
    return Cells(loaded=loaded, pressure_mpa=p, area_mm2=result.cell_area_mm2, line_load_n_per_mm=line,
                 point=kin.point, normal=kin.normal, pinion_velocity=kin.pinion_velocity,
                 gear_velocity=kin.gear_velocity, sliding_velocity=vs, sum_velocity=s,
                 approach_speed=kin.approach_speed,
                 sliding_profile=np.einsum("...i,...i->...", vs, across),
                 sliding_lengthwise=np.einsum("...i,...i->...", vs, along),
                 radius_sum_mm=rx, radius_side_mm=ry, entrainment_angle_deg=angle,
                 radius_across_mm=np.broadcast_to(1.0 / np.maximum(ka, STRAIGHT_CURVATURE), (N, P, C)),
                 sum_across=np.abs(np.einsum("...i,...i->...", s, across)),
                 pinion_across=np.abs(np.einsum("...i,...i->...", kin.pinion_velocity, across)),
                 gear_across=np.abs(np.einsum("...i,...i->...", kin.gear_velocity, across)),
                 pair_load_n=np.broadcast_to(np.nan_to_num(result.pair_load_n)[:, :, None], (N, P, C)),
                 line_contact=np.isinf(a), pinion_lu=lu)
