"""The LTCA's result (a deep-frozen :class:`beveloid.result.Result`) and its JSON."""
from __future__ import annotations

import math
import typing
from dataclasses import dataclass, field, replace

import numpy as np

from ...result import Result
from ...status import LoadedStatus
from ..model.gaps import PairGap
from ..model.grid import PairGrid, centres

#: tolerances of the grid-convergence indicator (change against the once-coarsened grid)
PRESSURE_CHANGE_TOL = 0.05  #: of a pair's surface peak pressure
LOAD_CHANGE_TOL = 0.01  #: of the total normal load, for any pair
#: the model's validity: linear elasticity and small strain
MAX_PRESSURE_OVER_E_STAR = 0.025  #: peak pressure / E* (2830 MPa for steel: beyond it gear steels yield)
MAX_HALF_WIDTH_TIMES_CURVATURE = 0.1  #: patch semi-axis across x relative curvature across (small strain)
#: between the reasons of one position's ``validity``
VALIDITY_SEPARATOR = "; "


class Convergence(typing.NamedTuple):
    """Per position: the largest relative change of a pair's surface peak pressure and of a pair's
    load (share of the total) when the grid is once coarsened; nan where not computed."""

    pressure_change: np.ndarray  # (N,)
    load_change: np.ndarray  # (N,)

    def converged(self) -> np.ndarray:
        with np.errstate(invalid="ignore"):
            return ~((self.pressure_change > PRESSURE_CHANGE_TOL) | (self.load_change > LOAD_CHANGE_TOL))


