"""Principal curvatures of the tooth surfaces and the relative curvature of two flanks in contact.

Stable API (used by the contact ellipse and by the loaded TCA's Hertz check):

* :func:`principal_curvatures` ``(geom, which, flank, l, u)`` -> :class:`PrincipalCurvatures`
  ``(k1, k2, d1, d2)``: principal curvatures in 1/mm, ``k1 >= k2``, and their unit principal
  directions in the member frame S_i.
* :func:`curvature_tensor` ``(geom, which, flank, l, u)`` -> (..., 3, 3): the same as a
  symmetric tensor K of S_i, ``t . K t`` = normal curvature along a unit tangent t.
* :func:`relative_curvature` ``(geom, flank, x, pinion_angle, errors)`` ->
  :class:`RelativeCurvature` ``(H, basis, normal, point)``: the second-order separation
  ``1/2 x^T H x`` of the two flanks in their common tangent plane at a solved contact
  ``x`` (``tca_kernels.UNKNOWNS``), with the orthonormal tangent basis it uses, in S_f.

Sign convention: a curvature is positive where the surface bends away from its outward
normal (a convex tooth, as an involute flank is).  With outward normals n_1 = -n_2 at a
contact, the separation of the flanks along n_1 is ``1/2 x^T (K_1 + K_2) x``, so H is the sum
of the two members' curvature tensors in the common tangent plane: positive definite for two
convex flanks, singular along a line contact.

Everything is composed in numpy from the generated kernels: each model's first and second
fundamental forms (``surface_<model>.surface_fundamental_forms_<flank>``, reached through
``tca_kernels.surface_fundamental_forms``) and the placement of Eqs 30-35
(``placement.pinion_placement`` / ``gear_placement`` with the five errors).  Every function
broadcasts over leading axes.

Tangent basis of :func:`relative_curvature`: ``e1`` is the pinion axis (+z_1, in S_f) projected
onto the tangent plane and normalised, ``e2 = n_1 x e1``
with n_1 the pinion's outward normal in S_f.  Angles in the tangent plane (the contact
ellipse's major axis) are measured from e1 toward e2.
"""
from __future__ import annotations

import typing

import numpy as np

from .generated import placement as _placement
from .generated import tca_kernels


class PrincipalCurvatures(typing.NamedTuple):
    k1: np.ndarray  #: larger principal curvature [1/mm], convex positive
    k2: np.ndarray  #: smaller principal curvature [1/mm]
    d1: np.ndarray  #: (..., 3) unit principal direction of k1 in S_i
    d2: np.ndarray  #: (..., 3) unit principal direction of k2 in S_i (d1 x d2 = outward normal)


class RelativeCurvature(typing.NamedTuple):
    H: np.ndarray  #: (..., 2, 2) [1/mm]: separation 1/2 x^T H x, x in the basis below
    basis: np.ndarray  #: (..., 2, 3) rows e1, e2: orthonormal tangent basis in S_f
    normal: np.ndarray  #: (..., 3) the pinion's outward unit normal in S_f (e1 x e2)
    point: np.ndarray  #: (..., 3) the pinion's contact point in S_f [mm]


def _forms(geom, which, flank, l, u):
    m = geom.member(which)
    return tca_kernels.surface_fundamental_forms(m.tooth_surface, flank, l, u, geom.surface_params(which))


def _tangent_frame(point_D_lu, normal):
    """Orthonormal tangent frame T (..., 3, 2): t1 = R_l/|R_l|, t2 = n x t1."""
    t1 = point_D_lu[..., :, 0]
    t1 = t1 / np.linalg.norm(t1, axis=-1, keepdims=True)
    t2 = np.cross(normal, t1)
    return np.stack([t1, t2], axis=-1)


def _curvature_in_frame(f):
    """(T, K2): the orthonormal tangent frame and the curvature matrix in it (convex positive)."""
    T = _tangent_frame(f.point_D_lu, f.normal)
    # (l, u) coordinates of the frame vectors: C = I^-1 R_D^T T
    C = np.linalg.solve(f.first_form, np.swapaxes(f.point_D_lu, -1, -2) @ T)
    K2 = -np.swapaxes(C, -1, -2) @ f.second_form @ C
    return T, 0.5 * (K2 + np.swapaxes(K2, -1, -2))


