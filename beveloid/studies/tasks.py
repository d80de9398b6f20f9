"""The pieces of ``beveloid paper`` on the machine's cores: local worker processes that run the
studies' independent pieces (each case's FE tooth data, error studies, crowning, loaded contact,
micro-geometry) while the main process waits for them and writes the report.

    with Tasks(workers=2) as tasks:
        handle = tasks.submit(fn, *args)     # fn: a module-level function, args picklable
        ...
        result = handle.get()                # its result, or the exception it raised

* ``workers=1``: each piece runs in this process when its result is asked for (the same code).
* ``workers=N``: a pool of N spawned processes (:mod:`multiprocessing`, ``spawn``: no state shared
  with this one), all started when the ``with`` block is entered.  Each runs numba and the BLAS / MKL
  libraries on one thread: the processes are the parallelism.  The workers ignore SIGINT (held
  blocked while the pool starts, in them and here: a Ctrl-C then is delivered, not lost): Ctrl-C
  reaches this process (the terminal sends it to every process of the group), which ends the workers
  (``terminate``) and passes the interrupt on.
* A worker that dies (killed by the out-of-memory killer, say) takes its piece with it, and a
  ``multiprocessing.Pool`` would wait for that piece forever: while this process waits for a result
  it checks every half second that the workers are alive, and raises
  :class:`beveloid.parallel.WorkLost` naming the worker (its pid and how it ended) and the piece it
  was running.  The ``with`` block then ends the other workers.

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
import time

from .. import interrupts
from ..parallel import one_thread_environment, resource_tracker_running


def say(msg) -> None:
    """A progress line on stderr, in one write: the processes' lines interleave whole."""
    sys.stderr.write(f"{msg}\n")
    sys.stderr.flush()


#: a worker's end of the queue on which it says which piece it starts (set by :func:`_worker_start`)
_started = None


#: how long entering waits for the workers to start (s); a worker not up by then is left to check_workers
WORKER_START_S = 120.0


def _worker_start(started) -> None:
    global _started
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the main process's to handle
    if hasattr(signal, "pthread_sigmask"):  # started with SIGINT blocked (Tasks.__enter__): a held one is dropped now
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    started.put((os.getpid(), None))  # up: Tasks.__enter__ waits for every worker to say so
    from ..parallel import single_threaded

    _started = started
    single_threaded()


def _piece_name(fn, args) -> str:
    """A piece in words for the message of a lost worker: ``module.function(args)``, shortened."""
    text = f"{fn.__module__}.{fn.__qualname__}({', '.join(map(repr, args))})"
    return text if len(text) <= 120 else text[:117] + "..."


def _run_piece(fn, args):
    """In a worker: say which piece this process starts (its pid and the piece), then run it."""
    _started.put((os.getpid(), _piece_name(fn, args)))
    return fn(*args)


def _how_it_ended(exitcode: int) -> str:
    if exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = f"signal {-exitcode}"
        return f"was killed by {name}" + (" (as the out-of-memory killer does)" if -exitcode == signal.SIGKILL else "")
    return f"exited with status {exitcode}"


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
        self._processes = []  # the pool's worker processes as started
        self._started = None  # the queue on which they say which piece they start
        self._running = {}  # pid -> the piece that worker started last
        self._pending = []  # the handles submitted
        self._up = set()  # the pids of the workers whose initializer has run

    def __enter__(self):
        if self.workers > 1:
            # started with SIGINT blocked (a blocked signal stays blocked across exec), the workers hold a
            # Ctrl-C that arrives while they start until their initializer ignores it: no traceback from a
            # worker that is still starting.  Blocked, not ignored, in this process too: a Ctrl-C that
            # arrives while the pool starts is held and delivered when it is unblocked, not lost
            block = threading.current_thread() is threading.main_thread() and hasattr(signal, "pthread_sigmask")
            if block:  # its first start unblocks SIGINT (multiprocessing.resource_tracker): before the block
                resource_tracker_running()
            mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT}) if block else None
            ctx = multiprocessing.get_context("spawn")
            try:
                before = set(multiprocessing.active_children())
                self._started = ctx.SimpleQueue()
                # the pool starts its processes here, under this signal mask and one thread each
                with one_thread_environment():
                    self._pool = ctx.Pool(self.workers, initializer=_worker_start, initargs=(self._started,))
                self._processes = [p for p in multiprocessing.active_children() if p not in before]
                # every worker up (its initializer run) before a Ctrl-C held meanwhile is delivered: a worker
                # stopped while it unpickles its start-up data prints a traceback (its semaphore is gone)
                deadline = time.monotonic() + WORKER_START_S
                while (len(self._up) < len(self._processes) and time.monotonic() < deadline
                       and all(p.exitcode is None for p in self._processes)):
                    time.sleep(0.01)
                    self._read_started()
            finally:
                if block:
                    try:
                        signal.pthread_sigmask(signal.SIG_SETMASK, mask)  # a Ctrl-C held meanwhile arrives here
                    except BaseException:
                        if self._pool is not None:
                            self._stop()
                        raise
        return self

    def __exit__(self, exc_type, *exc):
        if self._pool is None:
            return False
        if exc_type is not None:  # Ctrl-C, an error or a lost worker: the pieces still running are abandoned
            self._stop()
            return False
        try:
            for handle in self._pending:  # the pieces not asked for: waited for as get() waits (a lost worker raises)
                handle.wait()
        except BaseException:
            self._stop()
            raise
        self._pool.close()
        self._pool.join()
        return False

    def _stop(self) -> None:
        self._pool.terminate()
        self._pool.join()

    def submit(self, fn, *args):
        """A handle whose ``get()`` returns ``fn(*args)`` (raises what it raised, and
        :class:`~beveloid.parallel.WorkLost` if a worker process died)."""
        if self._pool is None:
            return _Now(fn, args)
        handle = _Remote(self, self._pool.apply_async(_run_piece, (fn, args)))
        self._pending.append(handle)
        self._read_started()
        return handle

    def _read_started(self) -> None:
        """The workers' "piece started" lines so far (read often: the pipe holds some 400 of them)."""
        while not self._started.empty():
            pid, name = self._started.get()
            if name is None:
                self._up.add(pid)
            else:
                self._running[pid] = name

    def check_workers(self) -> None:
        """Raise :class:`~beveloid.parallel.WorkLost` if a worker process has ended: the piece it was
        running is lost, and the pool would wait for it forever."""
        from ..parallel import WorkLost

        self._read_started()  # (also keeps the pipe from filling)
        dead = [p for p in self._processes if p.exitcode is not None]
        if not dead:
            return
        self._read_started()  # what it said before it died
        p = dead[0]
        piece = self._running.get(p.pid)
        raise WorkLost(f"a worker process (pid {p.pid}) {_how_it_ended(p.exitcode)} "
                       + (f"while running {piece}" if piece else "before it started a piece"))


class _Remote:
    def __init__(self, tasks, result):
        self._tasks, self._result = tasks, result

    def wait(self) -> None:
        while True:  # in steps: a Ctrl-C (or one that numba swallowed) and a lost worker are seen while waiting
            interrupts.check()
            self._result.wait(timeout=0.5)
            if self._result.ready():
                return
            self._tasks.check_workers()

    def get(self):
        self.wait()
        return self._result.get()
