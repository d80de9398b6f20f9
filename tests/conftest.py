"""Shared fixtures, and how the suite shares its expensive work when it runs in parallel.

``verification`` runs ``registry.verify()`` (the 50-digit check of all 38 equations,
~10 s of CPU: ``python benchmarks/bench_verification.py``) once per test process; every test that needs
results uses it.

The suite runs in parallel (pytest-xdist, ``-n auto --dist loadgroup`` in pyproject.toml):

* work built once per process and shared by many tests stays in one process: tests/generated/
  (their sympy models and renderings, ~20 s) and the tests that use ``verification`` form the
  xdist group "generated" (the derivations' cached solves serve both);
* tests/generated/ is collected first (sympy only: its worker builds the models while the other
  compiles the solver core); then the tests marked ``long_running`` (tens of seconds each), each followed by
  two ordinary tests (xdist hands a worker another test whenever it has two or fewer left:
  this keeps one worker from queueing all of them), so that the workers start them early
  instead of one finishing the run alone with one of them;
* numba compiles the solver core on its first use after a fresh install (~25 s) and caches it
  on disk.  Two workers compiling at once would each spend those 25 s, so the first use of the
  compiled backend in a process compiles everything the backend runs under a lock shared by
  every process of this install (the others then load numba's cache), on a fresh stack
  (:func:`on_a_fresh_stack`: so are the sympy work of tests/generated and the verification).  The fixture
  ``compiled_solver`` does it up front, for a test that must not compile in the middle (the
  CLI fuzz test, whose examples have a hang guard).
"""
from __future__ import annotations

import contextlib
import gc
import hashlib
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import warnings
from pathlib import Path

import pytest

from beveloid.solver import Solver
from beveloid.cli import GC_YOUNG_THRESHOLD

try:
    import fcntl
except ImportError:  # not POSIX: no lock, each process compiles (or loads the cache) by itself
    fcntl = None

ROOT = Path(__file__).resolve().parents[1]

# One BLAS thread in each test process and in the Pythons it starts: the parallel run keeps every
# core busy with a worker already, and a second BLAS thread per worker only competes with the other
# worker, spinning while it waits (docs/performance.md, "Test suite").  The variables for the
# libraries not loaded yet (MKL, by
# pypardiso) and for the child processes; numpy's OpenBLAS is loaded by the imports above.  A value
# set by the caller wins.
if "OPENBLAS_NUM_THREADS" not in os.environ:
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=1, user_api="blas")
for _blas in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_blas, "1")

# The suite runs on the built-in tooth-surface models only: an empty user model folder (docs/models.md),
# whatever the machine's own holds; tests of user models give theirs to the processes they start.
os.environ["BEVELOID_MODELS_DIR"] = tempfile.mkdtemp(prefix="beveloid-test-models-")

# The Python processes the tests start (`python -m beveloid.cli ...`, `python -c ...`) import the
# beveloid these tests import, the installed one: without this, Python puts their working folder
# (the checkout, pytest's) first on sys.path, so on a non-editable install (CI, the README's test
# command) they ran the checkout's copy instead (not what was installed) and compiled the solver
# a second time into it (~45 s of CPU).  PYTHONSAFEPATH: Python 3.11+.
os.environ["PYTHONSAFEPATH"] = "1"

# The Ctrl-C tests (tests/cli/test_interrupts.py, test_cli_outputs.py) send SIGINT to the Pythons they
# start.  A suite started in the background of a script (`cmd &` in a non-interactive shell) inherits
# SIGINT ignored, and so would every Python it starts: the signal would never arrive (seen: the runs
# went on to the end).  Caught here, it is back to the default in every program the tests start.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


# The test processes collect young objects less often, as the script does (GC_YOUNG_THRESHOLD):
# numba's first compilation and the sympy models make millions of objects that live on (measured:
# the compile ~10 % less CPU; docs/performance.md, "Test suite").  The older generations too, which
# the script leaves as they are: every 50 young collections, and the oldest every 100 of those (the
# compile step another ~10 % less, 24.7 -> 21.8 s, ~70 MB more at its peak; a test process lives
# a few minutes).
GC_OLDER_THRESHOLDS = (50, 100)
gc.set_threshold(GC_YOUNG_THRESHOLD, *GC_OLDER_THRESHOLDS)


