"""The sweep in this process on threads (beveloid/solver/threads.py map_unordered): whole pieces of
error sets, each solved and reduced to its per-set numbers on a pool thread, give bit for bit what
one solve of every set reduced as whole arrays gives (the sweep's reduction before it ran in pieces)."""
from __future__ import annotations

import threading

import numpy as np
import pytest

from beveloid import mesh, sweep, tca
from beveloid.solver import Solver, backends, threads
from beveloid.status import carries_numbers

pytestmark = pytest.mark.skipif(not backends.AVAILABLE, reason="the threads run the compiled solver")


def _whole_array_reduction(geom, options, res):
    """The per-set numbers from one solve_grid of every set, reduced as whole (K, N) arrays."""
    flank = options.flank
    errors = sweep.draw_errors(options.samples, options.ranges, options.seed, options.nominal)
    ref = tca.reference_contact(geom, flank)
    lo, hi = sweep.engagement_window(geom, flank, ref)
    grid, per_pitch, first = sweep.position_lattice(ref.pinion_angle, lo, hi, options.positions,
                                                    geom.pitch_angles[0])
    p_al, g_al = tca.contact_points(geom, flank, tca.solve_grid(geom, flank, np.zeros((1, 5)), grid).x[0])
    sol = tca.solve_grid(geom, flank, errors, grid, solver=Solver("compiled"))
    ok = carries_numbers(sol.status)
    P1, P2 = tca.solved_contact_points(geom, flank, sol.x, sol.status)
    n_ok = ok.sum(axis=1)
    has = n_ok > 0
    shift = {}
    for name, P, al in (("pinion", P1, p_al), ("gear", P2, g_al)):
        shift[name] = np.full(options.samples, np.nan)
        shift[name][has] = np.where(ok, P[..., 2] - al[None, :, 2], 0.0).sum(axis=1)[has] / n_ok[has]
    te = mesh.transmission_error(tca.unknowns(sol.x).gear_angle_rad, grid[None, :], tca.unknowns(ref.x).gear_angle_rad,
                                 ref.pinion_angle, geom.pinion.teeth / geom.gear.teeth)
    ptp = sweep.mesh_te_peak_to_peak(np.where(ok, te, np.nan), per_pitch, first, tca.first_touch_sign(geom, flank))
    return errors, sol, shift, ptp


def test_pieces_on_threads_give_the_whole_array_numbers_bit_for_bit(pair1, monkeypatch):
    options = sweep.Options(samples=41, positions=9, seed=4, chunk=7,
                            ranges={"dx_mm": 2.0, "dy_mm": 2.0, "vertical_deg": 1.0, "horizontal_deg": 0.5})
    ran_on = set()
    real = sweep._solve_sets

    def recorded(task):
        ran_on.add(threading.get_ident())
        return real(task)

    monkeypatch.setattr(sweep, "_solve_sets", recorded)
    monkeypatch.setattr(threads, "count", lambda: 2)
    res = sweep.analyze(pair1, options, solver=Solver("compiled"))
    assert ran_on and threading.get_ident() not in ran_on  # on the pool's threads, none on this one
    errors, sol, shift, ptp = _whole_array_reduction(pair1.geometry, options, res)
    np.testing.assert_array_equal(res.errors, errors)
    np.testing.assert_array_equal(res.status_codes, sol.status)
    np.testing.assert_array_equal(res.pinion_shift_mm, shift["pinion"])
    np.testing.assert_array_equal(res.gear_shift_mm, shift["gear"])
    np.testing.assert_array_equal(res.te_peak_to_peak, ptp)
    assert res.newton_iterations_mean == float(sol.iterations.mean())
    # a draw with every kind of point: the reduction meets sets with and without contact
    assert {0, 1, 3} <= set(np.unique(res.status_codes)) and np.isfinite(ptp).any()


@pytest.mark.parametrize("count, threads_, largest", [(64_000, 16, 2000), (64_000, 2, 2000), (41, 2, 7), (5, 4, 2000),
                                                      (200_000, 16, 2000)])
def test_pieces_cover_the_sets_in_whole_waves(count, threads_, largest):
    bounds = threads.pieces(count, threads_, largest)
    assert [i for a, b in bounds for i in range(a, b)] == list(range(count))
    sizes = [b - a for a, b in bounds]
    assert max(sizes) <= largest and max(sizes) - min(sizes) <= 1
    if count >= threads_ * threads.CHUNKS_PER_THREAD * 16:  # large: whole waves of at least 4 pieces a thread
        assert len(bounds) % threads_ == 0 and len(bounds) >= threads_ * threads.CHUNKS_PER_THREAD


def test_map_unordered_runs_each_item_once_on_pool_threads_single_threaded():
    def work(i):
        return i, threading.get_ident(), threads.count()

    got = dict(threads.map_unordered(work, range(23), 2))
    assert sorted(got) == list(range(23)) and all(got[i][0] == i for i in got)
    assert threading.get_ident() not in {v[1] for v in got.values()}
    assert {v[2] for v in got.values()} == {1}  # what runs there does not start threads of its own

    def fails(i):
        if i == 5:
            raise ValueError("item 5")
        return i

    with pytest.raises(ValueError, match="item 5"):
        list(threads.map_unordered(fails, range(8), 2))
