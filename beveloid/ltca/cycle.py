"""One mesh cycle of the LTCA: the rigid-body reference of every (position, pair) and the
contact problem of every position.

At each of N pinion positions over one mesh cycle (one pinion pitch, as
``tca.mesh_flank(..., window_pitches=1)``) one :func:`lcp.solve_contact` holds all pairs as
diagonal blocks sharing one rigid gear rotation:

    g_i = h_i - delta w_i + (C p)_i >= 0,   p_i >= 0,   p_i g_i = 0,   sum a_i t_i p_i = T1 / r1

w_i: closure of cell i per rad of gear rotation / r2, t_i: moment arm of cell i about the pinion
axis / r1; the load condition is the moment of the contact forces about the pinion axis = T1.
"""
from __future__ import annotations

import math
import typing

import numpy as np

from .. import tca
from . import gaps, lcp
from .compliance import BeveloidCompliance, halfspace_matrix, pair_tooth_compliance


class Setup:
    """Everything of one (geometry, flank, errors, positions, pairs) that does not depend on the grid."""

    def __init__(self, geom, flank, errors, positions, pairs, solver):
        self.geom, self.flank, self.solver = geom, flank, solver
        self.errors = tca.errors_array(errors)
        fr = tca.mesh_flank(geom, flank, self.errors, positions=positions, pairs=pairs, window_pitches=1,
                            backend=solver.backend)
        ref = tca.reference_contact(geom, flank)
        self.reference = ref
        ref_gear = tca.unknowns(ref.x).gear_angle_rad
        p1, p2 = geom.pitch_angles
        n1, n2 = geom.pinion.teeth, geom.gear.teeth
        self.n1_over_n2 = n1 / n2
        self.ks = np.arange(pairs) - pairs // 2
        self.phi1 = fr.pinion_angle[:positions]
        x = fr.unknowns.reshape(pairs, positions, 5).transpose(1, 0, 2)  # (N, P, 5) pair 0 unknowns
        status = np.asarray(fr.status, dtype=object).reshape(pairs, positions).T
        self.solved = np.array([[s != "failed" for s in row] for row in status], dtype=bool)
        # a tangency the rigid TCA did not solve between two solved positions of the same pair: the
        # interpolation of its neighbours places that pair's grid (the gap itself is measured on the
        # true surfaces), so a loaded pair never drops out of one position
        x, self.interpolated = _fill_between(x, self.phi1, self.solved)
        self.solved |= self.interpolated
        # the tangency lies on both flanks: its patch is a surface contact
        self.on_flank = np.array([[s in ("ok", "edge") for s in row] for row in status], dtype=bool)
        te = fr.transmission_error.reshape(pairs, positions).T
        active = fr.active.reshape(pairs, positions).T
        self.unloaded_te = np.array([te[j][active[j]][0] if active[j].any() else np.nan for j in range(positions)])
        # each pair's own rigid TE (its tangency, on or off the flanks): how far it stands open
        self.pair_te = np.where(self.solved, tca.unknowns(x).gear_angle_rad - self.ks[None, :] * p2 - ref_gear
                                + self.n1_over_n2 * (self.phi1[:, None] - ref.pinion_angle), np.nan)
        # the gear angle of the rigid envelope (the first pair to touch), else of the nearest solved pair
        with np.errstate(invalid="ignore"):
            nearest = np.array([self.pair_te[j, np.argmin(np.where(self.solved[j], np.abs(self.ks), 99))]
                                if self.solved[j].any() else np.nan for j in range(positions)])
        self.te_any = np.where(np.isfinite(self.unloaded_te), self.unloaded_te, nearest)
        self.has_reference = np.isfinite(self.te_any)
        self.gear_angle = self.te_any + ref_gear - self.n1_over_n2 * (self.phi1 - ref.pinion_angle)
        # pair k: pinion tooth 0 at phi1 - k p1, gear tooth 0 at phi2 + k p2 (tca.mesh_flank)
        self.pair_phi1 = self.phi1[:, None] - self.ks[None, :] * p1
        self.pair_phi2 = self.gear_angle[:, None] + self.ks[None, :] * p2
        # a finite placeholder where unsolved (never gridded): a solved tangency, else the reference
        spare = x[self.solved][0] if self.solved.any() else ref.x
        x = np.where(self.solved[..., None], x, spare)
        self.x = x
        self.start = np.concatenate([x[..., :4], np.where(np.isfinite(self.pair_phi2), self.pair_phi2,
                                                          x[..., 4])[..., None]], axis=-1)
        self.frame = gaps.principal_frame(geom, flank, x, self.pair_phi1, self.errors)
        self.solved &= np.isfinite(self.frame.axes).all(axis=(-1, -2))
        mn = geom.normal_module_mm
        depth = (geom.pinion.tip_height_mm + geom.pinion.cutter_addendum_mm) / math.cos(geom.normal_pressure_angle)
        face = geom.pinion.face_width_mm / max(math.cos(geom.pinion.helix_angle), 0.3)
        self.max_along_mm = math.hypot(depth, face) + mn
        self.gear_sign, self.pinion_sign = self._signs()

    def _signs(self):
        """(gear sign, pinion sign): -1 if the gap closes under +phi'_2, +1 if the moment arm is positive."""
        ok = self.solved & self.has_reference[:, None]
        if not ok.any():
            return 1.0, 1.0
        jj, kk = np.nonzero(ok)
        frames = gaps.Frames(self.start[jj, kk], self.pair_phi1[jj, kk], self.frame.origin[jj, kk],
                             self.frame.axes[jj, kk])
        cg = gaps.cell_gaps(self.geom, self.flank, self.errors, frames, np.zeros((jj.size, 1, 2)), self.solver)
        on = cg.on_flanks[:, 0] if cg.on_flanks.any() else np.isfinite(cg.gap_mm[:, 0])
        if not on.any():
            return 1.0, 1.0
        return (-1.0 if np.median(cg.gap_D_gear_angle[on, 0]) > 0 else 1.0,
                1.0 if np.median(cg.pinion_arm_mm[on, 0]) > 0 else -1.0)

    def full_load_n(self, torque_nm):
        """(N, P) the normal force of a pair carrying the whole torque at its tangency."""
        return torque_nm * 1e3 / np.maximum(self.frame.pinion_arm_mm, 1e-9)

    def open_pairs(self, rotation_rad):
        """(N, P) pairs standing open by more than 3x the loaded rotation (+2 urad): they cannot touch."""
        bound = 3.0 * np.abs(rotation_rad) + 2e-6
        with np.errstate(invalid="ignore"):
            return np.abs(self.pair_te - self.te_any[:, None]) > np.where(np.isfinite(bound), bound, np.inf)[:, None]


