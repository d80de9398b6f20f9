"""What an LTCA request may ask: the one range table that the CLI, the JSON and :func:`analyze` read.

``Options`` is frozen and checks itself on construction: a bad value raises ``ValueError`` with one
line naming the key, the value and what is valid.  ``Material`` holds the elastic constants.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from ..errors import OptionError
from ..names import FLANKS
from .mechanics import halfspace

#: how the teeth bend: "fe" the finite-element tooth (beveloid.fe), "plate" the Kirchhoff plate over
#: the equivalent spur tooth (tooth_compliance.py)
TOOTH_MODELS = ("fe", "plate")
FE_REFINEMENTS = (1, 4)

#: (low, high) of every numeric option; pairs must also be odd
RANGES = {
    "torque_nm": (0.0, 1e6),  # > low, <= high (N m, pinion torque)
    "positions": (1, 400),
    "pairs": (1, 9),
    "grid_cells": (3, 201),  # cells across / along the contact line per tooth pair
    "fe_refinement": FE_REFINEMENTS,  # the FE tooth's mesh: every element size divided by it
    "fe_coarsen": (1.0, 8.0),  # and multiplied by this (> 1: a cheaper, rougher tooth for quick looks and tests)
}

#: default cells (across, along the contact line) per tooth pair; the cell size follows the local
#: Hertz semi-axes (grid.py: CELL_FRACTION)
DEFAULT_GRID = (11, 17)

#: bytes per (cell of one pair)^2 of one position: the pair's dense half-space block, the gathered
#: active block and its factorisation
_BYTES_PER_CELL_PAIR = 8 * 3
#: bytes per cell of every (position, pair): gaps, points, pressures of the three grids kept
_BYTES_PER_CELL = 8 * 40


@dataclass(frozen=True)
class Material:
    """Elastic constants (MPa) of both members (default steel)."""

    pinion_e_mpa: float = halfspace.STEEL_E_MPA
    pinion_nu: float = halfspace.STEEL_NU
    gear_e_mpa: float = halfspace.STEEL_E_MPA
    gear_nu: float = halfspace.STEEL_NU

    @classmethod
    def from_spec(cls, spec) -> "Material":
        m = spec.material
        return cls(m.pinion_youngs_modulus_gpa * 1e3, m.pinion_poisson_ratio,
                   m.gear_youngs_modulus_gpa * 1e3, m.gear_poisson_ratio)

    @property
    def e_star_mpa(self) -> float:
        return halfspace.reduced_modulus_mpa(self.pinion_e_mpa, self.pinion_nu, self.gear_e_mpa, self.gear_nu)


def check_torque(value, key="torque_nm"):
    lo, hi = RANGES["torque_nm"]
    t = float(value) if isinstance(value, (int, float)) else math.nan
    if not (math.isfinite(t) and lo < t <= hi):
        raise OptionError(key, value, f"must be a number > 0 and <= {hi:.0f} (N m)")
    return t


def _check_integer(value, key, name):
    lo, hi = RANGES[name]
    if not (isinstance(value, int) and not isinstance(value, bool) and lo <= value <= hi):
        raise OptionError(key, value, f"must be an integer from {lo} to {hi}")
    return value


def check_positions(value, key="positions"):
    return _check_integer(value, key, "positions")


def check_pairs(value, key="pairs"):
    lo, hi = RANGES["pairs"]
    if not (isinstance(value, int) and not isinstance(value, bool) and lo <= value <= hi and value % 2 == 1):
        raise OptionError(key, value, f"must be an odd integer from {lo} to {hi}")
    return value


def check_grid(value, key="grid"):
    """None (cells from the defaults) or (across, along) integers within RANGES["grid_cells"]."""
    if value is None:
        return None
    lo, hi = RANGES["grid_cells"]
    try:
        across, along = value
    except (TypeError, ValueError):
        across = along = None
    if not all(isinstance(v, int) and not isinstance(v, bool) and lo <= v <= hi for v in (across, along)):
        raise OptionError(key, value, f"must be ACROSSxALONG with two integers from {lo} to {hi}, e.g. "
                                      f"{DEFAULT_GRID[0]}x{DEFAULT_GRID[1]}")
    return (across, along)


def default_tooth_model() -> str:
    """"fe" when gmsh and scikit-fem are installed, else "plate" (found without importing them)."""
    from importlib.util import find_spec

    return "fe" if find_spec("gmsh") is not None and find_spec("skfem") is not None else "plate"


def check_tooth_model(value, key="tooth_model"):
    if value not in TOOTH_MODELS:
        raise OptionError(key, value, f"must be one of {', '.join(TOOTH_MODELS)}")
    return value


def check_fe_refinement(value, key="fe_refinement"):
    return _check_integer(value, key, "fe_refinement")


def check_fe_coarsen(value, key="fe_coarsen"):
    lo, hi = RANGES["fe_coarsen"]
    v = float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else math.nan
    if not (math.isfinite(v) and lo <= v <= hi):
        raise OptionError(key, value, f"must be a number from {lo:g} to {hi:g} (1: the default mesh; docs/rating.md 5 says how far it is from converged)")
    return v


def _numbers(value) -> bool:
    """A sequence (or array) of real numbers, not a string."""
    try:
        return not isinstance(value, (str, bytes)) and all(isinstance(v, (int, float, np.integer, np.floating))
                                                           and not isinstance(v, bool) for v in np.ravel(value))
    except TypeError:
        return False


def available_memory_bytes() -> float:
    """What this process may still allocate: the machine's available memory (Linux), else 4 GB."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return 4e9


