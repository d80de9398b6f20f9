"""The unloaded gap over the contact grid of each (position, tooth pair), from the generated kernels.

Every cell centre is mapped onto the pinion flank (Newton on the generated surface jet: the point
whose offset from the tangency has the cell's tangent-plane coordinates) and then along the
pinion's normal onto the gear flank (Newton on the generated Eq 38 system): the distance along
the normal is the unloaded gap.  Both Newtons are ``solver.core.normal_gaps``, on either backend
(numba-compiled, or the same source interpreted by numpy).  A cell is on the flanks when both
Newtons converged and both points are on their blanks by the one boundary rule,
``solver.core.on_patch``.
"""
from __future__ import annotations

import functools
import typing

import numpy as np

from ... import curvature, tca
from ...generated import placement
from ...solver.core import on_patch
from ...solver.records import GapOutput, GapRequest

OFF_FLANK_GAP_MM = 10.0  #: the gap given to cells that lie off a blank: they never touch
NEWTON_TOL_MM = 1e-9  #: both Newtons of the gap (mm)
NEWTON_ITERATIONS = 10


class Frames(typing.NamedTuple):
    """The tangent-plane frame of Q tooth pairs: where each pair's cells are measured from."""

    start: np.ndarray  # (Q, 5) unknowns (tca_kernels.UNKNOWNS) to start both Newtons from
    pinion_angle: np.ndarray  # (Q,) rad, pair 0's frame
    origin: np.ndarray  # (Q, 3) the tangency on the pinion flank, S_1
    axes: np.ndarray  # (Q, 2, 3) unit (across, along) directions in S_1


class CellGaps(typing.NamedTuple):
    """Unloaded gap of grid cells (Q, cells): see :func:`cell_gaps`."""

    gap_mm: np.ndarray
    gap_D_gear_angle: np.ndarray  # ds/dphi'_2 (mm/rad)
    pinion_arm_mm: np.ndarray  # n_f1 . dR_f1/dphi'_1
    on_flanks: np.ndarray  # both Newtons converged and both points on their blanks (core.on_patch)
    pinion_lu: np.ndarray  # (Q, cells, 2)
    pinion_point: np.ndarray  # (Q, cells, 3) in S_1
    gear_point: np.ndarray  # (Q, cells, 3) in S_2
    margin_mm: np.ndarray  # the smaller of both points' smallest margins to their blanks (mm)


def cell_gaps(geom, flank, errors, frames: Frames, coords, solver, problem=None) -> CellGaps:
    """The gap of the cells ``coords`` (Q, n, 2) of Q pairs in their ``frames``:
    ``solver.core.normal_gaps`` (one point at a time, each starting from its neighbour's solution)."""
    Q, n = coords.shape[:2]
    M = Q * n
    rotation = placement.pinion_placement(frames.pinion_angle, geom.placement()).rotation
    core = solver.announced_core()
    out = GapOutput(pinion_lu=np.empty((M, 2)), gear_lu_gap=np.empty((M, 3)), rates=np.empty((M, 2)),
                    margin=np.empty(M), ok=np.empty(M, dtype=np.int64), pinion_point=np.empty((M, 3)),
                    gear_point=np.empty((M, 3)))
    c = np.ascontiguousarray
    request = GapRequest(pair_of_point=np.repeat(np.arange(Q), n), coords=c(coords.reshape(M, 2), dtype=float),
                         start=c(frames.start, dtype=float), pinion_angle=c(frames.pinion_angle, dtype=float),
                         origin=c(frames.origin, dtype=float), axes=c(frames.axes, dtype=float),
                         rotation=c(rotation, dtype=float), errors=c(errors, dtype=float),
                         tol_mm=float(NEWTON_TOL_MM), max_iter=int(NEWTON_ITERATIONS))
    core.normal_gaps(geom.problem(flank) if problem is None else problem, request, out)
    lu, gear, rates, margin, ok, p1, p2 = (out.pinion_lu, out.gear_lu_gap, out.rates, out.margin, out.ok,
                                           out.pinion_point, out.gear_point)
    r = lambda a: a.reshape((Q, n) + a.shape[1:])  # noqa: E731
    on = (ok == 1) & on_patch(margin, solver.options.patch_tol_mm) & np.isfinite(gear[:, 2])
    return CellGaps(gap_mm=r(gear[:, 2]), gap_D_gear_angle=r(rates[:, 0]), pinion_arm_mm=r(rates[:, 1]),
                    on_flanks=r(on), pinion_lu=r(lu), pinion_point=r(p1), gear_point=r(p2), margin_mm=r(margin))


def serpentine_gaps(setup, frames: Frames, coords, shape, solver, by_columns=False, fields=CellGaps._fields) -> CellGaps:
    """:func:`cell_gaps` of each pair's points ``coords`` (Q, rows x columns, 2), row-major in ``shape``
    (rows, columns), visited row by row (``by_columns``: column by column), every other one reversed:
    each point starts its Newtons from its neighbour, on a line (normal_gaps extrapolates along it).
    ``fields``: the CellGaps fields put back in row-major order, the others None (:func:`column_shifts` reads
    the gap alone)."""
    cg = cell_gaps(setup.geom, setup.flank, setup.errors, frames, _serpentine(coords, shape, by_columns), solver,
                   setup.problem)
    return CellGaps(*[_serpentine(a, shape, by_columns, back=True) if f in fields else None
                      for f, a in zip(CellGaps._fields, cg)])


