"""Loaded tooth contact analysis (LTCA) of crossed beveloid gears: the gear geometry joined
to the mechanics layer of :mod:`beveloid.loaded` (issue 13).  Approximate by construction;
the model, its choices and its limits are in docs/loaded_contact.md ("LTCA").

At each mesh position and for every tooth pair in the window:

* **Grid.**  A tensor grid of flat rectangular cells in the tangent plane of the pinion
  flank at the pair's rigid-body tangency (from :func:`beveloid.tca.mesh_flank`), its axes
  along the principal directions of the flanks' relative curvature
  (:func:`beveloid.curvature.relative_curvature`; ``across`` the contact line: the stiff
  direction; ``along`` it), each along-column shifted across onto the unloaded contact line.
  Every cell centre is mapped onto the pinion flank (Newton on the generated surface jet)
  and then along the pinion normal onto the gear flank (Newton on the generated Eq 38
  system): ``solver.core.normal_gaps``; the distance along the normal is the unloaded gap.
  Cells whose centre lies off either blank (``flank_margins`` < 0) cannot touch.
* **Extent.**  The grid extent is sized to the loaded patch, not to the flank: at the
  first, middle and last positions the solve is repeated with the extent set to ``margin``
  times the patch until it settles; any position whose patch reaches the grid's edge inside the flank makes
  the whole cycle run again on a larger grid.  Along the contact line the extent is capped
  by the flank diagonal, so a patch that reaches a flank edge meets the masked cells there:
  edge loading is represented directly.
* **Compliance.**  Boussinesq half-space of both bodies over the cells (one matrix for all
  pairs and positions: the cells are the same rectangles) plus tooth bending/shear/root
  compliance of both members, each as the thin-slice model of an equivalent spur tooth
  evaluated on the line of cell centres along the contact line.
* **Solve.**  One problem per position for all pairs: pressures >= 0, gaps >= 0,
  complementarity, one rigid gear rotation, and the moment of the contact forces about the
  pinion axis equal to the applied pinion torque.
"""
from __future__ import annotations

import functools
import math
import typing
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from . import tca
from .generated import flank_boundaries, placement, tca_kernels
from .loaded import halfspace, lcp, tooth_compliance
from .solver.core import on_patch

OFF_FLANK_GAP_MM = 10.0  #: the gap given to cells that lie off a blank: they never touch
_NEWTON_TOL_MM = 1e-9  #: both Newtons of the gap (mm)
_NEWTON_ITERATIONS = 10
_PATCH_TOL_MM = tca.DEFAULT_OPTIONS.patch_tol_mm  #: a cell is on a flank by the TCA's rule (core.on_patch)
_GAIN = tca_kernels.UNKNOWNS.index("gear_angle_rad")  # Jacobian columns by the generated names
_GEAR_LU = [tca_kernels.UNKNOWNS.index("gear_l_mm"), tca_kernels.UNKNOWNS.index("gear_u_mm")]


@dataclass(frozen=True)
class GridOptions:
    """The contact grid of one tooth pair (the same for every pair and position)."""

    across_cells: int = 13  #: cells across the contact line (resolves the Hertz width)
    along_cells: int = 31  #: cells along the contact line
    margin: float = 1.4  #: grid half-extent / patch half-extent found at the first, middle, last positions
    initial_across_mm: float = 0.6  #: first guess of the half-extent across the contact line
    max_regrids: int = 4  #: cycle re-runs with a larger grid when a patch reaches its edge

    def check(self):
        for name in ("across_cells", "along_cells"):
            v = getattr(self, name)
            if not (isinstance(v, int) and 3 <= v <= 201):
                raise ValueError(f"{name} = {v!r}: must be an integer from 3 to 201")
        if not (1.05 <= self.margin <= 5.0):
            raise ValueError(f"margin = {self.margin!r}: must be a number from 1.05 to 5")
        return self


@dataclass(frozen=True)
class Material:
    """Elastic constants (MPa) of both members."""

    pinion_e_mpa: float = halfspace.STEEL_E_MPA
    pinion_nu: float = halfspace.STEEL_NU
    gear_e_mpa: float = halfspace.STEEL_E_MPA
    gear_nu: float = halfspace.STEEL_NU

    @classmethod
    def from_spec(cls, spec) -> "Material":
        m = spec.material
        return cls(m.pinion_youngs_modulus_gpa * 1e3, m.pinion_poisson_ratio,
                   m.gear_youngs_modulus_gpa * 1e3, m.gear_poisson_ratio)

    @property
    def e_star_mpa(self) -> float:
        return halfspace.reduced_modulus_mpa(self.pinion_e_mpa, self.pinion_nu, self.gear_e_mpa, self.gear_nu)


# --------------------------------------------------------------------------------------------
# the gap over a pair's grid, from the generated kernels
# --------------------------------------------------------------------------------------------
@dataclass
class PairGap:
    """The unloaded gap over the cells of every (position, pair), arrays (..., cells)."""

    gap_mm: np.ndarray
    in_flank: np.ndarray  # both cell centres on their blanks and both Newtons converged
    gear_closure_mm: np.ndarray  # gap closure per rad of gear rotation (sign: closing > 0 at contact)
    pinion_arm_mm: np.ndarray  # moment arm about the pinion axis of a unit normal force on the cell
    pinion_point: np.ndarray  # (..., cells, 3) in S_1 (tooth 0)
    gear_point: np.ndarray  # (..., cells, 3) in S_2 (tooth 0)
    gear_sign: float  # +1 if closing turns the gear by +phi'_2
    pinion_sign: float  # +1 if the contact forces' moment about the pinion axis is negative along +z_1
    pinion_lu: np.ndarray = None  # (..., cells, 2) pinion surface parameters of the cell centres
    across_shift_mm: np.ndarray = None  # (..., along cells) offset of each along-column (follows the line)


def _newton(residual_and_jacobian, unknowns, iterations, tol=_NEWTON_TOL_MM, bound=1e3, active=None):
    """Vectorised Newton over flat points; each point stops when converged, diverged points are frozen.

    ``residual_and_jacobian(idx, z)`` -> (f (m, k), J (m, k, k)) for the points idx with unknowns z.
    Returns the unknowns and a converged mask.
    """
    z = unknowns.copy()
    todo = np.arange(z.shape[0]) if active is None else np.flatnonzero(active)
    done = np.zeros(z.shape[0], dtype=bool)
    last = np.full(z.shape[0], np.inf)
    for k in range(iterations + 1):
        if todo.size == 0:
            break
        f, jac = residual_and_jacobian(todo, z[todo])
        err = np.abs(f).max(axis=-1)
        conv = err < tol
        done[todo[conv]] = True
        # a point whose residual grows after the first two steps is off the surfaces' valid range
        keep = ~conv & np.isfinite(err) & (err < bound) & ((k < 2) | (err < 0.5 * last[todo]))
        last[todo] = err
        todo, f, jac = todo[keep], f[keep], jac[keep]
        if k == iterations:
            break
        if todo.size == 0:
            break
        with np.errstate(all="ignore"):
            z[todo] += _solve_small(jac, -f)
    return z, done


