"""Where chunks of independent work run: this process, local worker processes, or a Dask cluster.

    with executor(workers=4) as ex:                 # or executor(scheduler="tcp://host:8786")
        for index, result in ex.map_unordered(fn, items):
            ...                                     # results as they finish, with their item's index

``fn`` must be a module-level function (it is pickled to the workers) and ``fn(item)`` must not
depend on where it runs: the callers (``beveloid explore``, ``beveloid sweep --workers``) cut the
work into chunks whose contents and seeds depend only on the inputs, never on the number of
workers, so one worker, N local workers and a cluster give the same results bit for bit.

* ``workers=1``: in this process, in order.
* ``workers=N``: a ``concurrent.futures.ProcessPoolExecutor`` of N spawned processes, all started when
  the executor is entered (they start while the caller prepares its work).  Each loads
  the compiled solver once, in its initializer (:func:`warm_up` with the caller's ``initializer``:
  numba's on-disk cache, written by the first process that compiled it), and runs numba and the
  BLAS / OpenMP libraries on one thread (:data:`ONE_THREAD`: the processes are the parallelism; two
  workers whose BLAS had two threads each spent 14 % more CPU on an optimize run, docs/performance.md).
  They start with SIGINT blocked: a Ctrl-C at the terminal stops the caller, which stops them.
* ``scheduler=ADDRESS``: an existing Dask distributed cluster (``dask scheduler`` /
  ``dask worker ADDRESS``), through ``distributed.Client``; Dask's own scheduler places the chunks
  and re-runs those of a lost worker.  A worker plugin (:class:`WarmUp`) loads the compiled solver
  once per worker process when the client registers it; a worker on a machine without numba's
  cache compiles it there once.

``map_unordered`` hands every item to the workers when it is called (local processes and a cluster
start on them at once, so that the caller can do other work meanwhile; in this process they run as
they are iterated).  ``shares_files``: whether the workers write to this process's file system (this
process and local processes do; a cluster's workers may be other machines).

A lost local worker or a cluster that gives up on a chunk ends the iteration with
:class:`WorkLost` after every finished result was yielded; Ctrl-C (KeyboardInterrupt) passes
through the same way.  The callers keep what finished.
"""
from __future__ import annotations

import concurrent.futures as cf
import contextlib
import functools
import multiprocessing
import os
import signal
import threading
from collections.abc import Callable, Iterable, Iterator
from typing import Any

from . import interrupts
from .errors import UserError


#: the thread counts local worker processes start with (the processes are the parallelism)
ONE_THREAD = {name: "1" for name in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                     "NUMBA_NUM_THREADS")}


@contextlib.contextmanager
def one_thread_environment():
    """:data:`ONE_THREAD` in this process's environment meanwhile: read by the libraries as the processes
    started meanwhile import them."""
    saved = {k: os.environ.get(k) for k in ONE_THREAD}
    os.environ.update(ONE_THREAD)
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


class WorkLost(RuntimeError):
    """A worker died or the cluster gave up on a chunk: the finished chunks are kept."""


def load_solver() -> None:
    """The default warm-up of a worker: the compiled solver's functions (numba's cache) in this process."""
    from .solver import backends

    if backends.AVAILABLE:
        backends.namespace("compiled")


def warm_up(initializer=None) -> None:
    """A worker's start: numba single-threaded, then ``initializer`` (a module-level function that runs
    the work once, so that every compiled function it needs is loaded) or :func:`load_solver`; then the
    objects made so far (imports, numba's cache loads: ~10^5 that live as long as the worker) are moved
    out of the garbage collector's reach (``gc.freeze``, as the ``beveloid`` script does before its exit):
    neither the collections during its tasks nor its exit walk them (a worker's exit took ~0.35 s
    more without it, docs/performance.md)."""
    import gc

    single_threaded()
    (initializer or load_solver)()
    gc.freeze()


def single_threaded() -> None:
    """numba's thread count is per calling thread: a task on a Dask worker thread sets it itself."""
    from .solver import backends

    if backends.AVAILABLE:
        import numba

        numba.set_num_threads(1)