def curvature_tensor(geom, which, flank, l, u):
    """Curvature tensor (..., 3, 3) of a member's flank at (l, u) in S_i, convex positive:
    t . K t is the normal curvature [1/mm] along a unit tangent t; K n = 0."""
    T, K2 = _curvature_in_frame(_forms(geom, which, flank, l, u))
    return T @ K2 @ np.swapaxes(T, -1, -2)


def principal_curvatures(geom, which, flank, l, u) -> PrincipalCurvatures:
    """Principal curvatures k1 >= k2 [1/mm] (convex positive) and unit directions d1, d2 in S_i
    of a member's flank at (l, u); d1 x d2 is the outward normal."""
    f = _forms(geom, which, flank, l, u)
    T, K2 = _curvature_in_frame(f)
    w, v = np.linalg.eigh(K2)  # ascending
    d2 = T @ v[..., :, 0:1]
    d1 = T @ v[..., :, 1:2]
    d1, d2 = d1[..., 0], d2[..., 0]
    # orient d2 so that (d1, d2, n) is right-handed
    flip = np.sign(np.einsum("...i,...i->...", np.cross(d1, d2), f.normal))
    d2 = d2 * np.where(flip == 0, 1.0, flip)[..., None]
    return PrincipalCurvatures(w[..., 1], w[..., 0], d1, d2)


def member_rotations(geom, x, pinion_angle, errors):
    """(L_f1, L_f2): the members' rotations into S_f at the contact x (generated placement)."""
    x = np.asarray(x, dtype=float)
    pair = geom.placement()
    L1 = _placement.pinion_placement(np.asarray(pinion_angle, dtype=float), pair).rotation
    L2 = _placement.gear_placement(x[..., tca_kernels.UNKNOWNS.index("gear_angle_rad")],
                                   np.asarray(errors, dtype=float), pair).rotation
    return L1, L2


def relative_curvature(geom, flank, x, pinion_angle, errors) -> RelativeCurvature:
    """H (..., 2, 2) [1/mm] of the separation 1/2 x^T H x of the two flanks in the common tangent
    plane at the solved contacts x (..., 5) (tca_kernels.UNKNOWNS) for pinion angles (...) and
    errors (..., 5), with the tangent basis (e1 = the pinion axis projected on the plane) in S_f.

    H = K_1 + K_2, both members' curvature tensors turned into S_f; the pinion's outward normal
    defines the plane (at a solved contact the gear's is its opposite to the solver tolerance).
    """
    x = np.asarray(x, dtype=float)
    names = tca_kernels.UNKNOWNS
    l1, u1 = x[..., names.index("pinion_l_mm")], x[..., names.index("pinion_u_mm")]
    l2, u2 = x[..., names.index("gear_l_mm")], x[..., names.index("gear_u_mm")]
    f1, f2 = _forms(geom, "pinion", flank, l1, u1), _forms(geom, "gear", flank, l2, u2)
    L1, L2 = member_rotations(geom, x, pinion_angle, errors)
    K = []
    for f, L in ((f1, L1), (f2, L2)):
        T, K2 = _curvature_in_frame(f)
        Tf = L @ T
        K.append(Tf @ K2 @ np.swapaxes(Tf, -1, -2))
    n = np.einsum("...ij,...j->...i", L1, f1.normal)
    axis = L1[..., :, 2]
    e1 = axis - np.einsum("...i,...i->...", axis, n)[..., None] * n
    e1 = e1 / np.linalg.norm(e1, axis=-1, keepdims=True)
    e2 = np.cross(n, e1)
    E = np.stack([e1, e2], axis=-2)  # (..., 2, 3)
    H = E @ (K[0] + K[1]) @ np.swapaxes(E, -1, -2)
    H = 0.5 * (H + np.swapaxes(H, -1, -2))
    p = _placement.pinion_placement(np.asarray(pinion_angle, dtype=float), geom.placement())
    point = np.einsum("...ij,...j->...i", L1, tca_kernels.surface(
        geom.pinion.tooth_surface, flank, l1, u1, geom.surface_params("pinion")).point) + p.translation
    return RelativeCurvature(H, E, n, point)
