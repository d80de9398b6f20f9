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

from ... import tca
from ...status import PointStatus, Status
from ...tca.flank import mesh_paths
from ..model import gaps
from ..mechanics import halfspace, kernel, lcp
from ..model.compliance import pair_tooth_compliances
from ..model.grid import edges


class Setup:
    """Everything of one (geometry, flank, errors, positions, pairs) that does not depend on the grid."""

    def __init__(self, geom, flank, errors, positions, pairs, solver, frame=True, paths=None):
        """``frame=False``: the principal frames left to the caller (:meth:`with_frame`; :func:`setups`
        computes those of many error sets at once); ``paths``: this set's rigid mesh
        (``tca.flank.mesh_paths``, K = 1; None: solved here; :func:`setups` solves those of many sets at once)."""
        self.geom, self.flank, self.solver = geom, flank, solver
        self.problem = geom.problem(flank)  # the packed surfaces of the gap solves, once
        self.errors = tca.errors_array(errors)
        # the Solver itself, its tolerances with its backend (issue 42)
        fr = paths if paths is not None else mesh_paths(geom, flank, self.errors, positions, pairs, 1, solver=solver)
        ref = tca.reference_contact(geom, flank, solver.options)  # the Solver's tolerances
        self.reference = ref
        ref_gear = tca.unknowns(ref.x).gear_angle_rad
        p1, p2 = geom.pitch_angles
        n1, n2 = geom.pinion.teeth, geom.gear.teeth
        self.n1_over_n2 = n1 / n2
        self.ks = np.arange(pairs) - pairs // 2
        self.phi1 = fr.pinion_angle[:positions]
        x = fr.unknowns[0].reshape(pairs, positions, 5).transpose(1, 0, 2)  # (N, P, 5) pair 0 unknowns
        status = np.asarray(Status.labels(fr.code[0]), dtype=object).reshape(pairs, positions).T
        self.solved = np.array([[s != PointStatus.FAILED for s in row] for row in status], dtype=bool)
        # a tangency the rigid TCA did not solve between two solved positions of the same pair: the
        # interpolation of its neighbours places that pair's grid (the gap itself is measured on the
        # true surfaces), so a loaded pair never drops out of one position
        x, self.interpolated = _fill_between(x, self.phi1, self.solved)
        self.solved |= self.interpolated
        # the tangency lies on both flanks: its patch is a surface contact
        self.on_flank = np.array([[s in (PointStatus.OK, PointStatus.EDGE) for s in row] for row in status], dtype=bool)
        te = fr.transmission_error[0].reshape(pairs, positions).T
        active = fr.active[0].reshape(pairs, positions).T
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
        if frame:
            self.with_frame(gaps.principal_frame(geom, flank, x, self.pair_phi1, self.errors))

    def with_frame(self, frame):
        """The rest of the set-up, from the principal frames (:func:`gaps.principal_frame`) of ``self.x``."""
        geom = self.geom
        self.frame = frame
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
        cg = gaps.cell_gaps(self.geom, self.flank, self.errors, frames, np.zeros((jj.size, 1, 2)), self.solver,
                            self.problem)
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


def setups(geom, flank, error_sets, positions, pairs, solver, angles=None) -> list:
    """The :class:`Setup` of each error set, their rigid meshes in one call of the solver core and their
    principal frames in one evaluation of the surfaces (the same numbers as each set's own: the core solves each
    set alone, the frames are elementwise arrays, only longer; a crowned candidate's 16 sets 2.6 ms a set one
    by one, 0.5 ms together).  ``angles``: the ``positions`` pinion angles (rad) to solve at (None: the mesh
    cycle's, ``tca.flank.mesh_angles``)."""
    if len(error_sets) == 0:
        return []
    paths = mesh_paths(geom, flank, np.asarray(error_sets, dtype=float), positions, pairs, 1, solver=solver,
                       angles=angles)
    out = [Setup(geom, flank, e, positions, pairs, solver, frame=False, paths=paths.of_set(k))
           for k, e in enumerate(error_sets)]
    if out:
        frames = gaps.principal_frame(geom, flank, np.stack([s.x for s in out]), np.stack([s.pair_phi1 for s in out]),
                                      np.stack([s.errors for s in out])[:, None, None, :])
        for k, s in enumerate(out):
            s.with_frame(gaps.PrincipalFrame(*[a[k] for a in frames]))
    return out


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


