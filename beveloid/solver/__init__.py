"""The contact solver: one core (:mod:`.core`), its two backends (:mod:`.backends`) and the
:class:`Solver` object that every analysis takes (backend and tolerances resolved once).

    from beveloid.solver import Solver
    solver = Solver()                      # backend "auto": compiled when numba is installed
    solver = Solver("numpy")               # the interpreted reference of the same core
    solver.core.solve_paths(...)           # the core's functions for that backend
"""
from __future__ import annotations

import types
from dataclasses import dataclass, field

from . import backends
from .options import DEFAULT_OPTIONS, SolverOptions


#: why :attr:`Solver.dense_backend` does not follow the solver's backend
DENSE_BACKEND_WHY = ("the backend chooses how the TCA core runs (\"numpy\": its interpreted reference); the dense "
                     "kernels outside it (the LTCA's active-set solve, the FE tooth's root stresses) interpreted are "
                     "pure-Python loops over dense blocks, ~100x slower for the same numbers "
                     "(tests/ltca/test_ltca_batch.py compares the two), so they run compiled wherever numba is installed")


@dataclass(frozen=True)
class Solver:
    """A resolved backend ("numpy" or "compiled") and the solver's tolerances.

    ``Solver("auto")`` resolves once, here; bad backends are refused with one line.
    """

    backend: str = "auto"
    options: SolverOptions = field(default_factory=SolverOptions)

    def __post_init__(self):
        object.__setattr__(self, "backend", backends.resolve(self.backend))

    @property
    def compiled(self) -> bool:
        return self.backend == "compiled"

    @property
    def core(self) -> types.SimpleNamespace:
        """The core's functions on this backend (compiled, or loaded from numba's cache, on first use)."""
        return backends.namespace(self.backend)

    @property
    def dense_backend(self) -> str:
        """The backend of the dense kernels outside the core (the LTCA's contact solve and assembly,
        the FE tooth's root stresses): "compiled" wherever numba is installed, whatever :attr:`backend`
        (:data:`DENSE_BACKEND_WHY`); "numpy" without numba."""
        return "compiled" if backends.AVAILABLE else "numpy"

    def announced_core(self) -> types.SimpleNamespace:
        """:attr:`core`, saying on the terminal when numba has to compile it first."""
        ns = self.core
        backends.notify_compiling(ns)
        return ns

    @classmethod
    def of(cls, solver: "Solver | None") -> "Solver":
        """``solver`` itself, or the default solver for None.  A backend name is refused: below the
        command line every function takes a Solver (``Solver(name)`` is the one converter of a name)."""
        if isinstance(solver, Solver):
            return solver
        if solver is None:
            return cls()
        raise TypeError(f"expected a beveloid.solver.Solver or None, not {solver!r}: pass Solver({solver!r})"
                        if isinstance(solver, str) else
                        f"expected a beveloid.solver.Solver or None, not {type(solver).__name__}")


__all__ = ["DENSE_BACKEND_WHY", "DEFAULT_OPTIONS", "Solver", "SolverOptions"]