def pytest_collection_finish(session):
    """After collection: every object made so far (modules, test items) out of the collector's
    reach (``gc.freeze``): its full collections then walk only what the tests make.  And in a worker
    of ``--dist loadgroup``, xdist has tagged the node id of each grouped test with "@group" by now;
    say so when it has not (the tests still run, each worker building the shared work it needs)."""
    gc.collect()
    gc.freeze()
    if getattr(session.config.option, "loadgroup", False) and any(
            item.get_closest_marker("xdist_group") and "@" not in item.nodeid for item in session.items):
        warnings.warn("the xdist groups are not in effect (tests that share an expensive fixture are spread over "
                      "the workers and build it in each): see the pytest pin in pyproject.toml", stacklevel=1)


def on_a_fresh_stack(fn, *args, **kwargs):
    """``fn(*args, **kwargs)`` on a thread of its own, that is at the bottom of a fresh Python stack.

    CPython 3.11 keeps its frames in 16 KB chunks and unmaps a chunk as soon as the stack falls
    back below it: a deep recursion (sympy's derivations, numba's typing) that keeps crossing a
    chunk boundary maps and unmaps a chunk on every crossing.  A test runs ~60 frames deep in
    pytest, where the derivations of tests/generated crossed one ~380 000 times (2.5 s of system
    time and ~0.5 s more of user time; at the bottom of a stack: ~10 000 times, 0.1 s).  For work
    that needs no signal handler (those are the main thread's only)."""
    out = {}

    def run():
        try:
            out["value"] = fn(*args, **kwargs)
        except BaseException as exc:  # noqa: BLE001 - raised again in the caller's thread
            out["error"] = exc

    thread = threading.Thread(target=run, name=f"fresh-stack {getattr(fn, '__name__', 'work')}")
    thread.start()
    thread.join()
    if "error" in out:
        raise out["error"]
    return out["value"]


@pytest.fixture(scope="session")
def fresh_stack():
    """:func:`on_a_fresh_stack`, for fixtures and tests elsewhere in the suite."""
    return on_a_fresh_stack


@pytest.fixture(scope="session")
def pair1():
    """Case 1 of the paper's Table 1 as a :class:`beveloid.pair.Pair` (design and geometry built once)."""
    from beveloid.pair import Pair

    return Pair.example("case1")


@pytest.fixture(scope="session")
def pair2():
    """Case 2 of the paper's Table 1 as a :class:`beveloid.pair.Pair`."""
    from beveloid.pair import Pair

    return Pair.example("case2")


@pytest.fixture(scope="session")
def geom1(pair1):
    """Case 1's geometry as the solver sees it (``pair1.geometry``)."""
    return pair1.geometry


@pytest.fixture(scope="session")
def verification():
    """``(equations, results)`` from one ``registry.verify()`` call per session."""
    from beveloid.derivations import registry

    return on_a_fresh_stack(registry.verify)


# ---------------------------------------------------------------------------------------------
# parallel runs: groups and order
# ---------------------------------------------------------------------------------------------


def _group(item):
    marker = item.get_closest_marker("xdist_group")
    return marker.args[0] if marker and marker.args else marker.kwargs.get("name") if marker else None


#: test folders none of whose tests runs the compiled solver but those marked "solver" (measured: every compiled entry
#: point made to raise, these folders passed but for those)
WITHOUT_SOLVER = ("tests/derivations/", "tests/spec/", "tests/export/", "tests/pair/")