#: positions whose dense compliance blocks are made and solved together (cycle.solve_many)
CHUNK_POSITIONS = 4


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


class Problem(typing.NamedTuple):
    """One :func:`solve_many` problem: the positions ``positions`` (None: all) of ``setup`` on
    ``grid`` under ``torque_nm``; only the pairs in ``need`` (N, P) are gridded.  ``start``: a Solution
    of the same setup and torque on another grid, whose contact set mapped onto this grid
    (:func:`mapped_contact`) starts the active-set iteration (the solution does not depend on the start,
    only the iterations to it do); None: the uncoupled estimate.  ``shift_mm`` (N, P, along cells): the
    across offsets of the along-columns (:func:`beveloid.ltca.model.gaps.grid_gaps`) when known, None: probed.
    ``start_cells`` (N, P, cells): a start set taken cell for cell (:func:`held_contact` of a Solution on a
    grid of the same cell counts), at each position where it holds a cell instead of ``start``'s."""

    setup: Setup
    grid: typing.Any  # grid.PairGrid
    need: np.ndarray
    torque_nm: float
    positions: typing.Any = None
    start: typing.Any = None  # Solution
    shift_mm: typing.Any = None
    start_cells: typing.Any = None


def solve(setup: Setup, grid, need, torque_nm, e_star_mpa, teeth, positions=None) -> Solution:
    """Solve ``positions`` (default all) on ``grid``; only the pairs in ``need`` (N, P) are gridded."""
    return solve_many([Problem(setup, grid, need, torque_nm, positions)], e_star_mpa, teeth)[0]


