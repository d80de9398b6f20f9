"""Loaded tooth contact analysis (LTCA) of crossed beveloid gears: approximate by construction
(Boussinesq half-space + thin-slice tooth beams, frictionless, static); the model, its choices and
its limits are in docs/loaded_contact.md.

    from beveloid.ltca import Options, analyze
    from beveloid.pair import Pair
    from beveloid.solver import Solver
    result = analyze(Pair.example("case1"), Options(torque_nm=200.0, flank="left"), Solver())

Modules: ``options`` (the request and its range table), ``gaps`` (the unloaded gap from the
generated surfaces), ``grid`` (each pair's grid, sized from Hertz), ``compliance`` (the beveloid
compliance operator: half-space + tooth beams), ``cycle`` (the reference and one solve per
position), ``analysis`` (the passes), ``result`` (the result and its JSON), ``pattern`` (the
pattern over the cycle), ``plots``; the mechanics: ``halfspace``, ``lcp``, ``hertz``,
``tooth_compliance``, ``checks``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .compliance import BeveloidCompliance
from .options import DEFAULT_GRID, RANGES, Material, Options
from .pattern import FlankPattern, flank_pattern
from .result import LTCAResult, to_json_dict

__all__ = ["BeveloidCompliance", "DEFAULT_GRID", "FlankPattern", "GridOptions", "LTCAResult", "Material",
           "Options", "RANGES", "analyze", "flank_pattern", "to_json_dict"]


@dataclass(frozen=True)
class GridOptions:
    """Cells (across, along the contact line) per tooth pair, for the keyword form of :func:`analyze`."""

    across_cells: int = DEFAULT_GRID[0]
    along_cells: int = DEFAULT_GRID[1]


def analyze(pair, options=None, solver=None, *args, **kwargs) -> LTCAResult:
    """The loaded TCA of one flank over one mesh cycle.

    ``analyze(pair, options, solver)``: ``pair`` a :class:`beveloid.pair.Pair` (its misalignment and
    ``[material]`` are used unless ``options`` sets them) or a ``PairGeometry``; ``options`` an
    :class:`Options`; ``solver`` a :class:`beveloid.solver.Solver` (default: the default solver).

    The keyword form of earlier versions is kept, with the tooth it had (the plate):
    ``analyze(geom, torque_nm, flank="right", errors=(0,)*5, positions=20, pairs=3, grid=GridOptions(),
    material=Material(), backend="auto")``.  ``Options.tooth_model`` defaults to the FE tooth.
    """
    from ..solver import Solver
    from .analysis import run

    if not isinstance(options, Options):
        options, solver = _keyword_form(options, solver, args, kwargs)
    elif args or kwargs:
        raise TypeError("analyze(pair, options, solver) takes no further arguments")
    geom = getattr(pair, "geometry", pair)
    errors = options.errors
    if errors is None:
        errors = getattr(pair, "errors", np.zeros(5))
    material = options.material
    if material is None:
        spec = getattr(pair, "spec", None)
        material = Material.from_spec(spec) if spec is not None else Material()
    return run(geom, errors, options, material, Solver.of(solver), pair=pair)


def _keyword_form(torque_nm, third, args, kwargs):
    names = ("flank", "errors", "positions", "pairs", "grid", "material", "backend")
    values = dict(zip(names, ((third,) if third is not None else ()) + tuple(args)))
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
