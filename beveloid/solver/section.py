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
    for _ in range(MAX_ITERATIONS):
        k = np.flatnonzero(active)
        if not k.size:
            break
        jet = tca_kernels.surface_jet(model, flank, l[k], u[k], params[k] if per_element else params)
        p, J = jet.point, jet.point_D_lu
        rad = np.hypot(p[..., 0], p[..., 1])
        F = np.stack([rad - radius[k], p[..., 2] - z[k]], axis=-1)
        G = np.stack([(p[..., 0, None] * J[..., 0, :] + p[..., 1, None] * J[..., 1, :]) / rad[..., None],
                      J[..., 2, :]], axis=-2)
        with np.errstate(all="ignore"):
            d = np.linalg.solve(G, -F[..., None])[..., 0]
        l[k], u[k] = l[k] + d[..., 0], u[k] + d[..., 1]
        done = np.abs(d).max(axis=-1) < 1e-12 * np.maximum(1.0, radius[k])  # the last step was round-off
        active[k[done]] = False
    point = tca_kernels.surface(model, flank, l, u, params).point
    return SectionPoint(l.reshape(shape), u.reshape(shape), point.reshape(shape + (3,)), ~active.reshape(shape))