def _serpentine(a, shape, by_columns, back=False):
    """a (Q, rows x columns, ...) row-major in ``shape`` put in the order its rows (``by_columns``: its
    columns) are visited, every other one reversed; ``back``: the order undone (one gather, C-contiguous)."""
    return np.take(a, _serpentine_order(tuple(shape), bool(by_columns), bool(back)), axis=1)


@functools.lru_cache(maxsize=64)
def _serpentine_order(shape, by_columns, back):
    """The indices of :func:`_serpentine` (rows x columns,): the visit order, or (``back``) its inverse."""
    walk = shape[::-1] if by_columns else shape
    idx = np.arange(shape[0] * shape[1]).reshape(shape)
    b = (idx.T if by_columns else idx).reshape(walk).copy()
    b[1::2] = b[1::2, ::-1]
    order = b.ravel()
    if back:
        order = np.argsort(order)
    order.flags.writeable = False
    return order


class PrincipalFrame(typing.NamedTuple):
    axes: np.ndarray  # (..., 2, 3) (across, along) in S_1
    origin: np.ndarray  # (..., 3) the tangency on the pinion flank, S_1
    curvature_across: np.ndarray  # (...,) 1/mm: the gap is 1/2 (k_across x^2 + k_along y^2)
    curvature_along: np.ndarray  # (...,) 1/mm
    pinion_arm_mm: np.ndarray  # (...,) moment arm about the pinion axis of the normal at the tangency


def principal_frame(geom, flank, x, phi1, errors) -> PrincipalFrame:
    """The principal directions of the relative curvature H of the two flanks at each pair's
    tangency x (..., 5) (beveloid.curvature); 'across' is the stiffer one (the contact ellipse's
    minor axis), both in S_1, with the principal relative curvatures.  Tangencies where the
    curvature is not defined (not finite, a singular first form) get nan."""
    shape = x.shape[:-1]
    xs, ps = x.reshape(-1, x.shape[-1]), np.broadcast_to(phi1, shape).ravel()
    es = np.broadcast_to(errors, shape + (errors.shape[-1],)).reshape(-1, errors.shape[-1])
    out = PrincipalFrame(np.full((xs.shape[0], 2, 3), np.nan), np.full((xs.shape[0], 3), np.nan),
                         np.full(xs.shape[0], np.nan), np.full(xs.shape[0], np.nan), np.full(xs.shape[0], np.nan))
    rows = np.flatnonzero(np.isfinite(xs).all(axis=-1) & np.isfinite(ps))
    try:
        _frame_into(out, rows, geom, flank, xs[rows], ps[rows], es[rows])
    except np.linalg.LinAlgError:  # one singular row: the others one by one
        for i in rows:
            try:
                _frame_into(out, [i], geom, flank, xs[[i]], ps[[i]], es[[i]])
            except np.linalg.LinAlgError:
                pass
    return PrincipalFrame(*[a.reshape(shape + a.shape[1:]) for a in out])


def _frame_into(out, rows, geom, flank, x, phi1, errors):
    rc = curvature.relative_curvature(geom, flank, x, phi1, errors)
    val, vec = np.linalg.eigh(rc.H)  # ascending: column 1 is the stiff direction
    across_f = np.einsum("...k,...ki->...i", vec[..., :, 1], rc.basis)
    along_f = np.cross(rc.normal, across_f)
    rot = placement.pinion_placement(phi1, geom.placement()).rotation  # S_1 -> S_f
    to_s1 = lambda d: np.einsum("...ji,...j->...i", rot, d)  # noqa: E731  (L_f1^T d)
    u = tca.unknowns(x)
    s = geom.surface("pinion", flank, u.pinion_l_mm, u.pinion_u_mm)
    out.axes[rows] = np.stack([to_s1(across_f), to_s1(along_f)], axis=-2)
    out.origin[rows] = s.point
    out.curvature_across[rows] = val[..., 1]
    out.curvature_along[rows] = val[..., 0]
    out.pinion_arm_mm[rows] = np.abs(s.point[..., 0] * s.normal[..., 1] - s.point[..., 1] * s.normal[..., 0])


class PairGap(typing.NamedTuple):
    """The unloaded gap over the cells of every (position, pair), arrays (N, P, cells)."""

    gap_mm: np.ndarray
    in_flank: np.ndarray  # on both blanks, both Newtons converged, closing under load
    gear_closure_mm: np.ndarray  # gap closure per rad of gear rotation (> 0)
    pinion_arm_mm: np.ndarray  # moment arm about the pinion axis of a unit normal force on the cell (> 0)
    pinion_point: np.ndarray  # (N, P, cells, 3) in S_1 (tooth 0)
    gear_point: np.ndarray  # (N, P, cells, 3) in S_2 (tooth 0)
    pinion_lu: np.ndarray  # (N, P, cells, 2) pinion surface parameters of the cell centres
    across_shift_mm: np.ndarray  # (N, P, along cells) offset of each along-column (follows the line)


