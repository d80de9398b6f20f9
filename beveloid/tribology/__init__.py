"""Tribology of the loaded contact: sliding and sum velocities, EHL film, friction, mesh power loss,
efficiency and flash-temperature scuffing, on every contact cell of a loaded analysis
(docs/tribology.md: the model, each formula's source and the checks).

    from beveloid import ltca, tribology
    result = ltca.analyze(pair, ltca.LoadCase(200.0))
    tri = tribology.evaluate(result, pair, speed_rpm=1500.0)       # the pair's [lubricant]
    tri.mesh_power_loss_w, tri.efficiency, tri.scuffing_safety

``efficiency_map(results, pair, speeds_rpm)``: every LTCA result (one per torque) at every speed; the
contact is solved once per torque (the kinematics scales with the speed).

Modules: ``lubricant`` (the oil), ``cells`` (the speed-independent cell data, with the generated
contact kinematics), ``laws`` (the formulas), ``analysis`` (one speed), ``result``, ``plots``.
"""
from __future__ import annotations

import numpy as np

from ..result import freeze
from .lubricant import Lubricant, LubricantError
from .result import TribologyResult

__all__ = ["Cells", "Lubricant", "LubricantError", "PitchPoint", "TribologyResult", "evaluate", "efficiency_map",
           "Prepared", "prepare"]


def __getattr__(name):
    """The names of ``cells`` and ``analysis`` (``Cells``, ``build``; ``PitchPoint``, ``pitch_point``,
    ``evaluate_cells``), imported on first use: the spec's check of a lubricant (``tribology.lubricant``,
    every command) then imports no more of the tribology (nor the LTCA it needs)."""
    if name in ("Cells", "build"):
        from . import cells as module
    elif name in ("PitchPoint", "pitch_point", "evaluate_cells"):
        from . import analysis as module
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(module, name)


class Prepared:
    """One LTCA result's speed-independent tribology data: evaluate it at any speed (:meth:`at`)."""

    def __init__(self, result, pair, lubricant=None, roughness_ra_um=None, errors=None, e_star_mpa=None):
        spec = getattr(pair, "spec", None)
        geom = getattr(pair, "geometry", pair)
        if lubricant is None:
            if spec is None or not spec.lubricant.given:
                raise LubricantError("lubricant: missing; the tribology needs a [lubricant] section (an oil)",
                                     key="lubricant")
            lubricant = Lubricant.from_spec(spec.lubricant)
        if roughness_ra_um is None:
            roughness_ra_um = (spec.pinion.roughness_ra_um, spec.gear.roughness_ra_um) if spec is not None else None
        if roughness_ra_um is None or any(r is None for r in roughness_ra_um):
            raise LubricantError("pinion.roughness_ra_um: missing; the tribology needs both members' roughness",
                                 key="pinion.roughness_ra_um")
        if errors is None:
            errors = getattr(pair, "errors", np.zeros(5))
        if e_star_mpa is None:
            from ..ltca.options import Material

            e_star_mpa = (Material.from_spec(spec) if spec is not None else Material()).e_star_mpa
        from .analysis import pitch_point
        from .cells import build

        self.result, self.geom, self.lubricant = result, geom, lubricant
        self.roughness_ra_um = tuple(float(r) for r in roughness_ra_um)
        self.e_star_mpa = float(e_star_mpa)
        self.cells = freeze(build(result, geom, errors, self.e_star_mpa))  # once: every speed's result shares it
        self.pair = pair
        self.pitch = pitch_point(geom, result.flank)

    def at(self, speed_rpm) -> TribologyResult:
        from .analysis import evaluate_cells

        return evaluate_cells(self.cells, self.result, self.pitch, self.lubricant, speed_rpm, self.roughness_ra_um,
                              self.e_star_mpa, pair=self.pair)


def prepare(result, pair, **kw) -> Prepared:
    return Prepared(result, pair, **kw)


def evaluate(result, pair, speed_rpm, **kw) -> TribologyResult:
    """The tribology of an :class:`beveloid.ltca.LTCAResult` of ``pair`` (a Pair: its [lubricant],
    roughness, misalignment and material; or a PairGeometry with ``lubricant=``, ``roughness_ra_um=``)
    at the pinion speed ``speed_rpm``."""
    return Prepared(result, pair, **kw).at(speed_rpm)


def efficiency_map(results, pair, speeds_rpm, **kw) -> list:
    """``[[TribologyResult at speed s for s in speeds_rpm] for result in results]``: one LTCA result per
    torque, each prepared once and evaluated at every speed (no contact solved again)."""
    out = []
    for r in results:
        prep = Prepared(r, pair, **kw)
        out.append([prep.at(s) for s in speeds_rpm])
    return out
