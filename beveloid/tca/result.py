"""The result of a TCA (deep-frozen, its JSON by ``to_json()``) and analyze()."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import assembly_errors
from ..contact_ellipse import with_ellipses
from ..geometry import PairGeometry
from ..result import Result
from ..solver import Solver
from .backlash import Backlash, backlash
from .contact import ERROR_NAMES, FLANKS, errors_array, geometry_of
from .flank import FlankResult, mesh_flank
from .options import Options
from .reference import pitch_point_notes


@dataclass(frozen=True)
class TCAResult(Result):
    """The TCA of ``pair`` (a Pair or the PairGeometry analysed) under ``options`` (a :class:`tca.Options`):
    per flank its :class:`FlankResult`, the backlash when both flanks are solved, the notes; frozen."""

    geometry: PairGeometry
    errors: np.ndarray
    flanks: dict = field(default_factory=dict)  # flank name -> FlankResult
    backlash: Backlash | None = None
    notes: tuple = ()
    approach_mm: float | None = None  # elastic approach of the contact ellipses, when computed

    @property
    def backlash_um(self):
        return None if self.backlash is None else self.backlash.um

    def to_json(self) -> dict:
        """The JSON of `beveloid tca --json` (docs: beveloid/cli/tca.py)."""
        return _json(self)


def _json(result: TCAResult) -> dict:
    out = {
        "errors": assembly_errors.from_layout(result.errors),
        "flanks": {k: v.to_json() for k, v in result.flanks.items()},
        "te_peak_to_peak_urad": {k: (None if not np.isfinite(v.te_peak_to_peak) else v.te_peak_to_peak * 1e6)
                                 for k, v in result.flanks.items()},
    }
    bl = result.backlash
    if bl is not None:
        out["backlash_um"] = bl.um
        out["backlash_status"] = bl.status
        out["backlash_at_reference_um"] = bl.at_reference_um
        out["backlash_max_um"] = bl.max_um
    if result.approach_mm is not None:
        out["approach_mm"] = result.approach_mm
    out["newton_iterations_mean"] = {k: v.newton_iterations_mean for k, v in result.flanks.items()}
    out["notes"] = list(result.notes)
    if bl is not None and bl.um is None:
        out["notes"].append(f"backlash not measured ({bl.status}): {bl.reason}")
    return out


def _notes(flanks: dict[str, FlankResult], positions):
    if positions > 1:
        return []
    return [f"{fl} flank: TE peak-to-peak not available from one position (it needs several)" for fl in flanks]


def run(pair, errors, options: Options, solver: Solver) -> TCAResult:
    """TCA of ``options.flanks`` of a pair (Pair or PairGeometry) under ``errors`` (5,)."""
    geom = geometry_of(pair)
    e = errors_array(errors)
    flanks, notes = {}, []
    for fl in options.flanks:
        flanks[fl] = mesh_flank(geom, fl, e, positions=options.positions, pairs=options.pairs,
                                window_pitches=options.window_pitches, solver=solver)
        notes += pitch_point_notes(geom, fl, solver.options)
    notes += _notes(flanks, options.positions)
    bl = backlash(geom, e, solver=solver) if set(options.flanks) == set(FLANKS) else None
    result = TCAResult(geom, e, flanks, bl, tuple(notes), pair=pair, options=options)
    return with_ellipses(result, options.approach_mm, solver=solver) if options.approach_mm is not None else result


def analyze(pair, options: Options | None = None, *, solver: Solver | None = None) -> TCAResult:
    """TCA of a pair over the mesh (the backlash when both flanks are solved, the contact ellipses
    at ``options.approach_mm``): ``analyze(pair_or_geometry, Options(...), solver=Solver(...))``.

    ``pair``: a :class:`beveloid.pair.Pair` (its [misalignment] are the errors unless
    ``options.errors`` is set) or a PairGeometry; ``options``: an :class:`Options` (None: the
    default Options); ``solver``: a :class:`beveloid.solver.Solver` (None: the default).
    """
    if options is None:
        options = Options()
    elif not isinstance(options, Options):
        raise TypeError(f"tca.analyze(pair, options, *, solver=None) needs a tca.Options, not {type(options).__name__}")
    errors = options.errors
    if errors is None:
        errors = getattr(pair, "errors", np.zeros(len(ERROR_NAMES)))
    return run(pair, errors, options, Solver.of(solver))