def _solve_small(a, b):
    """x with a x = b for stacks of 2x2 or 3x3 systems (Cramer's rule: much faster than a
    batched LAPACK call for these sizes; a singular system gives non-finite x, caught by the caller)."""
    if a.shape[-1] == 2:
        det = a[:, 0, 0] * a[:, 1, 1] - a[:, 0, 1] * a[:, 1, 0]
        return np.stack([b[:, 0] * a[:, 1, 1] - b[:, 1] * a[:, 0, 1],
                         a[:, 0, 0] * b[:, 1] - a[:, 1, 0] * b[:, 0]], axis=-1) / det[:, None]
    c0, c1, c2 = a[:, :, 0], a[:, :, 1], a[:, :, 2]
    det = np.einsum("ni,ni->n", c0, np.cross(c1, c2))
    return np.stack([np.einsum("ni,ni->n", b, np.cross(c1, c2)), np.einsum("ni,ni->n", c0, np.cross(b, c2)),
                     np.einsum("ni,ni->n", c0, np.cross(c1, b))], axis=-1) / det[:, None]


def _project_onto_flank(geom, flank, l0, u0, origin, axes, coords, iterations=_NEWTON_ITERATIONS):
    """Pinion (l, u) whose point's offset from ``origin`` has components ``coords`` on the two ``axes``."""
    shape = coords.shape[:-1]
    flat = lambda a, k: np.broadcast_to(a, shape + a.shape[a.ndim - k:] if k else shape).reshape((-1,) + (  # noqa: E731
        a.shape[a.ndim - k:] if k else ()))
    o, ax, c = flat(origin, 1), flat(axes, 2), coords.reshape(-1, 2)
    z0 = np.stack([flat(np.asarray(l0, float), 0), flat(np.asarray(u0, float), 0)], axis=-1)

    def fj(idx, z):
        jet = geom.surface_jet("pinion", flank, z[:, 0], z[:, 1])
        a = ax[idx]
        f = (a @ (jet.point - o[idx])[:, :, None])[:, :, 0] - c[idx]
        return f, a @ jet.point_D_lu

    z, ok = _newton(fj, z0, iterations)
    return z[:, 0].reshape(shape), z[:, 1].reshape(shape), ok.reshape(shape)


def _gap_along_normal(geom, flank, l1, u1, l2, u2, phi1, phi2, errors, iterations=_NEWTON_ITERATIONS, active=None):
    """Gear point on the pinion normal line: (l2, u2, gap s, ds/dphi'_2, pinion arm, system, converged).

    Only the points where ``active`` (default all) are solved; the others come back not converged.
    """
    shape = np.broadcast_shapes(np.shape(l1), np.shape(l2), np.shape(phi1), np.shape(phi2))
    flat = lambda a: np.broadcast_to(np.asarray(a, float), shape).ravel()  # noqa: E731
    live = None if active is None else np.broadcast_to(active, shape).ravel()
    L1, U1, P1, P2 = flat(l1), flat(u1), flat(phi1), flat(phi2)
    n1 = geom.surface("pinion", flank, L1, U1).normal
    rot = placement.pinion_placement(P1, geom.placement()).rotation
    nf1 = np.einsum("nij,nj->ni", rot, n1)
    errors = tca.errors_array(errors)

    # Newton on R_f2(l2, u2) = R_f1 + s n_f1 with the gear's surface jet placed by the generated
    # Eqs 32-35 (one placement per point); Eq 38's kernel gives the final point and its Jacobians
    pin = placement.pinion_placement(P1, geom.placement())
    gear = placement.gear_placement(P2, errors, geom.placement())
    p1 = geom.surface("pinion", flank, L1, U1).point
    rf1 = np.einsum("nij,nj->ni", pin.rotation, p1) + pin.translation

    def system(idx, z):
        x = np.stack([L1[idx], U1[idx], z[:, 0], z[:, 1], P2[idx]], axis=-1)
        return tca.evaluate(geom, flank, x, P1[idx], errors)

    def fj(idx, z):
        jet = geom.surface_jet("gear", flank, z[:, 0], z[:, 1])
        rot = gear.rotation[idx]
        rf2 = (rot @ jet.point[:, :, None])[:, :, 0] + gear.translation[idx]
        f = rf1[idx] - rf2 + z[:, 2, None] * nf1[idx]
        return f, np.concatenate([-(rot @ jet.point_D_lu), nf1[idx, :, None]], axis=-1)

    z0 = np.stack([flat(l2), flat(u2), np.zeros(L1.size)], axis=-1)
    z, ok = _newton(fj, z0, iterations, active=live)
    idx = np.arange(L1.size)
    z = np.where(ok[:, None], z, z0)  # unsolved points: a finite placeholder, flagged by ok
    sy = system(idx, z)
    jac = np.concatenate([sy.residual_D_unknowns[..., :3, _GEAR_LU], nf1[..., None]], axis=-1)
    # ds/dphi'_2 by the implicit function theorem on F(l2, u2, s; phi'_2) = 0
    with np.errstate(all="ignore"):
        ds_dphi2 = np.linalg.solve(jac, -sy.residual_D_unknowns[..., :3, _GAIN, None])[..., 2, 0]
    # moment arm about the pinion axis: n_f1 . dR_f1/dphi'_1 = e_z . (R_f1 x n_f1)
    arm = np.einsum("ni,ni->n", nf1, sy.residual_D_pinion_angle[..., :3])
    r = lambda a: a.reshape(shape + a.shape[1:])  # noqa: E731
    sy = sy._replace(pinion_point=r(sy.pinion_point), gear_point=r(sy.gear_point))
    return r(z[:, 0]), r(z[:, 1]), r(z[:, 2]), r(ds_dphi2), r(arm), sy, r(ok)


class CellGaps(typing.NamedTuple):
    """Unloaded gap of grid cells (..., cells): see :func:`_cell_gaps`."""

    gap_mm: np.ndarray
    gap_D_gear_angle: np.ndarray  # ds/dphi'_2 (mm/rad)
    pinion_arm_mm: np.ndarray  # n_f1 . dR_f1/dphi'_1
    on_flanks: np.ndarray  # both Newtons converged and both points on their blanks (core.on_patch)
    pinion_lu: np.ndarray  # (..., cells, 2)
    pinion_point: np.ndarray  # (..., cells, 3) in S_1
    gear_point: np.ndarray  # (..., cells, 3) in S_2
    margin_mm: np.ndarray  # the smaller of both points' smallest margins to their blanks (mm)