def default_workers() -> int:
    """The cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not Linux
        return max(1, os.cpu_count() or 1)


class _Serial:
    shares_files = True

    def __init__(self):
        self.description = "1 worker (this process)"

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def map_unordered(self, fn: Callable, items: Iterable) -> Iterator[tuple[int, Any]]:
        for i, item in enumerate(items):
            with interrupts.guard():  # a Ctrl-C swallowed inside fn (numba's compile callbacks) stops here
                result = fn(item)
            yield i, result


def resource_tracker_running() -> None:
    """Start multiprocessing's resource tracker now if it is not running: its start (on the first lock or
    queue a pool makes) blocks SIGINT and then UNBLOCKS it, undoing a block held meanwhile, so that the
    workers started next take the terminal's Ctrl-C while they import (their tracebacks, issue 60).
    Started before SIGINT is blocked, it leaves the block alone."""
    from multiprocessing import resource_tracker

    resource_tracker.ensure_running()


@contextlib.contextmanager
def _sigint_blocked():
    """SIGINT blocked in this thread meanwhile (a Ctrl-C then arrives as soon as it is unblocked): the
    processes started meanwhile inherit the blocked signal, so the terminal's Ctrl-C, which goes to
    every process of its group, reaches only this one, which stops them (no traceback from each)."""
    if not hasattr(signal, "pthread_sigmask"):  # not POSIX
        yield
        return
    resource_tracker_running()
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


class _Local:
    shares_files = True

    def __init__(self, workers: int, initializer=None):
        self.workers = workers
        self.initializer = initializer
        self.description = f"{workers} local worker processes"
        self._pool = None
        self._used = False

    def __enter__(self):
        ctx = multiprocessing.get_context("spawn")
        self._pool = cf.ProcessPoolExecutor(self.workers, mp_context=ctx, initializer=warm_up,
                                            initargs=(self.initializer,))
        # every process starts now (the pool starts one per submitted task): their start (Python, numba's
        # cache loads, the initializer) runs while the caller prepares its work (issue 59)
        with _sigint_blocked(), one_thread_environment():
            for _ in range(self.workers):
                self._pool.submit(_started)
        return self

    def __exit__(self, *exc):
        if exc[0] is not None or not self._used:
            # a Ctrl-C or an error outside map_unordered's loop: work still submitted is abandoned; or no work
            # was handed out (a resumed run with nothing left): the processes are not waited for (they may
            # still be starting)
            self._stop_processes()
        self._pool.shutdown(wait=exc[0] is None, cancel_futures=True)
        return False

    def map_unordered(self, fn, items):
        # (the processes started in __enter__ never see the terminal's Ctrl-C and run on one thread; so does
        # one started here)
        self._used = True
        with _sigint_blocked(), one_thread_environment():
            futures = {self._pool.submit(fn, item): i for i, item in enumerate(items)}
        return self._results(futures)

    def _results(self, futures):
        try:
            for fut in cf.as_completed(futures):
                try:
                    result = fut.result()
                except cf.process.BrokenProcessPool as exc:
                    raise WorkLost(f"a local worker process died ({exc})") from None
                interrupts.check()
                yield futures[fut], result
        except (KeyboardInterrupt, GeneratorExit):  # Ctrl-C here or in the caller (which then drops this)
            self._stop_processes()  # they ignore Ctrl-C: the work in progress is abandoned
            raise
        finally:
            for fut in futures:
                fut.cancel()

    def _stop_processes(self):
        # (the pool's own table of its processes: ProcessPoolExecutor has no public way to stop them
        # before Python 3.14's terminate_workers)
        _quiet_broken_pool_race()
        for process in list((getattr(self._pool, "_processes", None) or {}).values()):
            process.terminate()


def _started() -> None:
    """The task that starts a local worker process (:meth:`_Local.__enter__`): nothing after its start."""


def _quiet_broken_pool_race() -> None:
    """Stopping the workers breaks the pool on purpose: the executor's manager thread then sets an
    exception on every pending future, and on Python 3.11 one already cancelled raises
    ``InvalidStateError`` in that thread, whose traceback printed a dozen lines after the one-line
    Ctrl-C message (seen under load).  That one error of that thread is not printed; every other
    thread's exception is, as before."""
    previous = threading.excepthook
    if getattr(previous, "_beveloid_quiet", False):
        return

    def hook(args):
        if issubclass(args.exc_type, cf.InvalidStateError) and "ExecutorManager" in type(args.thread).__name__:
            return
        previous(args)

    hook._beveloid_quiet = True
    threading.excepthook = hook