def _fill_between(x, phi1, solved):
    """x (N, P, 5) with each pair's unsolved positions that lie between two solved ones linearly
    interpolated in the pinion angle; and the mask of those positions."""
    x = x.copy()
    filled = np.zeros_like(solved)
    for k in range(solved.shape[1]):
        ok = np.flatnonzero(solved[:, k])
        if ok.size < 2:
            continue
        gap = np.flatnonzero(~solved[:, k])
        gap = gap[(gap > ok[0]) & (gap < ok[-1])]
        for i in range(x.shape[-1]):
            x[gap, k, i] = np.interp(phi1[gap], phi1[ok], x[ok, k, i])
        filled[gap, k] = True
    return x, filled


class Solution(typing.NamedTuple):
    """The contact problem of every position on one grid."""

    grid: typing.Any  # grid.PairGrid
    gap: gaps.PairGap
    pressure_mpa: np.ndarray  # (N, P, cells)
    converged: np.ndarray  # (N,)
    no_contact: np.ndarray  # (N,)
    rotation_rad: np.ndarray  # (N,) the rigid gear rotation delta / r2
    approach_mm: np.ndarray  # (N,) delta: the teeth's approach along the contact normal
    iterations: np.ndarray
    complementarity_residual: np.ndarray
    load_residual: np.ndarray

    def pair_load_n(self):
        return self.pressure_mpa.sum(axis=-1) * self.grid.cell_area_mm2()