@dataclass(frozen=True)
class LTCAResult(Result):
    """Loaded TCA of one flank over a mesh cycle (positions N, tooth pairs P) of ``pair`` under ``options``;
    deep-frozen.  The loaded contact patterns are computed on demand (:meth:`pattern`: they cost several
    times the plate LTCA), or once into a new result by :meth:`with_patterns`."""

    flank: str
    torque_nm: float
    pinion_angle: np.ndarray  # (N,) rad
    tooth_pairs: np.ndarray  # (P,)
    status: tuple  # (N,) LoadedStatus
    loaded_te: np.ndarray  # (N,) rad, nan where not ok
    unloaded_te: np.ndarray  # (N,) rad: the rigid TE envelope
    pair_load_n: np.ndarray  # (N, P) normal force of each pair, nan where not ok
    pair_max_pressure_mpa: np.ndarray  # (N, P) the largest cell pressure (surface or edge)
    pair_surface_max_pressure_mpa: np.ndarray  # (N, P) over the cells away from the flank edges; nan if none
    pair_edge_max_pressure_mpa: np.ndarray  # (N, P) over the cells at a flank edge (grid-dependent); nan if none
    pair_hertz_max_pressure_mpa: np.ndarray  # (N, P) Hertz for the pair's load and its tangency's curvature
    contact_area_mm2: np.ndarray  # (N,)
    pinion_moment_nmm: np.ndarray  # (N,) moment of the contact forces about the pinion axis
    iterations: np.ndarray  # (N,)
    complementarity_residual: np.ndarray  # (N,)
    load_residual: np.ndarray  # (N,)
    grid: PairGrid  # cell counts and each (position, pair)'s half-extents
    convergence: Convergence
    validity: tuple  # (N,) None within the model's validity, else why not
    pressure_mpa: np.ndarray  # (N, P, cells)
    gap: PairGap
    axes: np.ndarray  # (N, P, 2, 3) across/along in S_1
    tangency_unknowns: np.ndarray  # (N, P, 5) each pair's rigid-body tangency (tca_kernels.UNKNOWNS)
    pair_pinion_angle: np.ndarray  # (N, P) the pinion angle of each pair's tangency (pair 0 frame)
    notes: tuple = ()
    #: how the teeth bent: "fe" (beveloid.fe, mesh refinement ``fe_refinement``, sizes times
    #: ``fe_coarsen``) or "plate"
    tooth_model: str = "plate"
    fe_refinement: int | None = None
    fe_coarsen: float | None = None
    #: {member: (N, P)} the largest max-principal (tensile) stress in the loaded side's root fillet
    #: of each pair's tooth (MPa), nan where not ok; empty with the plate (it has no fillet)
    pair_root_stress_mpa: dict = field(default_factory=dict)
    #: {member: (N, P)} the most compressive min-principal stress in the other fillet (MPa, < 0)
    pair_root_compressive_stress_mpa: dict = field(default_factory=dict)
    #: {member: (N, P, 2)} where the tensile peak is: (z_mm member frame, height above the root cone mm)
    pair_root_stress_where: dict = field(default_factory=dict)
    #: {member: (z_mm (nb,), stress_mpa (nb,))} the loaded fillet's max principal stress along the face
    #: of the (position, pair) with the largest root stress
    root_stress_along_face: dict = field(default_factory=dict)
    #: (N,) the sum of the pair loads over the approach of the teeth along the normal (N/um)
    mesh_stiffness_n_per_um: np.ndarray | None = None
    #: {member: FlankPattern} at the default raster, when computed (:meth:`with_patterns`); empty otherwise
    patterns: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def converged(self) -> np.ndarray:
        return np.asarray([s == LoadedStatus.OK for s in self.status])

    @property
    def cell_area_mm2(self) -> np.ndarray:
        """(N, P) the area of one cell of each pair's grid."""
        return self.grid.cell_area_mm2()

    @property
    def across_half_mm(self) -> float:
        """The largest grid half-extent across the contact line (mm)."""
        return float(np.max(self.grid.across_half_mm))

    @property
    def along_half_mm(self) -> float:
        return float(np.max(self.grid.along_half_mm))

    @property
    def loaded_te_peak_to_peak(self) -> float:
        """rad; nan with fewer than 3 converged positions (a peak-to-peak needs a cycle)."""
        te = self.loaded_te[self.converged]
        return float(te.max() - te.min()) if te.size >= 3 else math.nan

    def cell_coordinates_mm(self, j, k):
        """(across, along) centres (nx, ny) of pair k's cells at position j in its tangent plane."""
        g = self.grid
        x = centres(g.across_half_mm[j, k], g.across_cells)[:, None] + self.gap.across_shift_mm[j, k][None, :]
        return x, np.broadcast_to(centres(g.along_half_mm[j, k], g.along_cells)[None, :], x.shape)

    def patch_semi_axes_mm(self):
        """(N, P, 2): each pair's loaded patch, (across, along) semi-axes sqrt(5 <x^2>) from the
        pressure's second moments about its centroid (exact for a Hertz ellipse aligned with the
        grid); nan for an unloaded pair or a position that did not converge."""
        N, P = self.pair_load_n.shape
        out = np.full((N, P, 2), np.nan)
        nx, ny = self.grid.across_cells, self.grid.along_cells
        for j in range(N):
            for k in range(P):
                p = self.pressure_mpa[j, k].reshape(nx, ny)
                if not self.converged[j] or p.sum() <= 0:
                    continue
                x, y = self.cell_coordinates_mm(j, k)
                w = p / p.sum()
                out[j, k] = [math.sqrt(5 * (w * (x - (w * x).sum()) ** 2).sum()),
                             math.sqrt(5 * (w * (y - (w * y).sum()) ** 2).sum())]
        return out

    def pattern(self, member, raster=None):
        """:func:`beveloid.ltca.results.pattern.flank_pattern` of one member on the analysed pair's flank: the one
        :meth:`with_patterns` stored (default raster), else computed now (not kept: the result is frozen)."""
        from .pattern import RASTER, flank_pattern

        raster = tuple(raster or RASTER)
        if raster == RASTER and member in self.patterns:
            return self.patterns[member]
        with np.errstate(all="ignore"):
            return flank_pattern(self, self.geometry_of_pair, member, raster)

    def with_patterns(self, rasters=None) -> "LTCAResult":
        """A new result carrying both members' loaded contact patterns (default raster), so that the JSON,
        the tables and the figures of one run compute them once; this result is not changed.  ``rasters``: a
        dict shared by the results of one pair (their flank rasters made once: ``pattern.flank_pattern``)."""
        from .pattern import flank_patterns

        if all(m in self.patterns for m in ("pinion", "gear")):
            return self
        with np.errstate(all="ignore"):  # (as pattern()); both members' fields share their grid parts
            return replace(self, patterns=flank_patterns(self, self.geometry_of_pair, rasters=rasters))

    def root_stress_max_mpa(self) -> dict:
        """{member: the largest pair_root_stress_mpa over the cycle (MPa) or None}."""
        out = {}
        for m, a in self.pair_root_stress_mpa.items():
            out[m] = float(np.nanmax(a)) if np.isfinite(a).any() else None
        return out

    def root_stress_location(self) -> dict:
        """{member: {"position", "pair", "z_mm", "height_mm", "flank"} of the largest root stress, or None}."""
        out = {}
        for m, a in self.pair_root_stress_mpa.items():
            if not np.isfinite(a).any():
                out[m] = None
                continue
            j, k = np.unravel_index(int(np.nanargmax(a)), a.shape)
            z, h = self.pair_root_stress_where[m][j, k]
            known = lambda v: float(v) if np.isfinite(v) else None  # noqa: E731
            out[m] = {"position": int(j), "pair": int(self.tooth_pairs[k]), "z_mm": known(z), "height_mm": known(h),
                      "flank": self.flank}
        return out

    def to_json(self) -> dict:
        """The JSON of ``beveloid ltca`` (the contract: README and cli/ltca.py); the bearing patterns' area
        fractions from :meth:`pattern`."""
        return _json(self)

    def warnings(self) -> list:
        """One line per problem a reader must know: grid not converged, outside the model's validity."""
        out = []
        conv = self.convergence.converged() | ~self.converged
        if not conv.all():
            bad = np.flatnonzero(~conv)
            changes = []
            for what, a, tol in (("peak pressure", self.convergence.pressure_change, PRESSURE_CHANGE_TOL),
                                 ("pair load", self.convergence.load_change, LOAD_CHANGE_TOL)):
                if np.isfinite(a[bad]).any():
                    changes.append(f"{what} change up to {np.nanmax(a[bad]) * 100:.1f} % (tolerance {tol * 100:g} %)")
                else:  # an edge peak is not compared (grid-dependent by nature), nor a pair that lost contact
                    changes.append(f"{what} not compared there")
            out.append(f"grid not converged at {bad.size} of {len(self.status)} positions ({', '.join(changes)}, against"
                       " a once-coarsened grid): use a finer --grid")
        reasons = sorted({why for v in self.validity if v for why in v.split(VALIDITY_SEPARATOR)})  # each once
        if reasons:
            n = sum(1 for v in self.validity if v)
            out.append(f"{n} of {len(self.status)} positions leave the model's validity (linear elastic, small "
                       f"strain): {'; '.join(reasons)}")
        if np.isfinite(self.pair_edge_max_pressure_mpa).any():
            out.append("edge contact: the edge peak pressure is grid-dependent (a sharp flank edge is singular); "
                       "loads and TE converge")
        return out


