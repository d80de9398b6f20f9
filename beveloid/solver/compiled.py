"""The compiled backend: the solver core's modules, and the generated scalar kernels they call,
compiled by numba from the same source files as the numpy backend runs.

How.  numba compiles a function together with the functions it calls, and finds them, when it
compiles, under their names in the function's module (its globals): there each must be a numba
dispatcher, while the numpy backend needs the plain functions under the same names.  So
:func:`load` executes each module of the core a second time, from its own file, as a module of
the package ``beveloid_compiled`` (which exists only in ``sys.modules``): its *compiled twin*
(``beveloid.solver.newton`` -> ``beveloid_compiled.solver.newton``).  Right after a twin is
executed, every function it defines is replaced, in the twin, by its numba dispatcher
(``numba.njit`` of that very function, :func:`beveloid.solver.backends.jit`).  The twins are
loaded callees first (:data:`TWINS`: the generated kernels, then linalg, newton, ...), so what a
twin imports from another twin (``from .newton import newton``) is a dispatcher already.  A
module that is not compiled (status, the numpy tca_kernels, patch_cover, records) is the same
module under both names.  The original modules are untouched: they are the numpy backend.
"""
from __future__ import annotations

import importlib
import importlib.util
import sys
import types

#: the package of the compiled twins (only in sys.modules)
ROOT = "beveloid_compiled"


def twin_name(module) -> str:
    """``beveloid.solver.newton`` -> ``beveloid_compiled.solver.newton``."""
    return ROOT + module.__name__[len("beveloid"):]


def _package(name):
    if name not in sys.modules:
        pkg = types.ModuleType(name)
        pkg.__path__ = []  # a package: its modules are put in sys.modules by load()
        sys.modules[name] = pkg


def _alias_the_rest(twinned):
    """Every module of beveloid that is not compiled, under its twin name too (the twins' relative
    imports of status, tca_kernels, records, ... then find the very same module)."""
    for name, mod in list(sys.modules.items()):
        if name.startswith("beveloid.") and mod is not None and name not in twinned and not hasattr(mod, "__path__"):
            sys.modules.setdefault(ROOT + name[len("beveloid"):], mod)


def load(modules, jit):
    """The compiled twins of ``modules`` (callees first): a dict real module -> twin in which
    ``jit(function, module)`` has replaced each function the module defines."""
    twinned = {m.__name__ for m in modules}
    for m in modules:
        parts = twin_name(m).split(".")
        for i in range(1, len(parts)):
            _package(".".join(parts[:i]))
    _alias_the_rest(twinned)
    twins = {}
    for m in modules:
        name = twin_name(m)
        if sys.modules.get(name) in (None, m):  # none yet, or the alias of a module not compiled until now
            spec = importlib.util.spec_from_file_location(name, m.__file__)
            twin = importlib.util.module_from_spec(spec)
            sys.modules[name] = twin
            spec.loader.exec_module(twin)  # its imports of earlier twins bind their dispatchers
            for attr, fn in list(vars(twin).items()):
                if isinstance(fn, types.FunctionType) and fn.__module__ == name:
                    setattr(twin, attr, jit(fn, m))
        twins[m] = sys.modules[name]
    return twins
