"""The compiled backend's parallel sweep: many error sets solved on threads.

The compiled ``solve_paths`` is the one serial function (``nogil``: numba releases the GIL while it
runs) called on slices of the error sets, each on a thread of a pool.  The paths of different error
sets share nothing, so the numbers are those of one serial call, on any number of threads.

:func:`map_unordered` runs whole pieces of work on the same pool (the sweep: each piece of error
sets drawn, solved and reduced to its per-set numbers on its thread), so that nothing but the
gathering waits on one thread; what a piece calls there runs single-threaded.

Before, numba compiled ``solve_paths`` a second time with ``parallel=True`` (its ``prange`` over
error sets): ~7 s more of the first compilation, and ~8 ms to start its threads on every call.
The thread count is numba's (``numba.set_num_threads``, ``NUMBA_NUM_THREADS``), read in the calling
thread when the call starts, so that a Dask worker's task set to one thread stays on one.
"""
from __future__ import annotations

import concurrent.futures
import functools
import itertools
import os
import queue
import threading

#: chunks per thread: small enough that a thread with slow paths does not finish last alone,
#: large enough that a chunk's call costs nothing next to its paths
CHUNKS_PER_THREAD = 4

_pool: concurrent.futures.ThreadPoolExecutor | None = None
_pool_lock = threading.Lock()
#: ``inside`` is set in the pool's own threads: work running there stays on its thread (a task that
#: waited for tasks queued behind it on the same pool would wait for ever)
_here = threading.local()


def _mark_pool_thread() -> None:
    _here.inside = True


def _threads() -> int:
    """The threads a call made from this thread may use: numba's count for it (1 in the pool's own)."""
    if getattr(_here, "inside", False):
        return 1
    import numba

    return numba.get_num_threads()


def count() -> int:
    """The threads a call made from this thread may use (numba's count for it; 1 in the pool's own)."""
    return _threads()


def _executor(threads: int) -> concurrent.futures.ThreadPoolExecutor:
    global _pool
    with _pool_lock:
        if _pool is None or _pool._max_workers < threads:
            old, _pool = _pool, concurrent.futures.ThreadPoolExecutor(max_workers=threads,
                                                                      thread_name_prefix="beveloid-paths",
                                                                      initializer=_mark_pool_thread)
            if old is not None:
                old.shutdown(wait=False)
        return _pool


def _forget_pool() -> None:
    """In a forked child the parent's threads do not exist: start a pool of its own when needed."""
    global _pool, _pool_lock
    _pool, _pool_lock = None, threading.Lock()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pool)


def chunk_bounds(count: int, chunks: int) -> list[tuple[int, int]]:
    """``chunks`` (at most ``count``) consecutive slices of range(count), sizes differing by one at most."""
    chunks = max(1, min(chunks, count))
    edges = [count * i // chunks for i in range(chunks + 1)]
    return list(zip(edges[:-1], edges[1:]))


def over_error_sets(serial):
    """``solve_paths(problem, request, settings, out)`` running the compiled ``serial`` over slices of
    ``request.errors`` (and the same slices of ``out``) on numba's thread count."""

    @functools.wraps(getattr(serial, "py_func", serial))
    def solve_paths(problem, request, settings, out):
        count = request.errors.shape[0]
        threads = min(_threads(), count)
        if threads <= 1:
            serial(problem, request, settings, out)
            return
        bounds = chunk_bounds(count, threads * CHUNKS_PER_THREAD)
        following = itertools.count()  # each thread takes the next chunk not yet taken (next() holds the GIL)

        def work():
            while (i := next(following)) < len(bounds):
                a, b = bounds[i]
                serial(problem, request._replace(errors=request.errors[a:b]), settings,
                       out._replace(**{k: v[a:b] for k, v in out._asdict().items()}))

        pool = _executor(threads)
        futures = [pool.submit(work) for _ in range(threads)]
        for f in futures:
            f.result()

    return solve_paths


def pieces(count: int, threads: int, largest: int, smallest: int = 16) -> list[tuple[int, int]]:
    """Bounds of the pieces of ``count`` items for :func:`map_unordered` on ``threads`` threads: a
    multiple of ``threads`` pieces (whole waves), at least CHUNKS_PER_THREAD a thread (a thread that
    drew slow items does not finish last alone), none over ``largest`` items, none under ``smallest``
    when avoidable (a piece's own start costs next to nothing then)."""
    waves = max(CHUNKS_PER_THREAD, -(-count // (threads * largest)))
    return chunk_bounds(count, max(min(threads * waves, count // smallest), -(-count // largest)))


def map_unordered(fn, items, threads: int):
    """(index, fn(item)) of each of ``items`` as they finish, on ``threads`` threads of the pool: each
    takes the next item not yet taken.  ``fn`` runs whole on its thread, and what it calls there runs
    single-threaded (:func:`_threads`).  An exception in ``fn`` is raised here; when the caller stops
    early (that exception, a Ctrl-C) the items not started are dropped and those running finish on
    their threads."""
    items = list(items)
    following = itertools.count()  # next() holds the GIL: each item is taken once
    finished = queue.SimpleQueue()
    stop = threading.Event()

    def work():
        while not stop.is_set() and (i := next(following)) < len(items):
            try:
                finished.put((i, fn(items[i]), None))
            except BaseException as exc:  # raised in the caller's thread
                finished.put((i, None, exc))
                return

    pool = _executor(threads)
    for _ in range(min(threads, len(items))):
        pool.submit(work)
    try:
        for _ in range(len(items)):
            i, result, exc = finished.get()
            if exc is not None:
                raise exc
            yield i, result
    finally:
        stop.set()