def _tooth_json(r: LTCAResult, num) -> dict:
    """The tooth model's keys (issue 31): root stress (FE only) and mesh stiffness."""
    ok = r.converged
    rows = lambda a: [[num(v, o) for v in row] for row, o in zip(a, ok)]  # noqa: E731
    fe = r.tooth_model == "fe"
    stiff = r.mesh_stiffness_n_per_um
    return {
        "tooth_model": r.tooth_model,
        "fe_refinement": r.fe_refinement if fe else None,
        "fe_coarsen": r.fe_coarsen if fe else None,
        "pair_root_stress_mpa": {m: rows(a) for m, a in r.pair_root_stress_mpa.items()} if fe else None,
        "pair_root_compressive_stress_mpa": ({m: rows(a) for m, a in r.pair_root_compressive_stress_mpa.items()}
                                             if fe else None),
        "root_stress_max_mpa": r.root_stress_max_mpa() if fe else None,
        "root_stress_location": r.root_stress_location() if fe else None,
        "root_stress_note": ("maximum principal stress in the root fillet of the loaded side (tension) and minimum "
                             "principal stress in the other fillet, from the FE tooth's influence data superposed "
                             "over the LTCA pressure (docs/loaded_contact.md); z_mm in the member's frame, "
                             "height_mm above the root cone" if fe else
                             "not computed: the plate tooth has no root fillet (use --tooth-model fe)"),
        "mesh_stiffness_n_per_um": (None if stiff is None else [num(v, o) for v, o in zip(stiff, ok)]),
        "mesh_stiffness_note": "sum of the pair normal loads over the approach of the teeth along the contact "
                               "normal (the loaded TE's displacement at the contact), per position",
        "mesh_stiffness_mean_n_per_um": num(_stiffness(r)[0]),
        "mesh_stiffness_peak_to_peak_n_per_um": num(_stiffness(r)[1]),
        "loaded_contact_ratio": num(_loaded_contact_ratio(r)),
        "loaded_contact_ratio_note": "mean number of tooth pairs carrying load over the cycle's distinct converged "
                                     "positions (resolution 1 / (positions - 1)); the unloaded one of the unmodified "
                                     "flanks: `beveloid design`",
    }


