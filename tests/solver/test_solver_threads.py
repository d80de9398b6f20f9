"""The compiled sweep on threads (beveloid/solver/threads.py): the numbers of one serial call on any
number of threads and chunks, numba's thread count obeyed, and a forked child starts its own pool."""
from __future__ import annotations

import subprocess
import sys
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


_FORK_SCRIPT = r"""
import hashlib, os, sys
import numpy as np
from beveloid.pair import Pair
from beveloid.solver import backends, threads
from beveloid.tca import grid
threads._threads = lambda: 2
geom = Pair.example("case1").geometry
ns = backends.namespace("compiled")
if not hasattr(ns.solve_paths_serial, "py_func"):  # NUMBA_DISABLE_JIT=1: the interpreted core, on threads too
    ns.solve_paths = threads.over_error_sets(ns.solve_paths_serial)
errors = np.ascontiguousarray(np.random.default_rng(5).normal(0.0, 0.01, (9, 5)))
def digest():
    sol = grid.solve_grid(geom, "right", errors, np.linspace(-0.2, 0.2, 7) + grid.reference_contact(geom, "right").pinion_angle)
    return hashlib.sha1(sol.x.tobytes() + sol.status.tobytes()).hexdigest()
grid.SERIAL_MAX_SETS = 4  # 9 error sets: on threads
parent = digest()
assert threads._pool is not None, "no pool in the parent"
read, write = os.pipe()
pid = os.fork()
if pid == 0:
    os.close(read)
    os.write(write, digest().encode())
    os._exit(0)
os.close(write)
child = os.read(read, 100).decode()
_, status = os.waitpid(pid, 0)
print(parent, child, status)
"""


def test_a_forked_child_solves_on_threads_of_its_own(compiled_solver, tmp_path):
    """The parent's pool has threads; a forked child has none of them (it would wait forever on
    them).  In a Python of its own: the test process's other threads (xdist's, BLAS's) are not the
    solver's to make fork-safe."""
    proc = subprocess.run([sys.executable, "-c", _FORK_SCRIPT], capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    parent, child, status = proc.stdout.split()
    assert status == "0" and child == parent