@pytest.hookimpl(tryfirst=True)  # before xdist reads the groups
def pytest_collection_modifyitems(config, items):
    for item in items:
        if "verification" in item.fixturenames:
            # with tests/generated: the derivations' solves and simplifications that both the specs and
            # registry.verify() run are cached per process (Eq 7, the tangency, the FPD angle: ~3 s)
            item.add_marker(pytest.mark.xdist_group("generated"))
    # tests/generated (sympy only, ~20 s) first: one worker builds its models while the other
    # compiles the solver core (numba, ~20 s on a fresh install), instead of waiting for its lock
    first = [item for item in items if _group(item) == "generated"]
    # then the folders that run no compiled solver code: the worker that built the sympy models
    # takes them while the other compiles (pytest_runtest_setup), instead of waiting for its lock
    # (xdist keeps this order: --no-loadscope-reorder in pyproject.toml)
    # (a test there marked "solver" runs the solver: with the rest, or it waits for the other worker's compile: seen
    # ~17 s idle on a fresh install)
    first += [item for item in items if _group(item) != "generated" and item.nodeid.startswith(WITHOUT_SOLVER)
              and not item.get_closest_marker("solver")]
    rest = [item for item in items if item not in set(first)]
    long = [item for item in rest if item.get_closest_marker("long_running")]
    ordinary = [item for item in rest if not item.get_closest_marker("long_running")]
    items[:] = first
    for item in long:
        items.append(item)
        items.extend(ordinary[:2])
        del ordinary[:2]
    items.extend(ordinary)


# ---------------------------------------------------------------------------------------------
# one numba compilation at a time
# ---------------------------------------------------------------------------------------------

_compiled = False


