"""The two backends of the one solver core (:mod:`beveloid.solver.core`).

* ``"numpy"``: the core's functions as they are, over the generated scalar kernels: the
  reference, needs nothing beyond numpy, slow (interpreted).
* ``"compiled"``: the same functions and kernels compiled by numba (``nogil``, the sweep on
  threads over error sets: :mod:`beveloid.solver.threads`; reference counting only where arrays are allocated; how the same
  source is compiled: :mod:`beveloid.solver.compiled`), with numba's
  on-disk cache: next to the sources, or in the folder named by ``BEVELOID_CACHE_DIR`` (or
  numba's own ``NUMBA_CACHE_DIR``).  Where the sources' folder cannot be written (a read-only
  install) the cache goes to the user's cache folder (``$XDG_CACHE_HOME/beveloid`` or
  ``~/.cache/beveloid``), else to the temporary folder; only when none can be written is the
  solver compiled in memory, with one line on stderr.

``"auto"`` is "compiled" when numba is installed.  Both run the same source, so they give the
same statuses and the same numbers.
"""
from __future__ import annotations

import functools
import hashlib
import importlib
import importlib.util
import os
import sys
import tempfile
import types

#: numba is installed (it is imported only when the compiled backend is first used: ~0.3 s).
AVAILABLE = importlib.util.find_spec("numba") is not None

BACKENDS = ("auto", "compiled", "numpy")


class BackendError(ValueError):
    """A backend that does not exist or is not installed: ``backend`` and ``requirement`` (what is valid)."""

    def __init__(self, backend, requirement):
        self.backend, self.requirement = backend, requirement
        super().__init__(f"backend = {backend}: {requirement}")


def resolve(backend: str) -> str:
    """'auto' -> 'compiled' when numba is installed, else 'numpy'."""
    if backend == "auto":
        return "compiled" if AVAILABLE else "numpy"
    if backend == "compiled" and not AVAILABLE:
        raise BackendError(backend, "numba is not installed; use backend numpy or pip install numba")
    if backend not in BACKENDS:
        raise BackendError(repr(backend), f"must be one of {', '.join(BACKENDS)}")
    return backend


#: the core's modules, by job (beveloid.solver.core is their one namespace)
CORE_MODULES = ("linalg", "newton", "first_touch", "clearance", "paths", "gaps", "chord")


def _modules():
    """Every generated scalar module the core reaches and the core's modules, callees first (all
    compiled together, in this order: beveloid.solver.compiled)."""
    from .. import generated
    from . import core

    gen = [importlib.import_module(f"{generated.__name__}.{m}") for m in generated.SCALAR_MODULES]
    gen.append(importlib.import_module(f"{generated.__name__}.tca_kernels_scalar"))
    jobs = [importlib.import_module(f"{__package__}.{m}") for m in CORE_MODULES]
    return gen + jobs + [core]


@functools.lru_cache(maxsize=None)
def namespace(backend: str) -> types.SimpleNamespace:
    """The core's functions (and the generated kernels it imports) for a resolved backend."""
    from . import core

    if backend == "numpy":
        funcs = {k: _quiet(v) for k, v in vars(core).items() if isinstance(v, types.FunctionType)}
        funcs.update({name + "_serial": funcs[name] for name in core.PARALLEL})
        return types.SimpleNamespace(**funcs, compiled=False)
    if backend != "compiled":
        raise ValueError(f"backend must be 'numpy' or 'compiled', got {backend!r}")
    return _compile(_modules())


def _quiet(fn):
    """``fn`` under ``numpy.errstate(all="ignore")``.  Run by the interpreter, the core's scalar
    arithmetic is numpy's, which warns where a diverging Newton iterate overflows (relieved flanks
    far off their patch); the core already answers such a point by its status (a non-finite
    residual is not converged), as the compiled core does silently, so the warnings are noise."""
    import numpy

    @functools.wraps(fn)
    def quiet(*args, **kwargs):
        with numpy.errstate(all="ignore"):
            return fn(*args, **kwargs)

    return quiet