def solve_many(problems, e_star_mpa, teeth) -> list:
    """The Solution of each :class:`Problem` (all of one cell count): their gaps one setup at a time,
    the compliance tables of every position of a problem at once (:func:`compliance_tables`), then the
    dense blocks' rows (:func:`block_rows`) and the contact problems (:func:`beveloid.ltca.mechanics.kernel.solve_positions`,
    compiled with the solver's backend) of :data:`CHUNK_POSITIONS` positions at a time."""
    parts, rows = [], []
    for pr in problems:
        N, P = pr.need.shape
        todo = np.zeros(N, dtype=bool)
        todo[list(range(N)) if pr.positions is None else list(pr.positions)] = True
        need = pr.need & todo[:, None] & pr.setup.solved & pr.setup.has_reference[:, None]
        gap = gaps.grid_gaps(pr.setup, pr.grid, need, pr.setup.solver, pr.shift_mm)
        live = todo & gap.in_flank.any(axis=(1, 2))
        parts.append((pr, gap, todo, live))
        rows.append(np.flatnonzero(live))
    nx, ny = problems[0].grid.across_cells, problems[0].grid.along_cells
    n = nx * ny
    P = problems[0].need.shape[1]
    J = sum(r.size for r in rows)
    solver = problems[0].setup.solver
    k = kernel.kernels(solver)
    limits = lcp.SolveLimits()
    p, result, r2s = np.zeros((J, P * n)), np.zeros((J, 5)), np.ones(J)
    # the dense blocks of CHUNK_POSITIONS positions at a time, their rows made by the solve as it reads them
    # (kernel.Rows): a problem's blocks at once (20 positions x 3 pairs of 187 cells: 17 MB) left the cache
    # before the solve read them
    buffer = np.empty((min(CHUNK_POSITIONS, max((r.size for r in rows), default=0)) * P, n, n))
    at_row = 0
    for (pr, gap, _, _), jj in zip(parts, rows):
        if jj.size == 0:
            continue
        sl = slice(at_row, at_row + jj.size)
        at_row += jj.size
        inside = gap.in_flank[jj]
        r1 = masked_median(gap.pinion_arm_mm[jj], inside)
        r2 = masked_median(gap.gear_closure_mm[jj], inside)
        area = pr.grid.cell_area_mm2()[jj]
        w = (np.where(inside, gap.gear_closure_mm[jj], r2[:, None, None]) / r2[:, None, None]).reshape(jj.size, -1)
        t = np.where(inside, gap.pinion_arm_mm[jj], r1[:, None, None]) / r1[:, None, None]
        at = (t * area[..., None]).reshape(jj.size, -1)
        h = np.ascontiguousarray(gap.gap_mm[jj].reshape(jj.size, -1))
        r2s[sl] = r2
        tables = compliance_tables(pr.grid, gap, jj, inside.any(axis=-1), e_star_mpa, teeth)
        warm = pr.start is not None or pr.start_cells is not None
        starts = np.zeros((jj.size, P * n if warm else 1), dtype=np.bool_)
        if pr.start is not None:
            starts = mapped_contact(pr.start, pr.grid, gap)[jj].reshape(jj.size, -1)
        if pr.start_cells is not None:
            held = (pr.start_cells & gap.in_flank)[jj].reshape(jj.size, -1)
            starts = np.where(held.any(axis=-1, keepdims=True), held, starts)
        starts = np.ascontiguousarray(starts)
        load = pr.torque_nm * 1e3 / r1
        for c0 in range(0, jj.size, CHUNK_POSITIONS):
            c = slice(c0, min(c0 + CHUNK_POSITIONS, jj.size))
            m = c.stop - c.start
            blocks = buffer[:m * P]
            off = (np.arange(m * P, dtype=np.int64) * n * n).reshape(m, P)
            rows_c = slice(sl.start + c.start, sl.start + c.stop)
            k.solve_positions(kernel.Layout(blocks.reshape(-1), off, np.arange(P, dtype=np.int64) * n,
                                            np.full(P, n, dtype=np.int64), np.ones((m, P), dtype=np.bool_),
                                            block_rows(tables, c, nx, ny)),
                              kernel.Cells(h[c], w[c], at[c], load[c]),
                              kernel.Start(limits.tolerance, limits.max_iterations, starts[c] if warm else starts,
                                           np.full(m, warm)),
                              kernel.Output(p[rows_c], result[rows_c]))
    out, at_row = [], 0
    for (pr, gap, todo, live), jj in zip(parts, rows):
        N = pr.need.shape[0]
        sl = slice(at_row, at_row + jj.size)
        at_row += jj.size
        pm = np.zeros((N, P, n))
        pm[jj] = p[sl].reshape(jj.size, P, n)
        res = result[sl]
        ok = np.zeros(N, bool)
        ok[jj] = res[:, 2] == 0
        rotation, approach = np.full(N, np.nan), np.full(N, np.nan)
        rotation[jj], approach[jj] = res[:, 0] / r2s[sl], res[:, 0]
        it = np.zeros(N, int)
        it[jj] = res[:, 1]
        comp, lres = np.full(N, np.nan), np.full(N, np.nan)
        comp[jj], lres[jj] = res[:, 3], res[:, 4]
        out.append(Solution(grid=pr.grid, gap=gap, pressure_mpa=pm, converged=ok, no_contact=todo & ~live,
                            rotation_rad=rotation, approach_mm=approach, iterations=it, complementarity_residual=comp,
                            load_residual=lres))
    return out


def mapped_contact(source: Solution, grid, gap) -> np.ndarray:
    """(N, P, cells) the cells of ``grid`` (its columns placed by ``gap``) on the flanks whose centre
    lies in a loaded cell of ``source`` (a converged Solution of the same frames on another grid): both
    grids' cells in the pair's tangent-plane coordinates."""
    sg = source.grid
    sx, sy = sg.across_cells, sg.along_cells
    nx, ny = grid.across_cells, grid.along_cells
    N, P = grid.across_half_mm.shape
    ux, uy = grid.unit_centres()
    y = uy * grid.along_half_mm[..., None]  # (N, P, ny)
    x = ux[:, None] * grid.across_half_mm[..., None, None] + gap.across_shift_mm[:, :, None, :]  # (N, P, nx, ny)
    with np.errstate(invalid="ignore", divide="ignore"):
        j = np.floor((y / sg.along_half_mm[..., None] + 1.0) * (0.5 * sy))
        j = np.where((j >= 0) & (j < sy), j, -1).astype(np.int64)  # nan (an ungridded pair) fails too
        shift = np.take_along_axis(source.gap.across_shift_mm, np.maximum(j, 0), axis=-1)
        i = np.floor(((x - shift[:, :, None, :]) / sg.across_half_mm[..., None, None] + 1.0) * (0.5 * sx))
        i = np.where((i >= 0) & (i < sx) & (j >= 0)[:, :, None, :], i, -1).astype(np.int64)
    loaded = (source.pressure_mpa > 0).reshape(N, P, sx, sy) & source.converged[:, None, None, None]
    hit = loaded[np.arange(N)[:, None, None, None], np.arange(P)[None, :, None, None], np.maximum(i, 0),
                 np.maximum(j, 0)[:, :, None, :]] & (i >= 0)
    return hit.reshape(N, P, nx * ny) & gap.in_flank