@contextlib.contextmanager
def _compile_lock(part: str = "core"):
    """An exclusive lock shared by the processes that run this install of beveloid (its numba
    cache lives beside it), one per ``part``: "core" (the solver core and what runs over it),
    "outside" (the kernels outside it, :func:`_compile_outside_core`)."""
    from beveloid.solver import backends

    if fcntl is None:
        yield
        return
    where = hashlib.sha1(str(Path(backends.__file__).resolve().parent).encode()).hexdigest()[:16]
    with open(Path(tempfile.gettempdir()) / f"beveloid-numba-compile-{where}-{part}.lock", "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


_outside_compiled = False
#: True while this process compiles the kernels outside the core: their calls then go straight to
#: the backend (the wrappers of _compile_once_under_a_lock would wait for the core's lock)
_compiling_outside = False


def _compile_outside_core():
    """The kernels outside the solver core, which call none of it: the loaded TCA's contact solve
    (ltca/mechanics/kernel.py, with the argument types ltca/passes/cycle.py passes) and the FE
    tooth's principal stresses (fe/principal.py).  Under a lock of their own: in a parallel run the
    worker that builds the sympy models compiles them first (~10 s on a fresh install) while the other
    compiles the core, which loads them from numba's cache when it gets to them.  Once per process."""
    global _outside_compiled, _compiling_outside
    if _outside_compiled:
        return
    _outside_compiled = True
    import numpy as np

    from beveloid.ltca.mechanics import lcp
    from beveloid.solver import Solver

    def run():
        lcp.solve_contact(np.eye(4) * 1e-3, np.zeros(4), np.ones(4), 10.0, solver=Solver("compiled"))
        _principal_stresses()

    _compiling_outside = True
    try:
        with _compile_lock("outside"), contextlib.suppress(Exception):
            on_a_fresh_stack(run)
    finally:
        _compiling_outside = False


def _principal_stresses():
    """fe/principal.py's and fe/lines.py's compiled functions called as fe/contact.py calls them (C-contiguous
    float64 operators (nodes, 6, G), loads (Q, G)), on a made-up tensor field."""
    import numpy as np

    from beveloid.fe import lines, principal

    fn = principal.functions()
    op = np.ascontiguousarray(np.arange(2 * 6 * 3, dtype=float).reshape(2, 6, 3))
    bound = fn.bounds(op, 1.0)
    order = np.arange(2, dtype=np.int64)
    fillet = principal.Fillet(op, bound, fn.block_bounds(bound, order, 32), order, 32, np.zeros((3, 2), dtype=np.uint8))
    fn.extreme(fillet, np.ones((1, 3)), 1.0, np.zeros(1, dtype=np.int64), np.full(1, np.nan))
    fn.slice_extremes(fillet, np.ones((1, 3)), 0, 1.0, np.ones(2, dtype=np.bool_), np.zeros(2, dtype=np.int64),
                      np.empty(1))
    # fe/lines.py's W C W^T, as FeTooth.line_compliances calls it
    lines.functions().line_compliances(np.eye(4), np.zeros((1, 2, 4), dtype=np.int64), np.ones((1, 2, 4)),
                                       np.empty((1, 2, 2)))
    lines.functions().corners(np.zeros((1, 3)), np.array([[1.0, 1.0], [2.0, 2.0]]), np.arange(2.0), np.zeros(3),
                              np.empty((1, 4), dtype=np.int64), np.empty((1, 4)))


def _compile_solver():
    """Run every entry point of the compiled backend once, on case 1 (compiles them, or loads
    them from numba's cache): the contact paths (TCA, sweep, backlash), the sweep's contact points,
    the single-point Newton, the loaded TCA's normal gaps and explore's rows.  Once per process,
    under the lock."""
    global _compiled
    if _compiled:
        return
    _compiled = True  # before the calls below, which come back through backends.namespace
    import numpy as np

    from beveloid import ltca, tca
    from beveloid.explore import run as explore_run
    from beveloid.pair import Pair
    from beveloid.solver import backends
    from beveloid.solver.records import settings

    def geometry():
        geom = Pair.from_spec(ROOT / "examples" / "case1.toml").geometry
        return geom, tca.reference_contact(geom, "right")

    def sweep_points(geom, ref):
        # the sweep's contact points of a solved grid (sweep.py; the one core entry point that the paths
        # above do not reach: missing here, the CLI fuzz test compiled it inside an example's hang guard)
        sol = tca.solve_grid(geom, "right", np.zeros(5), [ref.pinion_angle], solver=Solver("compiled"))  # serial
        tca.solved_contact_points(geom, "right", sol.x, sol.status, solver=Solver("compiled"))

    runs = (
        sweep_points,  # the serial grid, then its contact points
        # more error sets than tca.SERIAL_MAX_SETS: solve_paths on threads (sweeps; the same compiled function)
        lambda geom, ref: tca.solve_grid(geom, "right", np.zeros((tca.SERIAL_MAX_SETS + 1, 5)), [ref.pinion_angle],
                                         solver=Solver("compiled")),
        lambda geom, ref: backends.namespace("compiled").solve_point(
            geom.problem("right"), ref.x.copy(), ref.pinion_angle, np.zeros(5),
            settings(scale_mm=geom.gear.working_pitch_radius_mm, tol_mm=tca.newton_tolerance(geom), max_iter=3)),
        # a mesh study with its contact ellipses (the chord search) and both flanks (the backlash)
        lambda geom, ref: tca.analyze(geom, tca.Options(positions=3), solver=Solver("compiled")),
        # the kernels outside the core (compiled by the other worker meanwhile, or here), then the loaded
        # TCA's path over the core (its normal gaps)
        lambda geom, ref: _compile_outside_core(),
        lambda geom, ref: ltca.analyze(geom, ltca.LoadCase(100.0), ltca.Options(flank="right", positions=2, pairs=1, tooth_model="plate"), solver=Solver("compiled")),
        # explore's own compiled kernels (its rows over the core): its worker processes then load them
        # instead of each compiling them at once
        lambda geom, ref: explore_run.warm_up(),
    )
    def compile_all():
        geom, ref = geometry()
        for run in runs:
            with contextlib.suppress(Exception):
                run(geom, ref)

    # only a head start: whatever fails here, the tests run (and report) the same code themselves.
    # On a fresh stack: numba's typing recurses deeply (on_a_fresh_stack)
    with _compile_lock(), contextlib.suppress(Exception):
        on_a_fresh_stack(compile_all)


#: a parallel run of at least this many tests (the whole suite, not a few files) compiles up front
EAGER_COMPILE_MIN_TESTS = 500
_first_test = True


def pytest_runtest_setup(item):
    """In a parallel run of the whole suite, a worker whose first test is not of the group "generated"
    (sympy only) compiles the solver at once, under the lock: the worker that builds the sympy models
    meanwhile then loads numba's cache when it needs it, instead of waiting for a compilation that a
    test of the other worker started late (measured on a fresh install: ~20 s of one worker idle).
    The worker of the group "generated" compiles the kernels outside the core first (it waited ~12 s
    for the core's compilation after its sympy work: they fill that wait)."""
    global _first_test
    if not _first_test:
        return
    _first_test = False
    if os.environ.get("PYTEST_XDIST_WORKER") and len(item.session.items) >= EAGER_COMPILE_MIN_TESTS:
        from beveloid.solver import backends

        if backends.AVAILABLE:
            _compile_outside_core() if _group(item) == "generated" else _compile_solver()


@pytest.fixture(scope="session", autouse=True)
def _compile_once_under_a_lock():
    """The first ``backends.namespace("compiled")`` of the process compiles the solver first
    (``_compile_solver``); the namespace returned is the one the backend would return anyway."""
    from beveloid.solver import backends

    if not backends.AVAILABLE:
        yield
        return
    real = backends.namespace

    def namespace(backend):
        ns = real(backend)
        if backend == "compiled" and not _compiling_outside:
            _compile_solver()
        return ns

    # the kernels outside the core (ltca/mechanics/kernel.py, fe/principal.py) are compiled whatever the backend:
    # their first use compiles them with the rest, under the lock (two workers would each compile them)
    real_module = backends.compiled_module

    def compiled_module(module_name, names):
        if not _compiling_outside:
            _compile_solver()
        return real_module(module_name, names)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(backends, "namespace", namespace)
        mp.setattr(backends, "compiled_module", compiled_module)
        yield


@pytest.fixture(scope="session")
def compiled_solver():
    """The compiled backend compiled (or loaded from numba's cache) before the test starts."""
    from beveloid.solver import backends

    if backends.AVAILABLE:
        backends.namespace("compiled")


# Property-based tests draw the same examples on every machine and run (a search that found a new
# counterexample on one run only would make CI's outcome depend on luck): derandomized.
from hypothesis import settings as _hypothesis_settings  # noqa: E402

_hypothesis_settings.register_profile("beveloid", derandomize=True, print_blob=True)
_hypothesis_settings.load_profile("beveloid")


# ---------------------------------------------------------------------------------------------
# a real Dask cluster
# ---------------------------------------------------------------------------------------------

def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def cluster(tmp_path):
    """A real Dask cluster on 127.0.0.1: `dask scheduler` and two `dask worker` processes, torn down after
    (explore, sweep and optimize run on it in their tests)."""
    pytest.importorskip("distributed")  # in the test extra: never skipped where the extras are installed
    from distributed import Client

    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    dask = [sys.executable, "-m", "distributed.cli.dask_scheduler"]
    worker = [sys.executable, "-m", "distributed.cli.dask_worker"]
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    logs = open(tmp_path / "cluster.log", "w")
    procs = [subprocess.Popen(dask + ["--host", "127.0.0.1", "--port", str(port), "--dashboard-address", ":0"],
                              stdout=logs, stderr=logs, env=env)]
    try:
        for _ in range(2):
            procs.append(subprocess.Popen(worker + [address, "--nthreads", "1", "--no-nanny",
                                                    "--dashboard-address", ":0", "--local-directory", str(tmp_path)],
                                          stdout=logs, stderr=logs, env=env))
        deadline = time.monotonic() + 90
        while True:
            try:
                with Client(address, timeout="5s") as client:
                    client.wait_for_workers(2, timeout=max(1.0, deadline - time.monotonic()))
                break
            except (OSError, TimeoutError):
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.5)
        yield address
    finally:
        for p in procs[::-1]:
            p.terminate()
        for p in procs[::-1]:
            try:
                p.wait(timeout=3)
            except subprocess.TimeoutExpired:
                p.kill()
        logs.close()
