"""The rating does not decide on a grid its own LTCA shows too coarse (issue 57): a grid coarser than the default
either way whose grid-convergence indicator finds a position not converged is raised to the default's counts and
solved again, with a note; a coarse grid the indicator accepts stands, and so does the default (only warned)."""
from __future__ import annotations

import pytest

from beveloid import ltca, rating
from beveloid.ltca.options import DEFAULT_GRID
from beveloid.pair import Pair
from beveloid.rating.analysis import RAISED_GRID_NOTE, raised_grid
from beveloid.solver import Solver


def _rate(pair, torque_nm, grid):
    lt = ltca.Options(positions=10, tooth_model="plate", grid=grid)
    return rating.analyze(pair, ltca.LoadCase(torque_nm), rating.Options(ltca=lt, refine_positions=False,
                                                                        root_stress_check=False), solver=Solver())


@pytest.fixture(scope="module")
def case1():
    return Pair.example("case1")


def _numbers(r):
    v = r.verdict()
    return ([v["status"], v["lowest"], v["value"], r.loaded.surface_pressure_max_mpa]
            + [r.loaded.face_load[m].K_H_beta for m in ("pinion", "gear")])


def test_a_coarse_grid_its_indicator_rejects_is_raised_to_the_default(case1):
    """Case 1 at 800 N m (K_A K_v T on the plate tooth): on 7x11 the indicator finds positions not converged
    (a pair's load moves by more than 1 % of the mesh's against 5x7); the rating solves 11x17 instead, so that
    its numbers are the default grid's to the last bit, and says so in one note."""
    raised, default = _rate(case1, 800.0, (7, 11)), _rate(case1, 800.0, None)
    torque = 800.0 * raised.factors.K_A * raised.factors.K_v  # the rating's LTCA's
    coarse = ltca.analyze(case1, ltca.LoadCase(torque), ltca.Options(positions=10, tooth_model="plate", grid=(7, 11)),
                          solver=Solver())
    assert not (coarse.convergence.converged() | ~coarse.converged).all() and raised_grid(coarse) == DEFAULT_GRID
    said = [n for n in raised.notes if n.startswith(RAISED_GRID_NOTE)]
    assert len(said) == 1 and "from the asked 7x11 to 11x17" in said[0] and "not converged at" in said[0]
    assert not any(n.startswith(RAISED_GRID_NOTE) for n in default.notes)
    assert _numbers(raised) == _numbers(default)
    assert "grid not converged" not in " ".join(raised.notes)  # the raised grid's own indicator converges here


def test_a_coarse_grid_its_indicator_accepts_stands(case1):
    """Case 1 at 300 N m: 7x11 converges by the indicator, so the rating keeps it (its numbers are 7x11's, not
    the default's), and the default grid is never raised."""
    coarse, default = _rate(case1, 300.0, (7, 11)), _rate(case1, 300.0, None)
    assert not any(n.startswith(RAISED_GRID_NOTE) for n in coarse.notes + default.notes)
    assert coarse.loaded.surface_pressure_max_mpa != default.loaded.surface_pressure_max_mpa
    lt = ltca.analyze(case1, ltca.LoadCase(300.0), ltca.Options(positions=4, tooth_model="plate"), solver=Solver())
    assert raised_grid(lt) is None  # the default's counts: never raised, whatever its indicator says