def empty_gap(N, P, n, ny) -> PairGap:
    return PairGap(gap_mm=np.full((N, P, n), OFF_FLANK_GAP_MM), in_flank=np.zeros((N, P, n), dtype=bool),
                   gear_closure_mm=np.zeros((N, P, n)), pinion_arm_mm=np.zeros((N, P, n)),
                   pinion_point=np.full((N, P, n, 3), np.nan), gear_point=np.full((N, P, n, 3), np.nan),
                   pinion_lu=np.full((N, P, n, 2), np.nan), across_shift_mm=np.zeros((N, P, ny)))


def grid_gaps(setup, grid, need, solver, shift_mm=None) -> PairGap:
    """The gap over ``grid`` (grid.PairGrid) for the (position, pair)s in ``need`` (N, P).

    The grid follows the unloaded contact line: each along-column is centred on the vertex of the
    parabola through the gap at xi = -d, 0, +d (d = that grid's half-extent across); ``shift_mm``
    (N, P, along cells): these offsets instead (a grid of the same extents placed already)."""
    nx, ny = grid.across_cells, grid.along_cells
    N, P = need.shape
    out = empty_gap(N, P, nx * ny, ny)
    jj, kk = np.nonzero(need)
    if jj.size == 0:
        return out
    frames = Frames(setup.start[jj, kk], setup.pair_phi1[jj, kk], setup.frame.origin[jj, kk],
                    setup.frame.axes[jj, kk])
    X, Y = grid.across_half_mm[jj, kk], grid.along_half_mm[jj, kk]
    ux, uy = grid.unit_centres()  # (nx,), (ny,) in [-1, 1]
    yc = uy[None, :] * Y[:, None]  # (Q, ny)
    shift = column_shifts(setup, frames, X, yc, solver) if shift_mm is None else shift_mm[jj, kk]
    cx = ux[None, :, None] * X[:, None, None] + shift[:, None, :]  # (Q, nx, ny)
    cy = np.broadcast_to(yc[:, None, :], cx.shape)
    coords = np.stack([cx, cy], axis=-1).reshape(jj.size, nx * ny, 2)
    cg = serpentine_gaps(setup, frames, coords, (nx, ny), solver, by_columns=True)  # short steps across
    closure = -setup.gear_sign * cg.gap_D_gear_angle
    arm = setup.pinion_sign * cg.pinion_arm_mm
    with np.errstate(invalid="ignore"):
        inside = cg.on_flanks & (closure > 0) & (arm > 0)
    out.gap_mm[jj, kk] = np.where(inside, cg.gap_mm, OFF_FLANK_GAP_MM)
    out.in_flank[jj, kk] = inside
    out.gear_closure_mm[jj, kk] = np.where(inside, closure, 0.0)
    out.pinion_arm_mm[jj, kk] = np.where(inside, arm, 0.0)
    out.pinion_point[jj, kk], out.gear_point[jj, kk] = cg.pinion_point, cg.gear_point
    out.pinion_lu[jj, kk] = cg.pinion_lu
    out.across_shift_mm[jj, kk] = shift
    return out


def column_shifts(setup, frames, X, yc, solver):
    """(Q, ny) the across offset of each along-column at ``yc`` (Q, ny) of Q grids of half-extents
    ``X`` (Q,) across: the vertex of the parabola through the gap at -X, 0, +X (clipped to 3 X; where
    not found, the nearest column's)."""
    ny = yc.shape[1]
    probe = np.stack(np.broadcast_arrays((np.array([-1.0, 0.0, 1.0])[None, :, None] * X[:, None, None]),
                                         yc[:, None, :]), axis=-1).reshape(X.size, 3 * ny, 2)
    h3 = serpentine_gaps(setup, frames, probe, (3, ny), solver, fields=("gap_mm",)).gap_mm.reshape(X.size, 3, ny).transpose(0, 2, 1)
    d = X[:, None]
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        curv = h3[..., 0] - 2 * h3[..., 1] + h3[..., 2]
        shift = np.where(curv > 0, 0.5 * d * (h3[..., 0] - h3[..., 2]) / curv, np.nan)
        shift = np.where(np.isfinite(shift), np.clip(shift, -3 * d, 3 * d), np.nan)
    return fill_nan_rows(shift)


def fill_nan_rows(a):
    """Each row's NaNs replaced by the nearest finite entry of that row (0 if none)."""
    out = a.copy()
    idx = np.arange(a.shape[-1])
    for r in np.flatnonzero(~np.isfinite(a).all(axis=-1)):  # the rows with a NaN
        ok = np.isfinite(a[r])
        out[r] = np.interp(idx, idx[ok], a[r, ok]) if ok.any() else 0.0
    return out
