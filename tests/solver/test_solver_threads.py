"""The compiled sweep on threads (beveloid/solver/threads.py): the numbers of one serial call on any
number of threads and chunks, numba's thread count obeyed, and a forked child starts its own pool."""
from __future__ import annotations

import multiprocessing
import threading

import numpy as np
import pytest

from beveloid import tca
from beveloid.solver import backends, threads
from beveloid.solver.records import PathOutput, PathRequest
from beveloid.tca import grid

pytestmark = pytest.mark.skipif(not backends.AVAILABLE, reason="the compiled backend needs numba")


@pytest.mark.parametrize("count, chunks", [(1, 8), (7, 3), (40, 8), (41, 8), (5, 5), (3, 100)])
def test_chunks_cover_every_error_set_once_in_order_and_even(count, chunks):
    bounds = threads.chunk_bounds(count, chunks)
    assert len(bounds) == min(count, chunks)
    assert [i for a, b in bounds for i in range(a, b)] == list(range(count))
    sizes = [b - a for a, b in bounds]
    assert min(sizes) >= 1 and max(sizes) - min(sizes) <= 1


def _call(geom, errors, solve):
    ref = tca.reference_contact(geom, "right")
    phi = np.ascontiguousarray(ref.pinion_angle + np.linspace(-0.25, 0.25, 9))
    K, N = errors.shape[0], phi.shape[0]
    out = PathOutput(x=np.full((K, N, len(tca.tca_kernels.UNKNOWNS)), -7.0), status=np.full((K, N), -7), iterations=np.full((K, N), -7),
                     boundary=np.full((K, N), -7), active=np.full((K, N, 2), -7))
    from beveloid.solver import patch_cover

    request = PathRequest(pinion_cover=patch_cover.patch_cover(geom, "pinion", "right", 1e-9).cells,
                          x_ref=np.ascontiguousarray(ref.x), phi_ref=float(ref.pinion_angle), errors=errors,
                          phi_grid=phi)
    solve(geom.problem("right"), request, grid.solver_settings(geom, "right", tca.SolverOptions()), out)
    return out


def _errors(K, seed=5):
    rng = np.random.default_rng(seed)
    return np.ascontiguousarray(rng.normal(0.0, 1.0, (K, 5)) * np.array([0.05, 0.05, 0.05, 1e-3, 1e-3]))


@pytest.mark.parametrize("thread_count", [2, 3, 64])
def test_threads_give_the_serial_numbers_bit_for_bit(geom1, monkeypatch, thread_count):
    ns = backends.namespace("compiled")
    errors = _errors(37)
    serial = _call(geom1, errors, ns.solve_paths_serial)
    seen = set()
    two = threading.Event()  # the first chunk waits for a second thread (else one fast thread may take all)
    real = ns.solve_paths_serial

    def counting(*args):
        seen.add(threading.get_ident())
        if len(seen) > 1:
            two.set()
        two.wait(timeout=30)
        return real(*args)

    monkeypatch.setattr(threads, "_threads", lambda: thread_count)
    on_threads = _call(geom1, errors, threads.over_error_sets(counting))
    for name in PathOutput._fields:
        np.testing.assert_array_equal(getattr(on_threads, name), getattr(serial, name), err_msg=name)
    assert (serial.status != -7).all() and set(np.unique(serial.status)) & {0, 1}  # written, and solved
    assert 1 < len(seen) <= thread_count and threading.get_ident() not in seen


def test_one_numba_thread_runs_on_the_calling_thread(geom1):
    import numba

    ns = backends.namespace("compiled")
    seen = []
    real = ns.solve_paths_serial
    before = numba.get_num_threads()
    numba.set_num_threads(1)  # a Dask task's setting (beveloid.parallel.single_threaded)
    try:
        _call(geom1, _errors(40), threads.over_error_sets(lambda *a: (seen.append(threading.get_ident()), real(*a))))
    finally:
        numba.set_num_threads(before)
    assert seen == [threading.get_ident()]


def _child(queue):
    from beveloid.pair import Pair

    out = _call(Pair.example("case1").geometry, _errors(9), backends.namespace("compiled").solve_paths)
    queue.put(out.x.tobytes())


def test_a_forked_child_solves_on_threads_of_its_own(geom1, monkeypatch):
    """The parent's pool has threads; a forked child has none of them (it would wait forever on them)."""
    ns = backends.namespace("compiled")
    monkeypatch.setattr(threads, "_threads", lambda: 2)
    parent = _call(geom1, _errors(9), ns.solve_paths)  # the pool now exists in this process
    assert threads._pool is not None
    ctx = multiprocessing.get_context("fork")
    queue = ctx.Queue()
    proc = ctx.Process(target=_child, args=(queue,))
    proc.start()
    try:
        child = queue.get(timeout=120)
    finally:
        proc.join(timeout=30)
        if proc.is_alive():
            proc.kill()
    assert child == parent.x.tobytes()