def _cell_gaps(geom, flank, errors, frames, coords, backend):
    """The gap of the cells ``coords`` (Q, n, 2) of Q pairs with frames (start (Q, 5), phi1 (Q,),
    origin (Q, 3), axes (Q, 2, 3)).  The compiled backend runs ``solver.core.normal_gaps`` (one
    point at a time, compiled); the numpy backend the same two Newtons as whole-array operations
    (same start, steps and stopping rules; tests hold the two together)."""
    start, phi1, origin, axes = frames
    Q, n = coords.shape[:2]
    rotation = placement.pinion_placement(phi1, geom.placement()).rotation
    if backend == "compiled":
        core = tca.Solver("compiled").announced_core()
        M = Q * n
        out = dict(lu=np.empty((M, 2)), gear=np.empty((M, 3)), rates=np.empty((M, 2)), margin=np.empty(M),
                   ok=np.empty(M, dtype=np.int64), p1=np.empty((M, 3)), p2=np.empty((M, 3)))
        core.normal_gaps(geom.problem(flank), geom.pinion.blank(), geom.gear.blank(),
                         np.repeat(np.arange(Q), n), np.ascontiguousarray(coords.reshape(M, 2)),
                         np.ascontiguousarray(start), np.ascontiguousarray(phi1), np.ascontiguousarray(origin),
                         np.ascontiguousarray(axes), np.ascontiguousarray(rotation), errors, _NEWTON_TOL_MM,
                         _NEWTON_ITERATIONS, out["lu"], out["gear"], out["rates"], out["margin"], out["ok"],
                         out["p1"], out["p2"])
        r = lambda a: a.reshape((Q, n) + a.shape[1:])  # noqa: E731
        on = (out["ok"] == 1) & on_patch(out["margin"], _PATCH_TOL_MM)
        return CellGaps(gap_mm=r(out["gear"][:, 2]), gap_D_gear_angle=r(out["rates"][:, 0]),
                        pinion_arm_mm=r(out["rates"][:, 1]), on_flanks=r(on), pinion_lu=r(out["lu"]),
                        pinion_point=r(out["p1"]), gear_point=r(out["p2"]), margin_mm=r(out["margin"]))
    ex = lambda a: a[..., None]  # noqa: E731
    st = tca.unknowns(start)
    l1, u1, ok1 = _project_onto_flank(geom, flank, ex(st.pinion_l_mm), ex(st.pinion_u_mm), origin[:, None, :],
                                      axes[:, None, :, :], coords)
    l2, u2, s, ds2, arm, sy, ok2 = _gap_along_normal(geom, flank, l1, u1, ex(st.gear_l_mm), ex(st.gear_u_mm),
                                                     ex(phi1), ex(st.gear_angle_rad), errors, active=ok1)
    with np.errstate(invalid="ignore"):
        m1 = flank_boundaries.flank_margins(sy.pinion_point, l1, geom.pinion.blank()).margins.min(axis=-1)
        m2 = flank_boundaries.flank_margins(sy.gear_point, l2, geom.gear.blank()).margins.min(axis=-1)
        margin = np.minimum(m1, m2)
        on = ok1 & ok2 & on_patch(margin, _PATCH_TOL_MM) & np.isfinite(s)
    return CellGaps(gap_mm=s, gap_D_gear_angle=ds2, pinion_arm_mm=arm, on_flanks=on,
                    pinion_lu=np.stack([l1, u1], axis=-1), pinion_point=sy.pinion_point, gear_point=sy.gear_point,
                    margin_mm=margin)


def _principal_axes(geom, flank, x, phi1, errors):
    """Orthonormal (across, along) axes (..., 2, 3) in S_1 at each pair's tangency x (..., 5), and
    the tangency point in S_1: the principal directions of the relative curvature H of the two
    flanks (beveloid.curvature); 'across' is the stiffer one (the contact ellipse's minor axis)."""
    from . import curvature

    rc = curvature.relative_curvature(geom, flank, x, phi1, errors)
    _, vec = np.linalg.eigh(rc.H)  # ascending: column 1 is the stiff direction
    across_f = np.einsum("...k,...ki->...i", vec[..., :, 1], rc.basis)
    along_f = np.cross(rc.normal, across_f)
    rot = placement.pinion_placement(phi1, geom.placement()).rotation  # S_1 -> S_f
    to_s1 = lambda d: np.einsum("...ji,...j->...i", rot, d)  # noqa: E731  (L_f1^T d)
    u = tca.unknowns(x)
    origin = geom.surface("pinion", flank, u.pinion_l_mm, u.pinion_u_mm).point
    return np.stack([to_s1(across_f), to_s1(along_f)], axis=-2), origin


# --------------------------------------------------------------------------------------------
# tooth compliance of a beveloid member: an equivalent spur tooth (documented approximation)
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _MemberTooth:
    section: tooth_compliance.ToothSection
    module_mm: float
    teeth: int
    pressure_angle: float
    shift: float
    pitch_radius_mm: float  # of the member (generating pitch cylinder)
    virtual_pitch_radius_mm: float
    face_width_mm: float
    toe_mm: float
    direction: float
    coupling_mm: float
    e_mpa: float
    nu: float
    table_radius_mm: np.ndarray  # equivalent-tooth radii of the tabulated slice compliance
    table_mm2_per_n: np.ndarray  # g on table_radius_mm x table_radius_mm


def _member_tooth(geom, which, e_mpa, nu) -> _MemberTooth:
    m = geom.member(which)
    mn, an = geom.normal_module_mm, geom.normal_pressure_angle
    zv = int(min(400, max(6, round(m.teeth / math.cos(m.helix_angle) ** 3))))
    x = float(np.clip(m.rack_shift_mm / mn, -1.0, 1.0))
    ha, hf = m.tip_height_mm / mn, m.cutter_addendum_mm / mn
    section = tooth_compliance.involute_tooth_section(mn, zv, an, x, ha, hf)
    toe, heel = m.face_limits
    rb = 0.5 * mn * zv * math.cos(an)
    radii = np.linspace(max(rb * (1 + 1e-9), section.radius_mm[0] * (1 + 1e-6)), section.radius_mm[-1], 96)
    load = tooth_compliance.involute_load_points(mn, zv, radii, an, x)
    load = tooth_compliance.LoadPoints(np.clip(load.centreline_radius_mm, section.radius_mm[0] * (1 + 1e-9),
                                               section.radius_mm[-1]), load.load_angle_rad)
    table = tooth_compliance.slice_compliance_mm2_per_n(section, load, e_mpa, nu)
    return _MemberTooth(section, mn, zv, an, x, m.pitch_radius_mm, 0.5 * mn * zv, m.face_width_mm, toe,
                        1.0 if heel > toe else -1.0, tooth_compliance.plate_coupling_length_mm((ha + hf) * mn, nu),
                        e_mpa, nu, radii, table)