def held_contact(sol: Solution) -> np.ndarray:
    """(N, P, cells) the loaded cells of ``sol`` at its converged positions: a start set for a grid of the
    same cell counts (:attr:`Problem.start_cells`)."""
    return (sol.pressure_mpa > 0) & sol.converged[:, None, None]


def masked_median(values, mask) -> np.ndarray:
    """(J,) the median of each row's ``values`` where ``mask`` (rows (J, ...), each with one True at least)."""
    v = np.sort(np.where(mask, values, np.inf).reshape(mask.shape[0], -1), axis=1)
    m = mask.reshape(mask.shape[0], -1).sum(axis=1)
    rows = np.arange(v.shape[0])
    return 0.5 * (v[rows, (m - 1) // 2] + v[rows, m // 2])


class Tables(typing.NamedTuple):
    """The compliance of the pairs at J positions in compact form (:func:`compliance_tables`)."""

    halfspace: np.ndarray  # (J, P, 2 nx - 1, 2 ny - 1) the half-space Toeplitz table (mm/MPa)
    tooth: np.ndarray  # (J, P, ny, ny) both teeth's compliance along the centre line (mm/N)
    area: np.ndarray  # (J, P) cell area (mm^2)
    loaded: np.ndarray  # (J, P) the pair is in contact (else its cells are never active)


def compliance_tables(grid, gap, jj, loaded, e_star_mpa, teeth) -> Tables:
    """The compliance of each pair at positions ``jj``: its grid's half-space table and both teeth's
    compliance along its centre line (:func:`block_rows`: the rows of the dense blocks).  A pair not in
    contact (``loaded`` (J, P) false: never loaded, its cells never active) gets zeros."""
    nx, ny = grid.across_cells, grid.along_cells
    J, P = loaded.shape
    q = np.nonzero(loaded)
    d = np.zeros((J, P, 2 * nx - 1, 2 * ny - 1))
    T = np.zeros((J, P, ny, ny))
    if q[0].size:
        X, Y = grid.across_half_mm[jj][q], grid.along_half_mm[jj][q]
        ex, ey = edges(X, nx), edges(Y, ny)  # (cells + 1, Q): the cell size as the grid's edges give it
        d[q] = halfspace.uniform_influence_table(ex[1] - ex[0], ey[1] - ey[0], nx, ny, e_star_mpa)
        centre = (nx // 2) * ny + np.arange(ny)  # the cells on the grid's along-axis
        T[q] = pair_tooth_compliances(teeth[0], teeth[1], gap.pinion_point[jj][q][:, centre],
                                      gap.gear_point[jj][q][:, centre])
    return Tables(d, T, grid.cell_area_mm2()[jj], loaded)


def block_rows(tables: Tables, rows, nx, ny):
    """The :class:`beveloid.ltca.mechanics.kernel.Rows` of each pair at the positions ``rows`` (a slice) of
    ``tables``: the contact solve makes a row of a pair's compliance (mm/MPa) when its cell first enters a trial
    set, its half-space matrix plus both teeth's compliance along its centre line applied to every cell of the
    same along index, C[(i,a),(j,b)] = H + T[a, b] area; a pair not in contact only a unit diagonal."""
    d, T = tables.halfspace[rows], tables.tooth[rows]
    R, P = d.shape[:2]
    return kernel.Rows(np.ascontiguousarray(d.reshape(R * P, *d.shape[2:])),
                       np.ascontiguousarray(T.reshape(R * P, ny, ny)), np.ascontiguousarray(tables.area[rows].reshape(-1)),
                       np.ascontiguousarray(tables.loaded[rows].reshape(-1)), np.zeros((R * P, nx * ny), dtype=np.bool_))


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
