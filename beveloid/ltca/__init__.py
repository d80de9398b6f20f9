"""Loaded tooth contact analysis (LTCA) of crossed beveloid gears: approximate by construction
(Boussinesq half-space + thin-slice tooth beams, frictionless, static); the model, its choices and
its limits are in docs/loaded_contact.md.

    from beveloid.ltca import Options, analyze
    from beveloid.pair import Pair
    from beveloid.solver import Solver
    result = analyze(Pair.example("case1"), Options(torque_nm=200.0, flank="left"), solver=Solver())

``analyze_many(pair, options, torques_nm, error_sets, *, solver=None)`` -> :class:`Batch`: N positions x T
torques x K error sets in one call, the one engine of ``analyze`` (``batch``).

Its folders, from the request down: ``options`` (the request and its range table); ``passes`` (the
passes over the positions of a mesh cycle: ``analysis``, ``cycle``); ``model`` (the pair under load:
``gaps`` the unloaded gap from the generated surfaces, ``grid`` each pair's grid sized from Hertz,
``compliance`` the beveloid compliance operator, ``teeth`` the plate or the FE tooth); ``mechanics``
(independent of gears: ``halfspace``, ``hertz``, ``tooth_compliance``, ``lcp`` + ``kernel`` the
compiled active-set solve, ``checks``); ``results`` (``result`` the result and its JSON, ``batch``,
``pattern`` over the cycle, ``plots``).
"""
from __future__ import annotations

import numpy as np

from .results.batch import Batch
from .model.compliance import BeveloidCompliance
from .options import DEFAULT_GRID, RANGES, Material, Options
from .results.pattern import FlankPattern, flank_pattern
from .results.result import LTCAResult

__all__ = ["Batch", "BeveloidCompliance", "DEFAULT_GRID", "FlankPattern", "LTCAResult", "Material",
           "Options", "RANGES", "analyze", "analyze_many", "flank_pattern"]


def analyze(pair, options: Options, *, solver=None) -> LTCAResult:
    """The loaded TCA of one flank over one mesh cycle: ``analyze(pair_or_geometry, options, *,
    solver=None)`` -> a deep-frozen :class:`LTCAResult` (its JSON: ``result.to_json()``).

    ``pair`` a :class:`beveloid.pair.Pair` (its misalignment and ``[material]`` are used unless
    ``options`` sets them) or a ``PairGeometry``; ``options`` an :class:`Options`
    (``Options.tooth_model`` defaults to the FE tooth); ``solver`` a :class:`beveloid.solver.Solver`
    or None (the default solver).
    """
    from ..solver import Solver
    from .passes.analysis import run

    if not isinstance(options, Options):
        raise TypeError(f"ltca.analyze(pair, options, *, solver=None) needs an ltca.Options, not {type(options).__name__}")
    geom = getattr(pair, "geometry", pair)
    errors = options.errors
    if errors is None:
        errors = getattr(pair, "errors", np.zeros(5))
    material = options.material
    if material is None:
        spec = getattr(pair, "spec", None)
        material = Material.from_spec(spec) if spec is not None else Material()
    return run(geom, errors, options, material, Solver.of(solver), pair=pair)


def analyze_many(pair, options: Options, torques_nm=None, error_sets=None, *, solver=None) -> Batch:
    """N positions x T torques x K error sets of one pair in one call: a :class:`Batch` whose
    ``results[k][t]`` equals ``analyze(pair, options with torque_nm = torques_nm[t] and errors =
    error_sets[k], solver=solver)``.  ``torques_nm`` None: the options' torque; ``error_sets`` (K, 5) None:
    the options' errors (else the pair's misalignment).  ``options.material`` None: the pair's."""
    from ..solver import Solver
    from .passes.analysis import run_many
    from .results.batch import check_error_sets, check_torques

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
    return Batch(torque_nm=torques, errors=errors, results=tuple(tuple(r) for r in results), pair=pair,
                 options=options)