def _tooth_line_compliance(tooth: _MemberTooth, points) -> np.ndarray:
    """T[a, b] (mm/N): deflection along the normal at point a per unit normal force at point b.

    Points (n, 3) in the member's frame.  The radius maps onto the equivalent spur tooth by
    its height above the pitch cylinder; the axial position onto the face for the coupling.
    """
    r = np.hypot(points[:, 0], points[:, 1])
    rad = tooth.table_radius_mm
    rv = np.clip(tooth.virtual_pitch_radius_mm + (r - tooth.pitch_radius_mm), rad[0], rad[-1])
    rv = np.where(np.isfinite(rv), rv, rad[0])  # cells off the surfaces: never loaded, any finite value
    # bilinear interpolation of the tabulated slice compliance (96 radii over the flank)
    pos = np.interp(rv, rad, np.arange(rad.size))
    i0 = np.minimum(pos.astype(int), rad.size - 2)
    f = pos - i0
    t = tooth.table_mm2_per_n
    a, b = i0[:, None], i0[None, :]
    fa, fb = f[:, None], f[None, :]
    g = ((1 - fa) * (1 - fb) * t[a, b] + fa * (1 - fb) * t[a + 1, b] + (1 - fa) * fb * t[a, b + 1]
         + fa * fb * t[a + 1, b + 1])
    w = tooth.face_width_mm
    hz = 1e-3 * w
    z = np.clip(np.nan_to_num((points[:, 2] - tooth.toe_mm) * tooth.direction, nan=0.5 * w), hz, w - hz)
    k = tooth_compliance.face_coupling_per_mm(z, np.full(z.size, hz), w, tooth.coupling_mm)
    return g * k


# --------------------------------------------------------------------------------------------
# the LTCA
# --------------------------------------------------------------------------------------------
@dataclass
class LTCAResult:
    """Loaded TCA of one flank over a mesh cycle (positions N, tooth pairs P)."""

    flank: str
    torque_nm: float
    pinion_angle: np.ndarray  # (N,) rad
    tooth_pairs: np.ndarray  # (P,)
    status: list  # (N,) "ok" | "not converged" | "no contact"
    loaded_te: np.ndarray  # (N,) rad, nan where not ok
    unloaded_te: np.ndarray  # (N,) rad: the rigid TE envelope
    pair_load_n: np.ndarray  # (N, P) normal force of each pair, nan where not ok
    pair_max_pressure_mpa: np.ndarray  # (N, P); 0 for an unloaded pair
    contact_area_mm2: np.ndarray  # (N,)
    pinion_moment_nmm: np.ndarray  # (N,) moment of the contact forces about the pinion axis
    iterations: np.ndarray  # (N,)
    complementarity_residual: np.ndarray  # (N,)
    load_residual: np.ndarray  # (N,)
    across_half_mm: float
    along_half_mm: float
    grid: GridOptions
    pressure_mpa: np.ndarray  # (N, P, cells)
    gap: PairGap
    cell_area_mm2: np.ndarray  # (cells,)
    axes: np.ndarray  # (N, P, 2, 3) across/along in S_1
    tangency_unknowns: np.ndarray = None  # (N, P, 5) each pair's rigid-body tangency (tca_kernels.UNKNOWNS)
    pair_pinion_angle: np.ndarray = None  # (N, P) the pinion angle of each pair's tangency (pair 0 frame)
    notes: list = field(default_factory=list)
    _patterns: dict = field(default_factory=dict, repr=False)

    @property
    def converged(self) -> np.ndarray:
        return np.asarray([s == "ok" for s in self.status])

    def cell_coordinates_mm(self, j, k):
        """(across, along) centres (nx, ny) of pair k's cells at position j in its tangent plane."""
        nx, ny = self.grid.across_cells, self.grid.along_cells
        xe, ye = _edges(self.across_half_mm, nx), _edges(self.along_half_mm, ny)
        x = 0.5 * (xe[1:] + xe[:-1])[:, None] + self.gap.across_shift_mm[j, k][None, :]
        return x, np.broadcast_to(0.5 * (ye[1:] + ye[:-1])[None, :], x.shape)

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

    def pattern(self, geom, member, raster=(48, 96)):
        """:func:`flank_pattern` of one member (cached)."""
        if (member, raster) not in self._patterns:
            self._patterns[member, raster] = flank_pattern(self, geom, member, raster)
        return self._patterns[member, raster]

    def to_json_dict(self, geom):
        ok = self.converged
        num = lambda v, ok_=True: float(v) if ok_ and np.isfinite(v) else None  # noqa: E731
        fractions = {m: self.pattern(geom, m).area_fraction for m in ("pinion", "gear")}
        return {
            "flank": self.flank,
            "torque_nm": self.torque_nm,
            "torque_note": "pinion torque; the moment of the contact forces about the pinion axis equals it",
            "pinion_angle_rad": [float(v) for v in self.pinion_angle],
            "status": list(self.status),
            "loaded_transmission_error_urad": [num(v * 1e6, o) for v, o in zip(self.loaded_te, ok)],
            "unloaded_transmission_error_urad": [num(v * 1e6) for v in self.unloaded_te],
            "tooth_pairs": [int(k) for k in self.tooth_pairs],
            "pair_normal_load_n": [[num(v, o) for v in row] for row, o in zip(self.pair_load_n, ok)],
            "pair_max_pressure_mpa": [[num(v, o) for v in row] for row, o in zip(self.pair_max_pressure_mpa, ok)],
            "contact_area_mm2": [num(v, o) for v, o in zip(self.contact_area_mm2, ok)],
            "pair_patch_semi_axes_mm": [[None if not np.all(np.isfinite(ab)) else [float(ab[0]), float(ab[1])]
                                         for ab in row] for row in self.patch_semi_axes_mm()],
            "pattern_area_fraction": {m: (None if f is None else float(f)) for m, f in fractions.items()},
            "grid": {"across_cells": self.grid.across_cells, "along_cells": self.grid.along_cells,
                     "across_half_extent_mm": self.across_half_mm, "along_half_extent_mm": self.along_half_mm},
            "solver": {"iterations": [int(v) for v in self.iterations],
                       "complementarity_residual": [num(v) for v in self.complementarity_residual],
                       "load_residual": [num(v) for v in self.load_residual],
                       "moment_residual": [num(abs(m / (self.torque_nm * 1e3) - 1.0), o)
                                           for m, o in zip(self.pinion_moment_nmm, ok)]},
            "notes": list(self.notes),
        }


