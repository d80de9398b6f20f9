"""Loaded tooth contact analysis (LTCA) of crossed beveloid gears: approximate by construction
(Boussinesq half-space + thin-slice tooth beams, frictionless, static); the model, its choices and
its limits are in docs/loaded_contact.md.

    from beveloid.ltca import Options, analyze
    from beveloid.pair import Pair
    from beveloid.solver import Solver
    result = analyze(Pair.example("case1"), Options(torque_nm=200.0, flank="left"), Solver())

``analyze_many(pair, options, torques_nm, error_sets, solver)`` -> :class:`Batch`: N positions x T
torques x K error sets in one call, the one engine of ``analyze`` (``batch``).

Modules: ``options`` (the request and its range table), ``gaps`` (the unloaded gap from the
generated surfaces), ``grid`` (each pair's grid, sized from Hertz), ``compliance`` (the beveloid
compliance operator: half-space + tooth beams), ``cycle`` (the reference and the solves of
every position), ``kernel`` (the compiled active-set solve), ``analysis`` (the passes), ``result`` (the result and its JSON), ``pattern`` (the
pattern over the cycle), ``plots``; the mechanics: ``halfspace``, ``lcp``, ``hertz``,
``tooth_compliance``, ``checks``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .batch import Batch
from .compliance import BeveloidCompliance
from .options import DEFAULT_GRID, RANGES, Material, Options
from .pattern import FlankPattern, flank_pattern
from .result import LTCAResult, to_json_dict

__all__ = ["Batch", "BeveloidCompliance", "DEFAULT_GRID", "FlankPattern", "GridOptions", "LTCAResult", "Material",
           "Options", "RANGES", "analyze", "analyze_many", "flank_pattern", "to_json_dict"]


@dataclass(frozen=True)
class GridOptions:
    """Cells (across, along the contact line) per tooth pair, for the keyword form of :func:`analyze`."""

    across_cells: int = DEFAULT_GRID[0]
    along_cells: int = DEFAULT_GRID[1]


def analyze(pair, options: Options | None = None, solver=None, **legacy) -> LTCAResult:
    """The loaded TCA of one flank over one mesh cycle: ``analyze(pair_or_geometry, options,
    solver=None)`` -> an immutable :class:`LTCAResult` (its JSON: ``result.to_json_dict(geom)``).

    ``pair`` a :class:`beveloid.pair.Pair` (its misalignment and ``[material]`` are used unless
    ``options`` sets them) or a ``PairGeometry``; ``options`` an :class:`Options`; ``solver`` a
    :class:`beveloid.solver.Solver`, a backend name or None (the default solver).

    Deprecated, kept for the callers written before Options (tests/ltca, studies, benchmarks), with the
    tooth it had (the plate):
    ``analyze(geom, torque_nm, flank="right", errors=(0,)*5, positions=20, pairs=3, grid=GridOptions(),
    material=Material(), backend="auto")``.  ``Options.tooth_model`` defaults to the FE tooth.
    """
    from ..solver import Solver
    from .analysis import run

    if not isinstance(options, Options):
        options, solver = _keyword_form(options, solver, legacy)
    elif legacy:
        raise TypeError(f"analyze(pair, options, solver): give {', '.join(sorted(legacy))} in Options")
    geom = getattr(pair, "geometry", pair)
    errors = options.errors
    if errors is None:
        errors = getattr(pair, "errors", np.zeros(5))
    material = options.material
    if material is None:
        spec = getattr(pair, "spec", None)
        material = Material.from_spec(spec) if spec is not None else Material()
    return run(geom, errors, options, material, Solver.of(solver), pair=pair)


def analyze_many(pair, options: Options, torques_nm=None, error_sets=None, solver=None) -> Batch:
    """N positions x T torques x K error sets of one pair in one call: a :class:`Batch` whose
    ``results[k][t]`` equals ``analyze(pair, options with torque_nm = torques_nm[t] and errors =
    error_sets[k], solver)``.  ``torques_nm`` None: the options' torque; ``error_sets`` (K, 5) None:
    the options' errors (else the pair's misalignment).  ``options.material`` None: the pair's."""
    from ..solver import Solver
    from .analysis import run_many
    from .batch import check_error_sets, check_torques

    torques = check_torques([options.torque_nm] if torques_nm is None else torques_nm)
    if error_sets is None:
        error_sets = [options.errors if options.errors is not None else getattr(pair, "errors", np.zeros(5))]
    errors = check_error_sets(error_sets)
    geom = getattr(pair, "geometry", pair)
    material = options.material
    if material is None:
        spec = getattr(pair, "spec", None)
        material = Material.from_spec(spec) if spec is not None else Material()
    results = run_many(geom, list(errors), list(torques), options, material, Solver.of(solver), pair=pair)
    return Batch(torque_nm=torques, errors=errors, results=tuple(tuple(r) for r in results))


def _keyword_form(torque_nm, flank, kwargs):
    """(Options, backend) of the deprecated form analyze(geom, torque_nm, flank, **keywords)."""
    names = ("flank", "errors", "positions", "pairs", "grid", "material", "backend")
    values = {} if flank is None else {"flank": flank}
    if "torque_nm" in kwargs:
        torque_nm = kwargs.pop("torque_nm")
    for k in kwargs:
        if k not in names or k in values:
            raise TypeError(f"analyze() got an unexpected or repeated argument {k!r}")
    values.update(kwargs)
    grid = values.get("grid")
    if isinstance(grid, GridOptions):
        grid = (grid.across_cells, grid.along_cells)
    errors = values.get("errors")
    return (Options(torque_nm=torque_nm, flank=values.get("flank", "right"), positions=values.get("positions", 20),
                    pairs=values.get("pairs", 3), grid=grid,
                    errors=None if errors is None else tuple(np.asarray(errors, float).ravel()),
                    material=values.get("material"), tooth_model="plate"), values.get("backend", "auto"))