def _loaded_contact_ratio(r) -> float:
    from .batch import loaded_contact_ratio

    return loaded_contact_ratio(r)


def _stiffness(r) -> tuple:
    """(mean, peak-to-peak) of the converged positions' mesh stiffness (N/um); nan where unknown (the
    peak-to-peak: fewer than 3 positions)."""
    from .batch import summary

    s = summary(r)
    return s["mesh_stiffness_mean_n_per_um"], s["mesh_stiffness_peak_to_peak_n_per_um"]


def _harmonics_json(r, geom, num) -> dict:
    from .batch import MESH_ORDERS, gear_base_radius_mm, te_harmonics

    h = te_harmonics(r)
    rb = gear_base_radius_mm(geom)
    return {"te_harmonics_urad": [num(v * 1e6) for v in h],
            "te_harmonics_um": [num(v * rb * 1e3) for v in h],
            "te_harmonics_mesh_orders": list(MESH_ORDERS),
            "te_harmonics_note": "amplitudes of mesh orders 1-6 of the loaded TE over one mesh cycle (the "
                                 "positions span exactly one cycle, the repeated end point counted once): gear "
                                 "rotation (urad) and along the line of action (um, times the gear's base radius "
                                 f"{rb:.3f} mm); null when a position did not converge or an order reaches half "
                                 "the samples"}


