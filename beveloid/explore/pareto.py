"""The Pareto front of an exploration: designs no other design beats on every objective.

All objectives are minimized: the largest FPD angle ``max_fpd_angle_deg`` (small: nearly line
contact, a large pattern), the worst first-order path shift in the tolerance box
``worst_path_shift_mm`` (small: robust against assembly errors) and, with ``--mc``, the fraction of
Monte Carlo error sets with edge contact ``mc_edge_fraction``.  Only ``ok`` designs with every
objective finite take part.
"""
from __future__ import annotations

import numpy as np

OBJECTIVES = ("max_fpd_angle_deg", "worst_path_shift_mm")
MC_OBJECTIVE = "mc_edge_fraction"
#: rows compared at once with three or more objectives
_BLOCK = 512


def objectives(mc: bool) -> tuple[str, ...]:
    return OBJECTIVES + ((MC_OBJECTIVE,) if mc else ())


def front(points: np.ndarray) -> np.ndarray:
    """Boolean mask of the non-dominated rows of points (n, k), minimizing every column; rows with a
    non-finite entry are never on the front.  A row equal to a front row is on the front too."""
    points = np.asarray(points, dtype=float)
    n = points.shape[0]
    on = np.zeros(n, dtype=bool)
    finite = np.nonzero(np.isfinite(points).all(axis=1))[0]
    if finite.size == 0:
        return on
    P = points[finite]
    order = np.lexsort(P.T[::-1])  # by the first objective, ties by the next: a dominator comes first
    if P.shape[1] == 2:  # sorted by f1: dominated when an earlier row has a smaller f2 (or equal f2, smaller f1)
        f1, f2 = P[order, 0], P[order, 1]
        best = np.minimum.accumulate(f2)
        prev = np.concatenate([[np.inf], best[:-1]])
        # f1 of the first row that reached the running minimum before each row
        first = np.maximum.accumulate(np.where(np.concatenate([[True], f2[1:] < best[:-1]]), np.arange(f2.size), 0))
        at = np.concatenate([[0], first[:-1]])
        keep = ~((prev < f2) | ((prev == f2) & (f1[at] < f1)))
        on[finite[order[keep]]] = True
        return on
    # more objectives: blocks of rows in that order, each row checked against the front so far and its
    # block (a dominated row is dominated by a row of the front: checking those is enough)
    kept = np.zeros(0, dtype=np.int64)
    for start in range(0, order.size, _BLOCK):
        block = order[start:start + _BLOCK]
        B = P[block]
        F = np.concatenate([P[kept], B])
        le = (F[:, None, :] <= B[None, :, :]).all(axis=2)
        lt = (F[:, None, :] < B[None, :, :]).any(axis=2)
        kept = np.concatenate([kept, block[~(le & lt).any(axis=0)]])
    on[finite[kept]] = True
    return on