def __getattr__(name: str):
    """``WarmUp``, made on first use: distributed (~0.6 s to import) is imported only where a cluster is used,
    not by every command, local worker process or ``import beveloid.parallel``."""
    if name == "WarmUp":
        return _warm_up_plugin()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@functools.lru_cache(maxsize=None)
def _warm_up_plugin() -> type:
    from distributed import WorkerPlugin  # Dask is optional (the cluster extra): without it there is no --scheduler

    class WarmUp(WorkerPlugin):
        """Dask worker plugin: load the compiled solver once per worker process."""

        name = "beveloid-warm-up"

        def __init__(self, initializer=None):
            self.initializer = initializer

        def setup(self, worker):
            warm_up(self.initializer)

    WarmUp.__module__, WarmUp.__qualname__ = __name__, "WarmUp"  # pickled by reference, as a module-level class
    return WarmUp


def _lost_chunk_errors() -> tuple[type[BaseException], ...]:
    """The exception types by which Dask says a chunk is lost (not a bug in the chunk's function)."""
    import asyncio
    import concurrent.futures

    from distributed import KilledWorker
    from distributed.comm.core import CommClosedError

    # distributed's FutureCancelledError derives from concurrent.futures.CancelledError
    return KilledWorker, CommClosedError, asyncio.CancelledError, concurrent.futures.CancelledError


class _Dask:
    shares_files = False

    def __init__(self, address: str, initializer=None):
        self.address = address
        self.initializer = initializer
        self.description = f"Dask cluster at {address}"
        self._client = None

    def __enter__(self):
        try:
            from distributed import Client
        except ImportError:
            raise UserError(f"--scheduler = {self.address}: needs Dask distributed; pip install"
                            f" 'dask[distributed]'") from None
        try:
            self._client = Client(self.address, timeout="20s")
        except (OSError, TimeoutError) as exc:
            raise UserError(f"--scheduler = {self.address}: no Dask scheduler answers there ({exc}); start one with"
                            f" `dask scheduler` and workers with `dask worker ADDRESS`") from None
        try:
            plugin = _warm_up_plugin()
            self._client.register_plugin(plugin(self.initializer), name=plugin.name)
            workers = len(self._client.scheduler_info()["workers"])
        except BaseException:
            self._client.close()
            raise
        self.description = f"Dask cluster at {self.address} ({workers} workers)"
        return self

    def __exit__(self, *exc):
        self._client.close()
        return False

    def map_unordered(self, fn, items):
        futures = self._client.map(fn, list(items), pure=False)
        return self._results(futures)

    def _results(self, futures):
        from distributed import as_completed

        index = {f.key: i for i, f in enumerate(futures)}
        try:
            for fut in as_completed(futures):
                try:
                    result = fut.result()
                except _lost_chunk_errors() as exc:  # KilledWorker, a lost connection: keep what finished
                    raise WorkLost(f"the Dask cluster lost a chunk ({type(exc).__name__}: {exc})") from None
                yield index[fut.key], result
        finally:
            self._client.cancel([f for f in futures if not f.done()])


def executor(workers: int | None = None, scheduler: str | None = None, initializer=None):
    """An executor context: ``scheduler`` (a Dask address) or ``workers`` local processes (default: the
    cores); each worker process runs :func:`warm_up` (``initializer``) once when it starts."""
    if scheduler is not None and workers is not None:
        raise UserError(f"--workers = {workers} with --scheduler = {scheduler}: give one of them (the cluster's"
                        f" workers are set where they are started)")
    if scheduler is not None:
        return _Dask(scheduler, initializer)
    n = default_workers() if workers is None else workers
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 1024:
        raise UserError(f"--workers = {workers}: must be an integer from 1 to 1024")
    return _Serial() if n == 1 else _Local(n, initializer)