def _json(result: LTCAResult) -> dict:
    r = result
    geom = r.geometry_of_pair
    ok = r.converged
    num = lambda v, ok_=True: float(v) if ok_ and v is not None and np.isfinite(v) else None  # noqa: E731
    rows = lambda a: [[num(v, o) for v in row] for row, o in zip(a, ok)]  # noqa: E731
    fractions = {m: r.pattern(m).area_fraction for m in ("pinion", "gear")}
    ptp = r.loaded_te_peak_to_peak
    return {
        "flank": r.flank,
        "torque_nm": r.torque_nm,
        "torque_note": "pinion torque; the moment of the contact forces about the pinion axis equals it",
        "pinion_angle_rad": [float(v) for v in r.pinion_angle],
        "status": list(r.status),
        "loaded_transmission_error_urad": [num(v * 1e6, o) for v, o in zip(r.loaded_te, ok)],
        "unloaded_transmission_error_urad": [num(v * 1e6) for v in r.unloaded_te],
        "loaded_transmission_error_peak_to_peak_urad": num(ptp * 1e6),
        "statistics_note": None if np.isfinite(ptp) else "not available: a peak-to-peak needs 3 or more converged "
                                                          "positions",
        "tooth_pairs": [int(k) for k in r.tooth_pairs],
        "pair_normal_load_n": rows(r.pair_load_n),
        "pair_max_pressure_mpa": rows(r.pair_max_pressure_mpa),
        "pair_surface_max_pressure_mpa": rows(r.pair_surface_max_pressure_mpa),
        "pair_edge_max_pressure_mpa": rows(r.pair_edge_max_pressure_mpa),
        "pair_hertz_max_pressure_mpa": rows(r.pair_hertz_max_pressure_mpa),
        "hertz_note": "Hertz (half-space only) for each pair's load and the relative curvature at its rigid "
                      "tangency; the LTCA's surface peak departs from it near the flank edges and where the "
                      "tooth beams bend under a patch as long as the tooth is high: within 5 % where the "
                      "patch's semi-axis along the contact (pair_patch_semi_axes_mm[.][.][1]) is under half "
                      "the tooth height (tooth_height_mm), lower beyond (docs/loaded_contact.md 5.1)",
        "tooth_height_mm": {m: float(geom.member(m).tip_height_mm + geom.member(m).cutter_addendum_mm)
                            for m in ("pinion", "gear")},
        "edge_pressure_note": "at a flank edge (tip, form limit, toe, heel): grid-dependent, grows with refinement",
        "contact_area_mm2": [num(v, o) for v, o in zip(r.contact_area_mm2, ok)],
        "pair_patch_semi_axes_mm": [[None if not np.all(np.isfinite(ab)) else [float(ab[0]), float(ab[1])]
                                     for ab in row] for row in r.patch_semi_axes_mm()],
        "pattern_area_fraction": {m: (None if f is None else float(f)) for m, f in fractions.items()},
        "grid": {"across_cells": r.grid.across_cells, "along_cells": r.grid.along_cells,
                 "across_half_extent_mm": r.across_half_mm, "along_half_extent_mm": r.along_half_mm,
                 "pair_across_half_extent_mm": [[float(v) for v in row] for row in r.grid.across_half_mm],
                 "pair_along_half_extent_mm": [[float(v) for v in row] for row in r.grid.along_half_mm],
                 "rule": "cells sized from each pair's Hertz semi-axes at its load (docs/loaded_contact.md)"},
        "grid_convergence": {
            "pressure_change": [num(v, o) for v, o in zip(r.convergence.pressure_change, ok)],
            "load_change": [num(v, o) for v, o in zip(r.convergence.load_change, ok)],
            "converged": [bool(c) if o else None for c, o in zip(r.convergence.converged(), ok)],
            "pressure_tolerance": PRESSURE_CHANGE_TOL, "load_tolerance": LOAD_CHANGE_TOL,
            "note": "largest change of a pair's surface peak pressure and of a pair's load share against the "
                    "same grids once coarsened"},
        "validity": {"within": not any(r.validity), "positions": list(r.validity),
                     "model": "linear elastic, small strain, frictionless, static"},
        "solver": {"iterations": [int(v) for v in r.iterations],
                   "complementarity_residual": [num(v) for v in r.complementarity_residual],
                   "load_residual": [num(v) for v in r.load_residual],
                   "moment_residual": [num(abs(m / (r.torque_nm * 1e3) - 1.0), o)
                                       for m, o in zip(r.pinion_moment_nmm, ok)]},
        **_tooth_json(r, num),
        **_harmonics_json(r, geom, num),
        "warnings": r.warnings(),
        "notes": list(r.notes),
    }
