"""The flank point at a radius in a transverse section: one 2 x 2 Newton in (l, u), numpy, vectorised.

It finds the pitch point of the TE reference (``tca.reference``), of every design of an
exploration at once (``explore.contact``, one set of surface parameters per design) and the tip
curve of the whole tooth and its export (``tooth.profile``). The residual is
(radius of R(l, u) - radius, z of R(l, u) - z); the Jacobian comes from the generated jet
(point_D_lu), so convergence is quadratic and a step below 1e-12 max(1, radius) mm is round-off.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..generated import tca_kernels

MAX_ITERATIONS = 30


class SectionPoint(NamedTuple):
    l_mm: np.ndarray
    u_mm: np.ndarray
    point: np.ndarray  # (..., 3) member frame S_i
    converged: np.ndarray  # bool (...)


def point_at_radius(model, flank, params, radius_mm, z_mm, l0_mm, u0_mm=0.0) -> SectionPoint:
    """The point of the flank ``model`` (surface parameters ``params``: one set, or one per element)
    at ``radius_mm`` in the section ``z_mm``, by Newton from (l0_mm, u0_mm); elementwise."""
    shape = np.broadcast(radius_mm, z_mm, l0_mm, u0_mm).shape
    radius, z, l, u = (np.array(np.broadcast_to(a, shape), dtype=float).reshape(-1)
                       for a in (radius_mm, z_mm, l0_mm, u0_mm))
    active = np.ones(l.shape, dtype=bool)
    per_element = np.ndim(params) > 1
    k = slice(None)  # every element until one has converged
    for _ in range(MAX_ITERATIONS):
        jet = tca_kernels.surface_jet(model, flank, l[k], u[k], params[k] if per_element else params)
        p, J = jet.point, jet.point_D_lu
        rad = np.hypot(p[:, 0], p[:, 1])
        f0, f1 = rad - radius[k], p[:, 2] - z[k]
        g00 = (p[:, 0] * J[:, 0, 0] + p[:, 1] * J[:, 1, 0]) / rad  # d radius / d(l, u)
        g01 = (p[:, 0] * J[:, 0, 1] + p[:, 1] * J[:, 1, 1]) / rad
        g10, g11 = J[:, 2, 0], J[:, 2, 1]  # d z / d(l, u)
        with np.errstate(all="ignore"):  # the 2 x 2 Newton step -G^-1 F by Cramer's rule
            det = g00 * g11 - g01 * g10
            dl, du = (g01 * f1 - g11 * f0) / det, (g10 * f0 - g00 * f1) / det
        l[k], u[k] = l[k] + dl, u[k] + du
        idx = np.arange(l.size)[k]
        active[idx[np.maximum(np.abs(dl), np.abs(du)) < 1e-12 * np.maximum(1.0, radius[k])]] = False  # round-off
        if not active.any():
            break
        k = np.flatnonzero(active)
    point = tca_kernels.surface(model, flank, l, u, params).point
    return SectionPoint(l.reshape(shape), u.reshape(shape), point.reshape(shape + (3,)), ~active.reshape(shape))
