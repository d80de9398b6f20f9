"""A design's Monte Carlo numbers depend on the design and the request alone (issue 29): not on its chunk,
on what the process computed before, on numba's thread count or on the run.  The designs are two of the
worked example (docs/explore.md) whose sets are nearly all edge contact and failed points, where the TE
peak-to-peak (tens to hundreds of urad) is the most sensitive to any difference."""
from __future__ import annotations

import numba
import numpy as np
import pytest

from beveloid.solver import Solver
from beveloid.explore import rows
from beveloid.explore.grid import Plan, parse_vary
from beveloid.spec import load_example, spec_to_dict

TOLERANCES = dict(dx_mm=0.05, dy_mm=0.05, dz_mm=0.05, vertical_deg=0.02, horizontal_deg=0.02)
MC = rows.MonteCarloRequest(samples=40, positions=20, flank="right", seed=0)


@pytest.fixture(scope="module")
def edge_plan():
    plan = Plan(spec_to_dict(load_example("case1")), (parse_vary("pinion.cone_angle_deg=3.75:4:2"),
                                                      parse_vary("pinion.helix_angle_deg=32:32:1")))
    return plan, rows.compute(plan, 0, plan.count, TOLERANCES)


def _mc(plan, cols, start, stop, backend="auto", request=MC):
    part = {k: np.asarray(v)[start:stop] for k, v in cols.items()}
    rows.monte_carlo(part, plan, slice(start, stop), TOLERANCES, request, solver=Solver(backend))
    return {k: part[k] for k in rows.MC_COLUMNS + ("mc_status",)}


def _same(a, b):
    for k in a:
        np.testing.assert_array_equal(a[k], b[k], err_msg=k)


def test_monte_carlo_of_a_design_is_the_same_in_any_chunk_run_or_thread_count(edge_plan):
    plan, cols = edge_plan
    assert cols["status"].tolist() == ["ok", "ok"]
    whole = _mc(plan, cols, 0, 2)
    assert (whole["mc_edge_fraction"] > 0.3).all() and (whole["mc_te_peak_to_peak_urad_p95"] > 10).all()
    alone = _mc(plan, cols, 1, 2)  # design 1 in a chunk of its own, nothing computed before it
    _same({k: v[1:] for k, v in whole.items()}, alone)
    _same(whole, _mc(plan, cols, 0, 2))  # the same run again
    before = numba.get_num_threads()
    try:
        for threads in (1, numba.config.NUMBA_NUM_THREADS):  # the parallel solver on one thread and on all
            numba.set_num_threads(threads)
            _same(whole, _mc(plan, cols, 0, 2))
    finally:
        numba.set_num_threads(before)


def test_compiled_and_interpreted_solvers_agree_on_the_monte_carlo(edge_plan):
    """The numpy backend runs the same core as Python: no memory left unwritten by either could give
    these the same statistics (equal to the last digits only: numba's arithmetic may differ by an ulp)."""
    plan, cols = edge_plan
    small = MC._replace(samples=6, positions=8)
    compiled, interpreted = _mc(plan, cols, 1, 2, "compiled", small), _mc(plan, cols, 1, 2, "numpy", small)
    assert compiled["mc_edge_fraction"][0] > 0.3
    for k in rows.MC_COLUMNS:
        np.testing.assert_allclose(interpreted[k], compiled[k], rtol=1e-7, err_msg=k)
