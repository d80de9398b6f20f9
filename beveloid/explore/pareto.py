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


def objectives(mc: bool) -> tuple[str, ...]:
    return OBJECTIVES + ((MC_OBJECTIVE,) if mc else ())


def front(points: np.ndarray) -> np.ndarray:
    """Boolean mask of the non-dominated rows of points (n, k), minimizing every column; rows with a
    non-finite entry are never on the front.  A row equal to a front row is on the front too.  pymoo's
    non-dominated sorting (its efficient non-dominated sort) over the finite rows."""
    from pymoo.util.nds.non_dominated_sorting import NonDominatedSorting

    points = np.asarray(points, dtype=float)
    on = np.zeros(points.shape[0], dtype=bool)
    finite = np.flatnonzero(np.isfinite(points).all(axis=1))
    if finite.size:
        first = NonDominatedSorting(method="efficient_non_dominated_sort").do(points[finite],
                                                                               only_non_dominated_front=True)
        on[finite[np.asarray(first, dtype=np.int64)]] = True
    return on