_cache_warned = False
_cache_redirected = False
#: names the folder of the compiled solver's cache (before numba's own NUMBA_CACHE_DIR)
CACHE_ENV = "BEVELOID_CACHE_DIR"


@functools.lru_cache(maxsize=None)
def _nrt_option() -> bool:
    """numba takes the (underscored, so unpromised) _nrt option: without it every function keeps
    reference counting (slower, the same results)."""
    try:
        from numba.core import cpu

        return hasattr(cpu.CPUTargetOptions, "_nrt")
    except ImportError:  # numba internals moved
        return False


def _writable(folder) -> bool:
    try:
        os.makedirs(folder, exist_ok=True)
        return os.access(folder, os.W_OK | os.X_OK)
    except OSError:
        return False


def fallback_cache_dir() -> str | None:
    """A writable folder for numba's cache when the sources' folder is not: BEVELOID_CACHE_DIR,
    the user's cache folder, the temporary folder (per user); None if none can be written."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    uid = os.getuid() if hasattr(os, "getuid") else os.environ.get("USERNAME", "user")
    for folder in (os.environ.get(CACHE_ENV), os.path.join(base, "beveloid", "numba"),
                   os.path.join(tempfile.gettempdir(), f"beveloid-numba-{uid}")):
        if folder and _writable(folder):
            return folder
    return None


def _use_cache_dir(numba, folder):
    numba.config.CACHE_DIR = folder


def _jit(fn, inline="never", nrt=True):
    global _cache_warned, _cache_redirected
    import numba

    opts = dict(nogil=True, inline=inline)
    if _nrt_option():
        # numba's reference counting, off for the functions that allocate nothing (core.ALLOCATING);
        # set explicitly either way, as a callee otherwise inherits its caller's setting
        opts["_nrt"] = nrt
    if not _cache_redirected and os.environ.get(CACHE_ENV) and not os.environ.get("NUMBA_CACHE_DIR"):
        _cache_redirected = True  # the user's choice, before the sources' folder
        if _writable(os.environ[CACHE_ENV]):
            _use_cache_dir(numba, os.environ[CACHE_ENV])
    for attempt in range(2):
        try:
            return numba.njit(cache=True, **opts)(fn)
        except RuntimeError as exc:  # "cannot cache function ...: no locator available"
            if "cannot cache" not in str(exc):
                raise
        folder = None if _cache_redirected else fallback_cache_dir()
        _cache_redirected = True
        if folder is None:
            break
        _use_cache_dir(numba, folder)
    if not _cache_warned:
        sys.stderr.write(f"beveloid: no writable folder for numba's cache (the install is read-only; set {CACHE_ENV}"
                         " to a writable folder): the contact solver is compiled in memory on every run\n")
        _cache_warned = True
    return numba.njit(cache=False, **opts)(fn)


def sources_stamp(modules) -> str:
    """A digest of the sources of every module compiled together.

    numba's on-disk cache checks only the source file of the function it caches, while these
    functions call (and inline) functions of the other modules: after ``beveloid derive`` changes a
    generated kernel or the glue (a new surface model), a cached core function would run the old
    kernels.  Each function's cache entry is therefore named after the digest of all the sources
    (its qualified name carries it), so changed sources compile afresh and unchanged ones load."""
    digest = hashlib.sha1()
    for mod in modules:
        with open(mod.__file__, "rb") as fh:
            digest.update(fh.read())
    return digest.hexdigest()[:12]


@functools.lru_cache(maxsize=None)
def core_stamp() -> str:
    """:func:`sources_stamp` of the core and the generated kernels it compiles with (for other
    compiled callers of the core, e.g. beveloid.explore, to name their cache entries by)."""
    return sources_stamp(_modules())


def _compile(modules):
    """The core's namespace on the compiled backend: the compiled twins of ``modules``
    (:mod:`beveloid.solver.compiled`), each function jit-compiled by :func:`_jit` with its options
    by name (``core.ALLOCATING``; ``core.PARALLEL`` on threads)."""
    from . import compiled, core, threads

    stamp = sources_stamp(modules)

    def jit(fn, module):
        name = fn.__name__
        fn.__qualname__ = f"{name}__{stamp}"  # its cache entry belongs to these sources
        # the generated kernels are not inlined: inlining them (numba inline="always") made an
        # evaluation ~20 % faster but the first compilation 157 s instead of 47 s; the glue that
        # dispatches to them (tca_kernels_scalar: small, unpacks the work tuples) is, which made the
        # first compilation faster too (docs/performance.md)
        inline = "always" if module.__name__.endswith(".tca_kernels_scalar") else "never"
        return _jit(fn, inline=inline, nrt=name in core.ALLOCATING)

    twins = compiled.load(modules, jit)
    twin_core = twins[core]
    # the core's functions and the kernels it imports, as the core sees them (by the core's names)
    funcs = {name: getattr(twin_core, name) for name, fn in vars(core).items() if isinstance(fn, types.FunctionType)}
    # where numba runs nothing compiled (NUMBA_DISABLE_JIT=1) the functions are the interpreted core
    funcs = {name: fn if hasattr(fn, "py_func") else _quiet(fn) for name, fn in funcs.items()}
    # each parallel function: the compiled serial one (its "_serial" name) run over slices of its
    # error sets on threads (beveloid.solver.threads); where numba compiles nothing, the serial one
    for name in core.PARALLEL:
        serial = funcs[name]
        funcs[name + "_serial"] = serial
        if hasattr(serial, "py_func"):
            funcs[name] = threads.over_error_sets(serial)
    return types.SimpleNamespace(**funcs, compiled=True)


@functools.lru_cache(maxsize=None)
def compiled_module(module_name: str, names: tuple):
    """A plain module outside the core (in numba's subset, importing nothing of the package) with its
    functions ``names`` compiled: the module executed again from its file as a twin (numba finds each
    function's callees, compiled, in its globals), each function jit-compiled by :func:`_jit` and cached
    on disk under the digest of that file.  None of the core is involved: its compile stays as it is."""
    module = importlib.import_module(module_name)
    name = module_name.replace(".", "_") + "__compiled"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, module.__file__)
        twin = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(twin)
        stamp = sources_stamp([module])
        for attr in names:
            fn = getattr(twin, attr)
            fn.__qualname__ = f"{attr}__{stamp}"  # its cache entry belongs to this source
            setattr(twin, attr, _jit(fn, nrt=True))
        sys.modules[name] = twin
    return sys.modules[name]


def needs_compiling(ns) -> bool:
    """True when the compiled sweep has no usable cache on disk (none yet, or one written for
    other sources): the first run compiles, ~10-60 s."""
    if not getattr(ns, "compiled", False):
        return False
    try:
        cache = ns.solve_paths_serial._cache
        if not hasattr(cache, "_cache_file"):  # compiled in memory: it compiles on every run
            return True
        return not cache._cache_file._load_index()  # empty when absent or stale (the sources changed)
    except Exception:  # numba internals moved: say nothing rather than guess
        return False


_notified = False


#: what every command says on stderr before numba compiles the solver (half a minute to a minute or more of CPU, without
#: output; docs/performance.md: `beveloid tca` 34.5 s of CPU at load 0.9 on one 2-core host, 72.5 s on a slower one,
#: 101.6 s wall at load 13.5)
COMPILING = ("beveloid: compiling the contact solver with numba: the first run after an installation or a change of"
             " the models (derive --model) takes from half a minute to a minute or two of CPU time, depending on the"
             " machine and the command, several minutes on a machine busy with other work; cached afterwards")


def notify_compiling(ns, stream=None):
    """Say on stderr that numba is about to compile (nothing when its cache serves), terminal or not:
    every command that solves a contact (tca, design, ltca, sweep, paper, ...) reaches it through
    :meth:`beveloid.solver.Solver.announced_core`.  The cache is looked at once per process (reading
    its index costs ~1 ms, more than a mesh study's solve)."""
    global _notified
    stream = stream or sys.stderr
    if _notified or not getattr(ns, "compiled", False):
        return
    _notified = True
    if needs_compiling(ns):
        try:
            stream.write(COMPILING + "\n")
            stream.flush()
        except (OSError, ValueError):  # a closed stderr: nothing can be said
            pass
