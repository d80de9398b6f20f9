"""The pieces of ``beveloid paper`` on the machine's cores: local worker processes that run the
studies' independent pieces (each case's FE tooth data, error studies, crowning, loaded contact,
micro-geometry) while the main process waits for them and writes the report.

    with Tasks(workers=2) as tasks:
        handle = tasks.submit(fn, *args)     # fn: a module-level function, args picklable
        ...
        result = handle.get()                # its result, or the exception it raised

* ``workers=1``: each piece runs in this process when its result is asked for (the same code).
* ``workers=N``: a pool of N spawned processes (:mod:`multiprocessing`, ``spawn``: no state shared
  with this one).  Each runs numba and the BLAS / MKL libraries on one thread: the processes are the
  parallelism.  The workers ignore SIGINT: Ctrl-C reaches this process (the terminal sends it to
  every process of the group), which ends the workers (``terminate``) and passes the interrupt on.

The pieces depend only on their arguments, never on the number of workers: one worker and N give
the same files and report.  (beveloid/parallel.py runs chunks of one function, results as they
finish; here the pieces differ and are waited for in the order the report needs them.)
"""
from __future__ import annotations

import multiprocessing
import os
import signal
import sys
import threading

from .. import interrupts

#: the thread counts the workers start with (the processes are the parallelism)
ONE_THREAD = {name: "1" for name in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                     "NUMBA_NUM_THREADS")}


def say(msg) -> None:
    """A progress line on stderr, in one write: the processes' lines interleave whole."""
    sys.stderr.write(f"{msg}\n")
    sys.stderr.flush()


def _worker_start() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the main process's to handle
    from ..parallel import single_threaded

    single_threaded()


class _Now:
    """The result of a piece run in this process when asked for."""

    def __init__(self, fn, args):
        self._fn, self._args, self._done = fn, args, False

    def get(self):
        if not self._done:
            with interrupts.guard():
                self._value = self._fn(*self._args)
            self._done = True
        return self._value


class Tasks:
    """Run pieces of work on ``workers`` processes (1: in this process); see the module docstring."""

    def __init__(self, workers: int = 1):
        self.workers = max(1, int(workers))
        self._pool = None

    def __enter__(self):
        if self.workers > 1:
            saved = {k: os.environ.get(k) for k in ONE_THREAD}
            os.environ.update(ONE_THREAD)  # read by the libraries as the workers import them
            # started with SIGINT ignored, the workers ignore it from their first instruction (an ignored
            # signal stays ignored across exec, and Python then installs no handler of its own): a Ctrl-C
            # at the terminal prints no traceback from a worker that is still starting
            ignore = threading.current_thread() is threading.main_thread()
            handler = signal.signal(signal.SIGINT, signal.SIG_IGN) if ignore else None
            try:
                self._pool = multiprocessing.get_context("spawn").Pool(self.workers, initializer=_worker_start)
            finally:
                if ignore:
                    signal.signal(signal.SIGINT, handler)
                for k, v in saved.items():
                    if v is None:
                        os.environ.pop(k, None)
                    else:
                        os.environ[k] = v
        return self

    def __exit__(self, exc_type, *exc):
        if self._pool is not None:
            if exc_type is None:
                self._pool.close()
            else:  # Ctrl-C or an error: the pieces still running are abandoned
                self._pool.terminate()
            self._pool.join()
        return False

    def submit(self, fn, *args):
        """A handle whose ``get()`` returns ``fn(*args)`` (raises what it raised)."""
        if self._pool is None:
            return _Now(fn, args)
        return _Remote(self._pool.apply_async(fn, args))


class _Remote:
    def __init__(self, result):
        self._result = result

    def get(self):
        while True:  # in steps: a Ctrl-C (or one that numba swallowed) is seen while waiting
            interrupts.check()
            try:
                return self._result.get(timeout=0.5)
            except multiprocessing.TimeoutError:
                continue
