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


__all__ = ["DEFAULT_OPTIONS", "Solver", "SolverOptions"]
