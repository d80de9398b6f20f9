"""Loaded tooth contact analysis (LTCA) of crossed beveloid gears: approximate by construction
(Boussinesq half-space + thin-slice tooth beams, frictionless, static); the model, its choices and
its limits are in docs/loaded_contact.md.

    from beveloid import ltca
    from beveloid.pair import Pair
    from beveloid.solver import Solver
    pair = Pair.example("case1")
    result = ltca.analyze(pair, ltca.LoadCase(torque_nm=200.0), ltca.Options(flank="left"), solver=Solver())
    tmap = ltca.analyze(pair, ltca.LoadCase(torque_nm=[50, 100, 200]))  # a torque list: a Batch (the map)

``analyze(pair, load, options=None, *, solver=None)``: ``load`` a :class:`LoadCase` (torque(s) and
assembly errors: the load), ``options`` an :class:`Options` (grid, positions, pairs, tooth model,
refinement: how it is computed).  One torque and one error set give an :class:`LTCAResult`; a torque
list or several error sets a :class:`Batch` (``results[k][t]``), as ``analyze_many`` always does:
N positions x T torques x K error sets in one call, the one engine of both.

Its modules and folders, from the request down: ``load`` (the load case), ``options`` (how it is
computed: the range table), ``studies`` (the torque map and the tolerance box under load); ``passes`` (the
passes over the positions of a mesh cycle: ``analysis``, ``cycle``); ``model`` (the pair under load:
``gaps`` the unloaded gap from the generated surfaces, ``grid`` each pair's grid sized from Hertz,
``compliance`` the beveloid compliance operator, ``teeth`` the plate or the FE tooth); ``mechanics``
(independent of gears: ``halfspace``, ``hertz``, ``tooth_compliance``, ``lcp`` + ``kernel`` the
compiled active-set solve, ``checks``); ``results`` (``result`` the result and its JSON, ``batch``,
``pattern`` over the cycle, ``plots``).
"""
from __future__ import annotations

import numpy as np

from . import studies
from .load import LoadCase
from .options import DEFAULT_GRID, RANGES, Material, Options
from .results.batch import Batch

__all__ = ["Batch", "BeveloidCompliance", "DEFAULT_GRID", "FlankPattern", "LTCAResult", "LoadCase", "Material",
           "Options", "RANGES", "analyze", "analyze_many", "flank_pattern", "studies"]


def __getattr__(name):
    """``BeveloidCompliance``, ``LTCAResult``, ``FlankPattern`` and ``flank_pattern``, imported on first use: a
    process that only asks for a load case, options or the tolerance box's tasks (``beveloid ltca --samples``'s
    own process, whose workers analyse) imports no compliance operator, Hertz sizing or
    contact model (issue 59: the serial part of each parallel command)."""
    if name == "BeveloidCompliance":
        from .model import compliance as module
    elif name == "LTCAResult":
        from .results import result as module
    elif name in ("FlankPattern", "flank_pattern"):
        from .results import pattern as module
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(module, name)


def _checked(pair, load, options, caller):
    if not isinstance(load, LoadCase):
        raise TypeError(f"ltca.{caller}(pair, load, options=None, *, solver=None) needs an ltca.LoadCase as load, "
                        f"not {type(load).__name__}")
    if options is None:
        options = Options()
    if not isinstance(options, Options):
        raise TypeError(f"ltca.{caller}(pair, load, options=None, *, solver=None) needs an ltca.Options or None as "
                        f"options, not {type(options).__name__}")
    return options


def _material(pair, options):
    if options.material is not None:
        return options.material
    spec = getattr(pair, "spec", None)
    return Material.from_spec(spec) if spec is not None else Material()


def analyze(pair, load: LoadCase, options: Options | None = None, *, solver=None):
    """The loaded TCA of one flank over one mesh cycle: ``analyze(pair, load, options=None, *,
    solver=None)`` -> a deep-frozen :class:`LTCAResult` (its JSON: ``result.to_json()``), or a :class:`Batch` when ``load`` holds a
    torque list or several error sets (``load.is_map``; :func:`analyze_many`).

    ``pair`` a :class:`beveloid.pair.Pair` (its misalignment and ``[material]`` are used unless
    ``load`` / ``options`` set them) or a ``PairGeometry``; ``load`` a :class:`LoadCase`; ``options``
    an :class:`Options` or None (the defaults; ``Options.tooth_model`` defaults to the FE tooth);
    ``solver`` a :class:`beveloid.solver.Solver` or None (the default solver).
    """
    options = _checked(pair, load, options, "analyze")
    if load.is_map:
        return analyze_many(pair, load, options, solver=solver)
    from ..solver import Solver
    from .passes.analysis import run

    geom = getattr(pair, "geometry", pair)
    return run(geom, load.error_sets(pair)[0], load.torque_nm, options, _material(pair, options), Solver.of(solver),
               pair=pair)


def analyze_many(pair, load: LoadCase, options: Options | None = None, *, solver=None, convergence=True,
                 along_face=True, compression=True, extra=()) -> Batch:
    """N positions x T torques x K error sets of one pair in one call: a :class:`Batch` whose
    ``results[k][t]`` equals ``analyze(pair, LoadCase(load.torques_nm[t], errors=error set k), options,
    solver=solver)``; the error sets are ``load.errors`` (one set or a list), else the pair's misalignment.
    ``convergence=False``: the grid-convergence indicator (a once-coarsened grid solved again, about a tenth of
    an analysis) is not computed, every other number the same to the last bit; each result's ``convergence``
    is nan (not computed), as the tolerance box and optimize use it (they report none of it).
    ``along_face=False``: no result's ``root_stress_along_face`` (the FE tooth's fillet along the face at the
    largest root stress, read only by the plots of one analysis) is computed (each is empty), every other
    number the same to the last bit.  ``compression=False``: no result's ``pair_root_compressive_stress_mpa``
    (the FE tooth's other fillet's compressive extreme, read only by one analysis's JSON) is sought (each is
    empty), every other number the same to the last bit.  ``extra``: more cases, (error set (5,), torque N m)
    each, analysed in the same call after the load's (one set-up, the same waves: optimize's candidate adds
    its rating's LTCA to its tolerance box), their results in ``Batch.extra``; each result is that case's
    own, to the last bit, whatever it is analysed with."""
    from ..solver import Solver
    from .passes.analysis import run_many

    options = _checked(pair, load, options, "analyze_many")
    torques = np.array(load.torques_nm, dtype=float)
    errors = load.error_sets(pair)
    geom = getattr(pair, "geometry", pair)
    leave_out = tuple(k for k, kept in (("convergence", convergence), ("along_face", along_face),
                                        ("compression", compression)) if not kept)
    from .results.batch import check_error_sets

    extra = [(check_error_sets(e, "extra")[0], float(t)) for e, t in extra]
    results = run_many(geom, list(errors) + [e for e, _ in extra], [list(torques)] * len(errors) + [[t] for _, t in extra],
                       options, _material(pair, options), Solver.of(solver), pair=pair, leave_out=leave_out)
    return Batch(torque_nm=torques, errors=errors, results=tuple(tuple(r) for r in results[:len(errors)]), pair=pair,
                 options=options, extra=tuple(r[0] for r in results[len(errors):]))
