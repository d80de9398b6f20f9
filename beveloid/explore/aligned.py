"""The aligned contact at the pitch point of many designs, in one loop: explore's call of the solver core.

For each design the core's own ``solve_point`` (the aligned contact at P) and ``solve_paths`` (its
status there: surface contact or not), exactly what ``tca.sensitivity`` calls for one design.  The
numpy backend runs this module as it is; the compiled one runs its compiled twin
(:mod:`beveloid.solver.compiled`, by :func:`beveloid.explore.contact.sensitivities`), where the names
imported below are the core's numba dispatchers (``solve_paths`` there: its serial version).
"""
from __future__ import annotations

import numpy as np

from ..solver.newton import solve_point
from ..solver.paths import solve_paths
from ..solver.records import PathOutput, PathRequest, Problem, Settings

__all__ = ["aligned_contacts"]


def aligned_contacts(pm, gm, flank, batch, limits, out):
    """Per design of ``batch`` (contact.Batch; ``limits``: contact.BatchLimits): the aligned contact at P
    (solve_point) and its status at P (solve_paths), into ``out`` (contact.BatchOutput)."""
    cover = np.zeros((0, 8))
    zeros = np.zeros(5)
    errors = np.zeros((1, 5))
    grid = np.zeros(1)
    xo = np.empty((1, 1, 5))
    co = np.empty((1, 1), dtype=np.int64)
    io = np.empty((1, 1), dtype=np.int64)
    bo = np.empty((1, 1), dtype=np.int64)
    ao = np.empty((1, 1, 2), dtype=np.int64)
    for i in range(batch.x0.shape[0]):
        problem = Problem(pinion_model=pm, gear_model=gm, flank=flank, pinion_params=batch.pinion_params[i],
                          gear_params=batch.gear_params[i], pair=batch.pair[i], pinion_blank=batch.pinion_blank[i],
                          gear_blank=batch.gear_blank[i])
        settings = Settings(scale_mm=limits.scale_mm[i], tol_mm=limits.tol_mm[i], max_iter=limits.max_iter,
                            patch_tol_mm=limits.patch_tol_mm, homotopy_steps=limits.homotopy_steps,
                            first_touch_sign=1.0)
        x, conv, _, _ = solve_point(problem, batch.x0[i], batch.phi[i], zeros, settings)
        if not conv:
            out.code[i] = -1
            continue
        grid[0] = batch.phi[i]
        solve_paths(problem, PathRequest(pinion_cover=cover, x_ref=x, phi_ref=batch.phi[i], errors=errors,
                                         phi_grid=grid),
                    settings, PathOutput(x=xo, status=co, iterations=io, boundary=bo, active=ao))
        out.code[i] = co[0, 0]
        for j in range(xo.shape[2]):  # (a loop: numba's slice assignment compiles a shape-check message, ~1 s)
            out.x[i, j] = xo[0, 0, j]