def solve(setup: Setup, grid, need, torque_nm, e_star_mpa, teeth, positions=None) -> Solution:
    """Solve ``positions`` (default all) on ``grid``; only the pairs in ``need`` (N, P) are gridded."""
    N, P = need.shape
    nx, ny = grid.across_cells, grid.along_cells
    todo = np.zeros(N, dtype=bool)
    todo[list(range(N)) if positions is None else list(positions)] = True
    need = need & todo[:, None] & setup.solved & setup.has_reference[:, None]
    gap = gaps.grid_gaps(setup, grid, need, setup.solver)
    area = grid.cell_area_mm2()
    line = np.arange(nx * ny) % ny  # along index of each cell
    centre = (nx // 2) * ny + np.arange(ny)  # the cells on the grid's along-axis
    out = dict(p=np.zeros((N, P, nx * ny)), ok=np.zeros(N, bool), none=np.zeros(N, bool),
               delta=np.full(N, np.nan), approach=np.full(N, np.nan), it=np.zeros(N, int), comp=np.full(N, np.nan), load=np.full(N, np.nan))
    for j in np.flatnonzero(todo):
        inside = gap.in_flank[j]
        if not inside.any():
            out["none"][j] = True
            continue
        r1 = float(np.median(gap.pinion_arm_mm[j][inside]))
        r2 = float(np.median(gap.gear_closure_mm[j][inside]))
        w = np.where(inside, gap.gear_closure_mm[j], r2) / r2
        t = np.where(inside, gap.pinion_arm_mm[j], r1) / r1
        blocks, tooth = [], []
        for k in range(P):
            blocks.append(halfspace_matrix(grid.across_half_mm[j, k], grid.along_half_mm[j, k], nx, ny, e_star_mpa)
                          if inside[k].any() else np.eye(nx * ny))
            tooth.append(pair_tooth_compliance(teeth[0], teeth[1], gap.pinion_point[j, k, centre],
                                               gap.gear_point[j, k, centre]) if inside[k].any()
                         else np.zeros((ny, ny)))
        comp = BeveloidCompliance(blocks, tooth, line, area[j])
        sol = lcp.solve_contact(comp, gap.gap_mm[j].ravel(), np.repeat(area[j], nx * ny), torque_nm * 1e3 / r1,
                                w.ravel(), t.ravel())
        out["p"][j] = sol.pressure_mpa.reshape(P, -1)
        out["ok"][j] = sol.converged
        out["delta"][j] = sol.approach_mm / r2
        out["approach"][j] = sol.approach_mm
        out["it"][j] = sol.iterations
        out["comp"][j] = sol.complementarity_residual
        out["load"][j] = sol.load_residual
    return Solution(grid=grid, gap=gap, pressure_mpa=out["p"], converged=out["ok"], no_contact=out["none"],
                    rotation_rad=out["delta"], approach_mm=out["approach"], iterations=out["it"], complementarity_residual=out["comp"],
                    load_residual=out["load"])


def merge(old: Solution, new: Solution, rows) -> Solution:
    """``old`` with the positions ``rows`` taken from ``new`` (the same cell counts)."""
    def take(a, b):
        a = np.array(a, copy=True)
        a[rows] = b[rows]
        return a
    grid = old.grid._replace(across_half_mm=take(old.grid.across_half_mm, new.grid.across_half_mm),
                             along_half_mm=take(old.grid.along_half_mm, new.grid.along_half_mm))
    gap = gaps.PairGap(*[take(a, b) for a, b in zip(old.gap, new.gap)])
    rest = {f: take(getattr(old, f), getattr(new, f)) for f in Solution._fields if f not in ("grid", "gap")}
    return Solution(grid=grid, gap=gap, **rest)