@dataclass(frozen=True)
class Options:
    """How a loaded analysis is computed (the load itself is a :class:`beveloid.ltca.LoadCase`).
    ``grid``: cells (across, along) per tooth pair, None = :data:`DEFAULT_GRID` (their size follows
    the local Hertz semi-axes in both cases); ``material``: None = the pair's ``[material]`` (steel
    without a spec); ``tooth_model``: "fe" or "plate", None = "fe" when gmsh and scikit-fem import
    (:func:`default_tooth_model`); ``fe_refinement``: the FE tooth's mesh refinement N (1-4);
    ``fe_coarsen``: every FE element size times this (1-8; > 1 a quick, rougher tooth); ``angles``: the pinion
    angles (rad) to solve at instead of ``positions`` over the mesh cycle (``positions`` is then their count;
    no command line sets it: the rating's refinement of a maximum between positions,
    ``rating.analysis.refine_positions``)."""

    flank: str = "right"
    positions: int = 20
    pairs: int = 3
    grid: tuple | None = None
    material: Material | None = None
    tooth_model: str | None = None
    fe_refinement: int = 1
    fe_coarsen: float = 1.0
    angles: tuple | None = None

    def __post_init__(self):
        if self.tooth_model is None:
            object.__setattr__(self, "tooth_model", default_tooth_model())
        check_tooth_model(self.tooth_model)
        check_fe_refinement(self.fe_refinement)
        object.__setattr__(self, "fe_coarsen", check_fe_coarsen(self.fe_coarsen))
        if self.flank not in FLANKS:
            raise OptionError("flank", self.flank, f"must be one of {', '.join(FLANKS)}")
        if self.angles is not None:
            lo, hi = RANGES["positions"]
            a = np.asarray(self.angles, dtype=float).ravel() if _numbers(self.angles) else np.array([np.nan])
            if not (lo <= a.size <= hi and np.isfinite(a).all()):
                raise OptionError("angles", self.angles, f"must be {lo} to {hi} finite pinion angles (rad), or None")
            object.__setattr__(self, "angles", tuple(float(v) for v in a))
            object.__setattr__(self, "positions", len(self.angles))
        check_positions(self.positions)
        check_pairs(self.pairs)
        object.__setattr__(self, "grid", check_grid(self.grid))
        if self.material is not None and not isinstance(self.material, Material):
            raise OptionError("material", self.material, "must be an ltca.Material")

    @property
    def cells(self) -> tuple:
        """(across, along) cells per tooth pair."""
        return self.grid or DEFAULT_GRID

    def memory_bytes(self) -> float:
        """An estimate of the peak memory of the request (bytes)."""
        n = self.cells[0] * self.cells[1]
        return self.pairs * n * n * _BYTES_PER_CELL_PAIR + self.positions * self.pairs * n * _BYTES_PER_CELL

    def check_memory(self, available: float | None = None):
        """ValueError (one line) when the request will not fit in the available memory."""
        need = self.memory_bytes()
        have = available_memory_bytes() if available is None else available
        if need > 0.8 * have:
            raise OptionError("grid", f"{self.cells[0]}x{self.cells[1]}", f"needs about {need / 1e9:.1f} GB with "
                              f"{self.pairs} pairs and {self.positions} positions, {have / 1e9:.1f} GB are available;"
                              f" use fewer cells (the default {DEFAULT_GRID[0]}x{DEFAULT_GRID[1]} is sized from the"
                              " contact)")