class _Setup:
    """Everything of one (geometry, flank, errors, positions) that does not depend on the grid size."""

    def __init__(self, geom, flank, errors, positions, pairs, backend="auto"):
        self.geom, self.flank = geom, flank
        self.backend = tca.resolve_backend(backend)
        self.errors = tca.errors_array(errors)
        fr = tca.mesh_flank(geom, flank, self.errors, positions=positions, pairs=pairs, window_pitches=1,
                            backend=self.backend)
        ref = tca.reference_contact(geom, flank)
        ref_gear = tca.unknowns(ref.x).gear_angle_rad
        p1, p2 = geom.pitch_angles
        self.ks = np.arange(pairs) - pairs // 2
        self.phi1 = fr.pinion_angle[:positions]
        x = fr.unknowns.reshape(pairs, positions, 5).transpose(1, 0, 2)  # (N, P, 5) pair 0 unknowns
        status = np.asarray(fr.status, dtype=object).reshape(pairs, positions).T
        self.solved = np.array([[s != "failed" for s in row] for row in status])
        # the pair's tangency lies on both flanks: its patch is a surface contact that sizes the grid
        self.on_flank = np.array([[s in ("ok", "edge") for s in row] for row in status])
        # how far each tangency lies inside both blanks (mm): a patch within that distance of its
        # tangency is a surface contact that may size the grid; nearer an edge it is edge contact
        with np.errstate(invalid="ignore"):
            margin, _ = tca.boundary_margins(geom, flank, x)
        self.tangency_margin_mm = np.where(self.solved, margin, -np.inf)
        te = fr.transmission_error.reshape(pairs, positions).T
        active = fr.active.reshape(pairs, positions).T
        self.unloaded_te = np.array([te[j][active[j]][0] if active[j].any() else np.nan for j in range(positions)])
        # each pair's own rigid TE (its tangency, on or off the flanks): how far it stands open
        self.pair_te = np.where(self.solved, tca.unknowns(x).gear_angle_rad - self.ks[None, :] * p2 - ref_gear
                                + (geom.pinion.teeth / geom.gear.teeth) * (self.phi1[:, None] - ref.pinion_angle),
                                np.nan)
        n1, n2 = geom.pinion.teeth, geom.gear.teeth
        # the gear angle of the rigid envelope (the first pair to touch), else of the nearest solved pair
        te_any = np.where(np.isfinite(self.unloaded_te), self.unloaded_te,
                          np.array([_nearest_te(x[j], self.solved[j], self.ks, p2, ref, n1, n2, self.phi1[j])
                                    for j in range(positions)]))
        self.has_reference = np.isfinite(te_any)
        self.te_any = te_any
        self.gear_angle = te_any + ref_gear - (n1 / n2) * (self.phi1 - ref.pinion_angle)
        # pair k: pinion tooth 0 at phi1 - k p1, gear tooth 0 at phi2 + k p2 (tca.mesh_flank)
        self.pair_phi1 = self.phi1[:, None] - self.ks[None, :] * p1
        self.pair_phi2 = self.gear_angle[:, None] + self.ks[None, :] * p2
        x = np.where(self.solved[..., None], x, x[positions // 2, pairs // 2])  # placeholder where unsolved
        self.x = x
        self.n1_over_n2 = n1 / n2
        self.axes, self.origin = _principal_axes(geom, flank, x, self.pair_phi1, self.errors)
        mn = geom.normal_module_mm
        depth = (geom.pinion.tip_height_mm + geom.pinion.cutter_addendum_mm) / math.cos(geom.normal_pressure_angle)
        face = geom.pinion.face_width_mm / max(math.cos(geom.pinion.helix_angle), 0.3)
        self.max_along_mm = math.hypot(depth, face) + mn

    def surface_contacts(self, across_half_mm):
        """(N, P): pairs whose tangency is on the flanks and more than 3 grid half-widths inside
        both blanks (their patch sizes the grid); all on-flank pairs if none is."""
        deep = self.on_flank & (self.tangency_margin_mm > 3.0 * across_half_mm)
        return deep if deep.any() else self.on_flank

    def gap(self, xe, ye, need=None) -> PairGap:
        """The gap over the grid with cell edges xe (across), ye (along) for the (position, pair)s in ``need``."""
        geom, flank = self.geom, self.flank
        xc, yc = 0.5 * (xe[1:] + xe[:-1]), 0.5 * (ye[1:] + ye[:-1])
        X, Y = np.meshgrid(xc, yc, indexing="ij")
        coords = np.stack([X.ravel(), Y.ravel()], axis=-1)  # (cells, 2), cell = i * ny + j
        N, P = self.pair_phi1.shape
        n = coords.shape[0]
        need = self.solved & self.has_reference[:, None] if need is None else need & self.solved
        need &= self.has_reference[:, None]
        jj, kk = np.nonzero(need)
        out_s = np.full((N, P, n), OFF_FLANK_GAP_MM)
        out_in = np.zeros((N, P, n), dtype=bool)
        out_ds2, out_arm = np.zeros((N, P, n)), np.zeros((N, P, n))
        out_p1, out_p2 = np.full((N, P, n, 3), np.nan), np.full((N, P, n, 3), np.nan)
        out_lu = np.full((N, P, n, 2), np.nan)
        out_shift = np.zeros((N, P, yc.size))
        if jj.size == 0:
            return PairGap(out_s, out_in, out_ds2, out_arm, out_p1, out_p2, 1.0, 1.0, out_lu, out_shift)
        x = self.x[jj, kk]
        ex = lambda a: a[..., None]  # noqa: E731

        start = np.stack(tca.unknowns(x)._replace(gear_angle_rad=self.pair_phi2[jj, kk]), axis=-1)
        frames = (start, self.pair_phi1[jj, kk], self.origin[jj, kk], self.axes[jj, kk])

        def gap_at(c):
            return _cell_gaps(geom, flank, self.errors, frames, c, self.backend)

        # the grid follows the unloaded contact line: each along-column is centred on the
        # vertex of the parabola through the gap at xi = -d, 0, +d (d = the grid half-extent)
        d = float(xe[-1])
        probe = np.stack(np.broadcast_arrays(np.array([-d, 0.0, d])[None, :], yc[:, None]), axis=-1).reshape(-1, 2)
        h3 = gap_at(np.broadcast_to(probe, (jj.size,) + probe.shape)).gap_mm.reshape(jj.size, yc.size, 3)
        with np.errstate(invalid="ignore", divide="ignore"):
            curv = h3[..., 0] - 2 * h3[..., 1] + h3[..., 2]
            shift = np.where(curv > 0, 0.5 * d * (h3[..., 0] - h3[..., 2]) / curv, np.nan)
        shift = np.where(np.isfinite(shift), np.clip(shift, -3 * d, 3 * d), np.nan)
        shift = _fill_nan_rows(shift)
        c = np.broadcast_to(coords, (jj.size, n, 2)).copy()
        c[..., 0] += shift[:, np.arange(n) % yc.size]
        cg = gap_at(c)
        s, ds2, arm = cg.gap_mm, cg.gap_D_gear_angle, cg.pinion_arm_mm
        inside = cg.on_flanks.copy()
        gear_sign = (-1.0 if np.median(ds2[inside]) > 0 else 1.0) if inside.any() else 1.0
        pinion_sign = (1.0 if np.median(arm[inside]) > 0 else -1.0) if inside.any() else 1.0
        closure = -gear_sign * ds2
        arm_p = pinion_sign * arm
        inside &= (closure > 0) & (arm_p > 0)
        out_s[jj, kk] = np.where(inside, s, OFF_FLANK_GAP_MM)
        out_in[jj, kk] = inside
        out_ds2[jj, kk], out_arm[jj, kk] = np.where(inside, closure, 0.0), np.where(inside, arm_p, 0.0)
        out_p1[jj, kk], out_p2[jj, kk] = cg.pinion_point, cg.gear_point
        out_lu[jj, kk] = cg.pinion_lu
        out_shift[jj, kk] = shift
        return PairGap(out_s, out_in, out_ds2, out_arm, out_p1, out_p2, gear_sign, pinion_sign, out_lu, out_shift)


def _fill_nan_rows(a):
    """Each row's NaNs replaced by the nearest finite entry of that row (0 if none)."""
    out = a.copy()
    idx = np.arange(a.shape[-1])
    for r in range(a.shape[0]):
        ok = np.isfinite(a[r])
        out[r] = np.interp(idx, idx[ok], a[r, ok]) if ok.any() else 0.0
    return out


def _nearest_te(x, solved, ks, p2, ref, n1, n2, phi1):
    """TE of the solved pair nearest to pair 0 (used when no pair touches on the flanks)."""
    if not solved.any():
        return np.nan
    k = int(np.argmin(np.where(solved, np.abs(ks), 99)))
    return tca.unknowns(x[k]).gear_angle_rad - ks[k] * p2 - tca.unknowns(ref.x).gear_angle_rad + (n1 / n2) * (phi1 - ref.pinion_angle)


def _edges(half, n):
    return np.linspace(-half, half, n + 1)


def _tooth_blocks(setup, gap, tooth_p, tooth_g, ny, nx, need):
    """(N, P, ny, ny) tooth compliance (mm/N) of both members along the centre line of each grid."""
    N, P = setup.pair_phi1.shape
    centre = (nx // 2) * ny + np.arange(ny)  # the cells on xi ~ 0
    out = np.zeros((N, P, ny, ny))
    for j, k in zip(*np.nonzero(need)):
        if gap.in_flank[j, k].any():
            t = (_tooth_line_compliance(tooth_p, gap.pinion_point[j, k, centre])
                 + _tooth_line_compliance(tooth_g, gap.gear_point[j, k, centre]))
            # Maxwell reciprocity: the beam model is symmetric up to the coupling's cell averaging
            out[j, k] = 0.5 * (t + t.T)
    return out


@functools.lru_cache(maxsize=8)
def _halfspace_matrix(across_half_mm, along_half_mm, nx, ny, e_star_mpa):
    """The Love matrix of the uniform grid (the same for every pair and position of a run)."""
    m = halfspace.tensor_influence_matrix_mm_per_mpa(_edges(across_half_mm, nx), _edges(along_half_mm, ny),
                                                     e_star_mpa)
    m.setflags(write=False)
    return m


def _solve_cycle(setup, xe, ye, torque_nm, material, tooth_p, tooth_g, only=None, open_rad=None):
    """Solve the positions ``only`` (default all); pairs standing open by more than ``open_rad``
    of gear rotation (their rigid TE against the envelope) are not gridded: they cannot touch."""
    nx, ny = xe.size - 1, ye.size - 1
    N, P = setup.pair_phi1.shape
    need = np.zeros((N, P), dtype=bool)
    need[list(range(N)) if only is None else list(only)] = True
    if open_rad is not None:
        with np.errstate(invalid="ignore"):
            far = np.abs(setup.pair_te - setup.te_any[:, None]) > open_rad
        need &= ~far
    gap = setup.gap(xe, ye, need)
    cells = halfspace.tensor_grid(xe, ye)
    area = cells.area_mm2
    c_hs = _halfspace_matrix(float(xe[-1]), float(ye[-1]), nx, ny, material.e_star_mpa)
    line = np.arange(nx * ny) % ny  # along index of each cell
    torque_nmm = torque_nm * 1e3
    positions = range(N) if only is None else only
    tooth = _tooth_blocks(setup, gap, tooth_p, tooth_g, ny, nx, need)
    out = dict(p=np.zeros((N, P, nx * ny)), ok=np.zeros(N, bool), delta=np.full(N, np.nan),
               it=np.zeros(N, int), comp=np.full(N, np.nan), load=np.full(N, np.nan), msg=[""] * N,
               r2=np.full(N, np.nan))
    for j in positions:
        inside = gap.in_flank[j]
        if not inside.any():
            out["msg"][j] = "no contact"
            continue
        r1 = float(np.median(gap.pinion_arm_mm[j][inside]))
        r2 = float(np.median(gap.gear_closure_mm[j][inside]))
        w = np.where(inside, gap.gear_closure_mm[j], r2) / r2
        t = np.where(inside, gap.pinion_arm_mm[j], r1) / r1
        comp = _PairCompliance(c_hs, tooth[j], line, area)
        sol = lcp.solve_contact(comp, gap.gap_mm[j].ravel(), np.tile(area, P), torque_nmm / r1, w.ravel(),
                                t.ravel())
        out["p"][j] = sol.pressure_mpa.reshape(P, -1)
        out["ok"][j] = sol.converged
        out["delta"][j] = sol.approach_mm / r2
        out["it"][j] = sol.iterations
        out["comp"][j] = sol.complementarity_residual
        out["load"][j] = sol.load_residual
        out["msg"][j] = "ok" if sol.converged else "not converged"
    return gap, cells, out


class _PairCompliance(lcp.Compliance):
    """C of every pair: the half-space matrix (shared) plus that pair's tooth compliance
    T[line_a, line_b] area_b, where ``line`` is a cell's index along the contact line.

    Only the columns of the active cells are ever formed (the solver needs C[S, S] and
    C[:, S] p_S), so no dense block is built per position.
    """

    def __init__(self, c_hs, tooth, line, area):
        n = c_hs.shape[0]
        P = tooth.shape[0]
        object.__setattr__(self, "blocks", ())
        object.__setattr__(self, "slices", tuple(slice(k * n, (k + 1) * n) for k in range(P)))
        object.__setattr__(self, "symmetric", (False,) * P)
        object.__setattr__(self, "_c", c_hs)
        object.__setattr__(self, "_t", tooth)
        object.__setattr__(self, "_line", line)
        object.__setattr__(self, "_area", area)

    def diagonal(self):
        d = np.diag(self._c)
        return np.concatenate([d + t[self._line, self._line] * self._area for t in self._t])

    def solve_active(self, active, rhs):
        out = np.zeros_like(rhs)
        for k, sl in enumerate(self.slices):
            idx = np.flatnonzero(active[sl])
            if idx.size:
                li = self._line[idx]
                block = self._c[np.ix_(idx, idx)] + self._t[k][np.ix_(li, li)] * self._area[idx]
                try:  # symmetric positive definite on a uniform grid (equal cell areas, symmetric T)
                    out[sl.start + idx] = scipy.linalg.cho_solve(scipy.linalg.cho_factor(block, check_finite=False),
                                                                 rhs[sl][idx], check_finite=False)
                except np.linalg.LinAlgError:
                    out[sl.start + idx] = np.linalg.solve(block, rhs[sl][idx])
        return out

    def matvec_active(self, active, p):
        out = np.zeros_like(p)
        ny = self._t.shape[-1]
        for k, sl in enumerate(self.slices):
            idx = np.flatnonzero(active[sl])
            if idx.size:
                force = p[sl][idx] * self._area[idx]
                per_line = np.bincount(self._line[idx], weights=force, minlength=ny)  # N per along index
                out[sl] = self._c[:, idx] @ p[sl][idx] + (self._t[k] @ per_line)[self._line]
        return out


def _interior(p, in_flank, nx, ny, reach=2):
    """Loaded cells (..., nx, ny) farther than ``reach`` cells (8-neighbourhood) from any
    off-flank cell: cells near a blank boundary carry edge contact, which the blank (not the
    grid) truncates."""
    q = (p > 0).reshape(p.shape[:-1] + (nx, ny))
    interior = in_flank.reshape(q.shape).copy()
    lead = [(0, 0)] * (interior.ndim - 2)
    for _ in range(reach):
        pad = np.pad(interior, lead + [(1, 1), (1, 1)], constant_values=True)
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                interior &= pad[..., 1 + di:1 + di + nx, 1 + dj:1 + dj + ny]
    return q & interior


def _touches_edge(p, in_flank, nx, ny, surface):
    """(across, along): an interior loaded cell in the outermost row / column of a grid, among
    the (position, pair)s whose tangency is on the flanks (``surface``)."""
    q = _interior(p, in_flank, nx, ny) & surface[..., None, None]
    return bool(q[..., [0, -1], :].any()), bool(q[..., :, [0, -1]].any())


def _extent(p, in_flank, nx, ny, xe, ye, surface):
    """Half-extents (across, along) of the interior loaded cells of surface contacts, None if none."""
    q = _interior(p, in_flank, nx, ny) & surface[..., None, None]
    xc, yc = 0.5 * (xe[1:] + xe[:-1]), 0.5 * (ye[1:] + ye[:-1])
    hx, hy = 0.5 * (xe[1] - xe[0]), 0.5 * (ye[1] - ye[0])
    rows = q.any(axis=tuple(range(q.ndim - 2)) + (q.ndim - 1,))
    cols = q.any(axis=tuple(range(q.ndim - 1)))
    return (float(np.abs(xc[rows]).max() + hx) if rows.any() else None,
            float(np.abs(yc[cols]).max() + hy) if cols.any() else None)


def _one_blas_thread():
    """A context limiting BLAS to one thread: the LTCA's many small factorisations and products
    run 3x slower with OpenBLAS threads on a busy 2-core machine (docs/performance.md)."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # optional: without it BLAS keeps its own thread count
        import contextlib

        return contextlib.nullcontext()
    return threadpool_limits(limits=1, user_api="blas")


def analyze(geom, torque_nm, flank="right", errors=(0, 0, 0, 0, 0), positions=20, pairs=3,
            grid: GridOptions = GridOptions(), material: Material = Material(), backend="auto") -> LTCAResult:
    """Loaded TCA of one flank over one mesh cycle (``positions`` pinion angles over one pinion pitch).

    ``torque_nm``: the pinion torque (N m), > 0.  Returns an :class:`LTCAResult`; a position
    whose contact problem did not converge carries its status and no numbers.
    """
    with _one_blas_thread():
        return _analyze(geom, torque_nm, flank, errors, positions, pairs, grid, material, backend)


def _analyze(geom, torque_nm, flank, errors, positions, pairs, grid, material, backend) -> LTCAResult:
    torque_nm = float(torque_nm)
    if not (math.isfinite(torque_nm) and torque_nm > 0):
        raise ValueError(f"torque_nm = {torque_nm!r}: must be a finite number > 0")
    grid.check()
    setup = _Setup(geom, tca.check_flank(flank), errors, positions, pairs, backend)
    tooth_p = _member_tooth(geom, "pinion", material.pinion_e_mpa, material.pinion_nu)
    tooth_g = _member_tooth(geom, "gear", material.gear_e_mpa, material.gear_nu)
    nx, ny = grid.across_cells, grid.along_cells
    # 1. size the grid on the middle position
    mid = positions // 2
    probe = sorted({0, mid, positions - 1})
    X, Y = grid.initial_across_mm, setup.max_along_mm
    rotation = np.nan
    for _ in range(8):
        xe, ye = _edges(X, nx), _edges(Y, ny)
        gap, _, o = _solve_cycle(setup, xe, ye, torque_nm, material, tooth_p, tooth_g, only=probe)
        rotation = np.nanmax(np.abs(o["delta"][probe]))
        sizing = setup.surface_contacts(X)[probe]
        ex, ey = _extent(o["p"][probe], gap.in_flank[probe], nx, ny, xe, ye, sizing)
        if ex is None:
            break
        edge_x, edge_y = _touches_edge(o["p"][probe], gap.in_flank[probe], nx, ny, sizing)
        newX = 2.0 * X if edge_x else grid.margin * ex
        newY = min(setup.max_along_mm, 2.0 * Y if edge_y else grid.margin * ey)
        settled = abs(newX / X - 1) < 0.15 and abs(newY / Y - 1) < 0.15
        X, Y = newX, newY
        if settled:
            break
    notes = []
    # 2. the cycle, regridded while a patch reaches the grid edge inside the flank
    for attempt in range(grid.max_regrids + 1):
        xe, ye = _edges(X, nx), _edges(Y, ny)
        # a pair open by more than 3x the middle position's loaded rotation (plus 2 urad) cannot touch
        open_rad = 3.0 * rotation + 2e-6 if np.isfinite(rotation) else None
        gap, cells, o = _solve_cycle(setup, xe, ye, torque_nm, material, tooth_p, tooth_g, open_rad=open_rad)
        edge_x, edge_y = _touches_edge(o["p"][o["ok"]], gap.in_flank[o["ok"]], nx, ny,
                                       setup.surface_contacts(X)[o["ok"]])
        edge_y = edge_y and Y < setup.max_along_mm
        if not (edge_x or edge_y):
            break
        if attempt == grid.max_regrids:
            notes.append("the loaded patch still reaches the grid edge after the last regrid: "
                         "pressures near that edge are truncated")
            break
        X = 1.5 * X if edge_x else X
        Y = min(setup.max_along_mm, 1.5 * Y) if edge_y else Y
    area = cells.area_mm2
    ok = o["ok"]
    p = o["p"]
    loads = np.einsum("jkc,c->jk", p, area)
    moment = np.einsum("jkc,c,jkc->j", p, area, np.where(gap.in_flank, gap.pinion_arm_mm, 0.0))
    gear_rot = gap.gear_sign * o["delta"]
    ref = tca.reference_contact(geom, flank)
    te_rigid_ref = setup.gear_angle - tca.unknowns(ref.x).gear_angle_rad + setup.n1_over_n2 * (setup.phi1 - ref.pinion_angle)
    loaded_te = np.where(ok, te_rigid_ref + gear_rot, np.nan)
    status = ["ok" if ok[j] else ("no contact" if o["msg"][j] == "no contact" else "not converged")
              for j in range(positions)]
    return LTCAResult(
        flank=flank, torque_nm=torque_nm, pinion_angle=setup.phi1, tooth_pairs=setup.ks, status=status,
        loaded_te=loaded_te, unloaded_te=setup.unloaded_te,
        pair_load_n=np.where(ok[:, None], loads, np.nan),
        pair_max_pressure_mpa=np.where(ok[:, None], p.max(axis=-1), np.nan),
        contact_area_mm2=np.where(ok, ((p > 0) * area).sum(axis=(1, 2)), np.nan),
        pinion_moment_nmm=np.where(ok, moment, np.nan), iterations=o["it"],
        complementarity_residual=o["comp"], load_residual=o["load"], across_half_mm=float(X), along_half_mm=float(Y),
        grid=grid, pressure_mpa=p, gap=gap, cell_area_mm2=area, axes=setup.axes,
        tangency_unknowns=np.where(setup.solved[..., None], setup.x, np.nan), pair_pinion_angle=setup.pair_phi1,
        notes=notes)


# --------------------------------------------------------------------------------------------
# the contact pattern on each flank
# --------------------------------------------------------------------------------------------
@dataclass
class FlankPattern:
    """Max pressure over the cycle on a raster of one member's flank (tooth 0)."""

    member: str
    points: np.ndarray  # (n, 3) raster nodes on the flank, member frame
    weight_mm2: np.ndarray  # (n,) area of each node's raster cell
    max_pressure_mpa: np.ndarray  # (n,) 0 where never loaded
    area_fraction: float | None


def _flank_raster(geom, flank, member, shape):
    """Nodes of a (l, u) raster covering the member's flank between its four boundaries."""
    m = geom.member(member)
    mn = geom.normal_module_mm
    lo_l, hi_l = 0.0, 3.0 * (m.cutter_addendum_mm + m.tip_height_mm) / math.cos(geom.normal_pressure_angle)
    half_u = 1.5 * m.face_width_mm / max(math.cos(m.helix_angle), 0.3) + 4 * mn
    box = (lo_l, hi_l, -half_u, half_u)
    for n_l, n_u in ((40, 80), shape):
        l = np.linspace(box[0], box[1], n_l)
        u = np.linspace(box[2], box[3], n_u)
        L, U = np.meshgrid(l, u, indexing="ij")
        jet = geom.surface_jet(member, flank, L, U)
        margin = flank_boundaries.flank_margins(jet.point, L, m.blank()).margins.min(axis=-1)
        inside = margin >= 0
        if not inside.any():
            return None
        il, iu = np.nonzero(inside)
        dl, du = l[1] - l[0], u[1] - u[0]
        box = (max(lo_l, l[il.min()] - dl), l[il.max()] + dl, u[iu.min()] - du, u[iu.max()] + du)
    cell = (l[1] - l[0]) * (u[1] - u[0])
    weight = np.linalg.norm(np.cross(jet.point_D_lu[..., 0], jet.point_D_lu[..., 1]), axis=-1) * cell
    return jet.point[inside], weight[inside]


def flank_pattern(result: LTCAResult, geom, member, raster=(48, 96)) -> FlankPattern:
    """The union over the cycle of the loaded cells, with the max pressure, on a flank raster.

    Between two computed positions each pair's patch is swept by translating it with the
    tangency point (sub-steps no longer than a cell across), so a patch narrower than its
    travel between positions still paints a band, as the paper's patterns do.
    """
    from scipy.spatial import cKDTree

    r = _flank_raster(geom, result.flank, member, raster)
    if r is None:
        return FlankPattern(member, np.zeros((0, 3)), np.zeros(0), np.zeros(0), None)
    nodes, weight = r
    pts = result.gap.pinion_point if member == "pinion" else result.gap.gear_point  # (N, P, cells, 3)
    p = np.where(result.converged[:, None, None], result.pressure_mpa, 0.0)
    hx = result.across_half_mm / result.grid.across_cells
    hy = result.along_half_mm / result.grid.along_cells
    reach = math.hypot(hx, hy) * 1.05
    clouds, values = [], []
    N, P = p.shape[:2]
    for j in range(N):
        for k in range(P):
            on = p[j, k] > 0
            if not on.any():
                continue
            base = pts[j, k, on]
            clouds.append(base)
            values.append(p[j, k, on])
            if j + 1 < N and result.converged[j + 1]:
                centre = np.average(base, axis=0, weights=p[j, k, on])
                on2 = p[j + 1, k] > 0
                if on2.any():
                    shift = np.average(pts[j + 1, k, on2], axis=0, weights=p[j + 1, k, on2]) - centre
                    steps = int(min(50, math.ceil(np.linalg.norm(shift) / (2 * hx))))
                    for s in range(1, steps):
                        clouds.append(base + shift * (s / steps))
                        values.append(p[j, k, on])
    if not clouds:
        return FlankPattern(member, nodes, weight, np.zeros(len(nodes)), 0.0)
    cloud = np.concatenate(clouds)
    val = np.concatenate(values)
    tree = cKDTree(cloud)
    dist, idx = tree.query(nodes, k=min(6, len(cloud)), distance_upper_bound=reach)
    dist, idx = np.atleast_2d(dist.T).T, np.atleast_2d(idx.T).T
    valx = np.append(val, 0.0)
    pmax = np.where(np.isfinite(dist), valx[np.minimum(idx, len(val))], 0.0).max(axis=-1)
    frac = float(weight[pmax > 0].sum() / weight.sum())
    return FlankPattern(member, nodes, weight, pmax, frac)
