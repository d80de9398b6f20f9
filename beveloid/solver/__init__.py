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
    def of(cls, solver: "Solver | str | None") -> "Solver":
        """A Solver from a Solver, a backend name or None (the default solver)."""
        if isinstance(solver, Solver):
            return solver
        return cls("auto" if solver is None else solver)


__all__ = ["DEFAULT_OPTIONS", "Solver", "SolverOptions"]
