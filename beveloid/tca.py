"""Tooth contact analysis of crossed beveloid gears under the five assembly errors (Eqs 28-38).

Built on the generated kernels only (``beveloid.generated``): the tooth surfaces of Eqs 1-7
and the TCA system of Eq 38 with its exact Jacobians.

Conventions (the paper is silent on these; see docs/validation.md):

* Flanks are named after the signs of Eqs 1-3 (upper sign = left).  The left flank of the
  pinion meshes with the left flank of the gear (both are the same flank plane of the common
  rack, Eq 18).
* Normals are outward from each tooth, so the contact condition is n_f1 = -n_f2.
* Each member's frame S_i has its origin on the axis in the reference transverse section
  (where its profile shift equals x_t).  That section lies b_c (``reference_section_offset_mm``)
  below the working pitch circle, which passes through the pitch point P of the pitch-cone
  design; default b_c = 0.  Face widths are centred on the working pitch circle.
* Flank boundaries: face width (toe at -W/2, heel at +W/2 about the working pitch circle),
  tip cone (tip height ``addendum_coefficient * m_n`` above the rack pitch plane, parallel to
  the root cone), form limit l >= 0 (the start of the rack's straight edge; no fillet).
* Pair k (k = ..., -1, 0, 1, ...) is pinion tooth k with gear tooth k.  Because each pair's
  solution is pair 0's solution turned by whole tooth pitches, pair 0 is solved on the
  shifted pinion angles and the points are turned back into place.
* TE = phi'_2 - phi'_2,ref + (N1/N2)(phi'_1 - phi'_1,ref), the reference being the contact
  at the pitch point P of the aligned pair on the same flank.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

from .generated import tca_system, tooth_surface

FLANKS = ("left", "right")
STATUS_OK, STATUS_EDGE, STATUS_OUTSIDE, STATUS_FAILED = "ok", "edge", "outside", "failed"
_STATUS_CODES = {0: STATUS_OK, 1: STATUS_EDGE, 2: STATUS_OUTSIDE, 3: STATUS_FAILED}

ERROR_NAMES = ("dx_mm", "dy_mm", "dz_mm", "vertical_rad", "horizontal_rad")


@dataclass(frozen=True)
class Member:
    """One member's generating data and blank, in mm and rad."""

    teeth: int
    helix_angle: float
    cone_angle: float
    cutter_addendum_mm: float
    rack_shift_mm: float
    pitch_radius_mm: float
    working_pitch_radius_mm: float
    working_mounting_distance_mm: float
    reference_section_offset_mm: float
    face_width_mm: float
    tip_height_mm: float  # tip above the rack pitch plane, along the rack depth axis
    pitch_point_angle: float  # theta_i of the pitch point on the working pitch cone

    @property
    def axial_placement_mm(self) -> float:
        """d_w - b_c: where the S_i origin sits on the axis, from the common perpendicular."""
        return self.working_mounting_distance_mm - self.reference_section_offset_mm

    def surface_params(self, alpha_n, half_thickness):
        return (alpha_n, self.helix_angle, self.cone_angle, self.cutter_addendum_mm, half_thickness,
                self.rack_shift_mm, self.pitch_radius_mm)

    def tip_radius(self, z):
        """Tip cone radius at axial position z (S_i): parallel to the rack's pitch plane."""
        return (self.pitch_radius_mm + (self.tip_height_mm + self.rack_shift_mm) / math.cos(self.cone_angle)
                + z * math.tan(self.cone_angle))

    def root_radius(self, z):
        return (self.pitch_radius_mm + (self.rack_shift_mm - self.cutter_addendum_mm) / math.cos(self.cone_angle)
                + z * math.tan(self.cone_angle))

    @property
    def face_limits(self):
        """(toe, heel) axial limits in S_i, centred on the working pitch circle (z = b_c)."""
        c = self.reference_section_offset_mm
        w = self.face_width_mm / 2
        return (c - w, c + w) if self.cone_angle >= 0 else (c + w, c - w)


@dataclass(frozen=True)
class PairGeometry:
    """Everything the TCA needs: the designed pair in mm and rad."""

    normal_module_mm: float
    normal_pressure_angle: float
    offset_mm: float
    shaft_angle: float
    pinion: Member
    gear: Member

    @property
    def half_thickness_mm(self):
        return math.pi * self.normal_module_mm / 4

    @classmethod
    def from_design(cls, result) -> "PairGeometry":
        """From a :class:`beveloid.design.DesignResult`."""
        mn = result.normal_module_mm

        def member(m):
            return Member(
                teeth=int(m.teeth), helix_angle=m.helix_angle, cone_angle=m.cone_angle,
                cutter_addendum_mm=m.cutter_addendum_mm, rack_shift_mm=m.rack_shift_mm,
                pitch_radius_mm=m.reference_pitch_radius_mm, working_pitch_radius_mm=m.working_pitch_radius_mm,
                working_mounting_distance_mm=m.working_mounting_distance_mm,
                reference_section_offset_mm=m.reference_section_offset_mm, face_width_mm=m.face_width_mm,
                tip_height_mm=m.addendum_coefficient * mn, pitch_point_angle=m.pitch_point_angle)

        return cls(mn, result.normal_pressure_angle, result.offset_mm, result.shaft_angle,
                   member(result.pinion), member(result.gear))

    def kernel_params(self):
        """Arguments of the generated residual after the five errors."""
        p, g = self.pinion, self.gear
        return (self.normal_pressure_angle, self.half_thickness_mm,
                p.helix_angle, p.cone_angle, p.cutter_addendum_mm, p.rack_shift_mm, p.pitch_radius_mm,
                g.helix_angle, g.cone_angle, g.cutter_addendum_mm, g.rack_shift_mm, g.pitch_radius_mm,
                self.offset_mm, self.shaft_angle, p.axial_placement_mm, g.axial_placement_mm)

    @property
    def pitch_angles(self):
        return 2 * math.pi / self.pinion.teeth, 2 * math.pi / self.gear.teeth


def errors_array(errors) -> np.ndarray:
    """(dx_mm, dy_mm, dz_mm, vertical_rad, horizontal_rad) -> array (..., 5)."""
    e = np.asarray(errors, dtype=float)
    if e.shape[-1:] != (5,):
        raise ValueError(f"errors must have 5 components (dx, dy, dz, vertical, horizontal), got shape {e.shape}")
    return e


# --------------------------------------------------------------------------------------------
# kernels
# --------------------------------------------------------------------------------------------
def _residual_fn(flank):
    if flank not in FLANKS:
        raise ValueError(f"flank must be one of {FLANKS}, got {flank!r}")
    return getattr(tca_system, "residual_" + flank)


def evaluate(geom: PairGeometry, flank, x, phi1, errors):
    """Residual and Jacobians at unknowns x (..., 5), pinion angles phi1 (...), errors (..., 5)."""
    x = np.asarray(x, dtype=float)
    e = errors_array(errors)
    return _residual_fn(flank)(x[..., 0], x[..., 1], x[..., 2], x[..., 3], x[..., 4], phi1,
                               e[..., 0], e[..., 1], e[..., 2], e[..., 3], e[..., 4], *geom.kernel_params())


def surface(geom: PairGeometry, which, flank, l, u):
    m = geom.pinion if which == "pinion" else geom.gear
    fn = getattr(tooth_surface, "surface_" + flank)
    return fn(l, u, *m.surface_params(geom.normal_pressure_angle, geom.half_thickness_mm))


def surface_jacobian(geom, which, flank, l, u):
    m = geom.pinion if which == "pinion" else geom.gear
    fn = getattr(tooth_surface, "surface_derivatives_" + flank)
    return fn(l, u, *m.surface_params(geom.normal_pressure_angle, geom.half_thickness_mm))[0]


# --------------------------------------------------------------------------------------------
# batched Newton
# --------------------------------------------------------------------------------------------
@dataclass
class NewtonResult:
    x: np.ndarray  # (B, 5)
    converged: np.ndarray  # (B,) bool
    iterations: np.ndarray  # (B,) int
    residual_norm: np.ndarray  # (B,) mm-scaled


def _scaled(F, scale):
    """Residual in mm: positions as they are, normal components times a length scale."""
    Fs = F.copy()
    Fs[..., 3:] *= scale
    return Fs


def newton(geom, flank, x0, phi1, errors, tol_mm=1e-12, max_iter=25):
    """Batched Newton on Eq 38 with the exact Jacobian; every row is its own problem."""
    x = np.array(np.broadcast_to(x0, np.broadcast_shapes(np.shape(x0), np.shape(phi1) + (5,))), dtype=float)
    B = x.shape[:-1]
    phi1 = np.broadcast_to(np.asarray(phi1, float), B)
    errors = np.broadcast_to(errors_array(errors), B + (5,))
    scale = geom.gear.working_pitch_radius_mm
    # round-off floor of the position residual grows with the coordinates' size
    tol = max(tol_mm, 64 * np.finfo(float).eps * (abs(geom.gear.axial_placement_mm) + geom.offset_mm + scale))
    iters = np.zeros(B, dtype=int)
    done = np.zeros(B, dtype=bool)
    res = np.full(B, np.inf)
    active = ~done
    for it in range(max_iter + 1):
        idx = np.nonzero(active.ravel())[0]
        if idx.size == 0:
            break
        xa = x.reshape(-1, 5)[idx]
        F, J, _, _ = evaluate(geom, flank, xa, phi1.ravel()[idx], errors.reshape(-1, 5)[idx])
        r = np.abs(_scaled(F, scale)).max(axis=-1)
        res.ravel()[idx] = r
        ok = r <= tol
        done.ravel()[idx[ok]] = True
        if it == max_iter:
            break
        todo = ~ok & np.isfinite(r)
        if not todo.any():
            active = np.zeros(B, dtype=bool)
            active.ravel()[idx[todo]] = True
            break
        sub = idx[todo]
        try:
            step = np.linalg.solve(J[todo], -F[todo][..., None])[..., 0]
        except np.linalg.LinAlgError:
            step = np.stack([_safe_solve(Jk, -Fk) for Jk, Fk in zip(J[todo], F[todo])])
        xf = x.reshape(-1, 5)
        xf[sub] = xa[todo] + step
        iters.ravel()[sub] += 1
        active = np.zeros(B, dtype=bool)
        active.ravel()[sub] = True
    return NewtonResult(x, done, iters, res)


def _safe_solve(J, F):
    try:
        return np.linalg.solve(J, F)
    except np.linalg.LinAlgError:
        return np.full(5, np.nan)


# --------------------------------------------------------------------------------------------
# reference contact at the pitch point
# --------------------------------------------------------------------------------------------
def _point_at_radius(geom, which, flank, radius, z):
    """(l, u) of the flank point at the given radius in the transverse section z; polar angle."""
    m = geom.pinion if which == "pinion" else geom.gear
    l, u = m.cutter_addendum_mm / math.cos(geom.normal_pressure_angle), 0.0
    for _ in range(30):
        p, _, _ = surface(geom, which, flank, l, u)
        J = surface_jacobian(geom, which, flank, l, u)
        rad = math.hypot(p[0], p[1])
        F = np.array([rad - radius, p[2] - z])
        G = np.array([[(p[0] * J[0, 0] + p[1] * J[1, 0]) / rad, (p[0] * J[0, 1] + p[1] * J[1, 1]) / rad],
                      [J[2, 0], J[2, 1]]])
        d = np.linalg.solve(G, -F)
        l, u = l + d[0], u + d[1]
        if abs(d).max() < 1e-12 * max(1.0, radius):  # quadratic convergence: the last step was round-off
            break
    p, _, _ = surface(geom, which, flank, l, u)
    return l, u, math.atan2(p[1], p[0])


@dataclass(frozen=True)
class Reference:
    flank: str
    pinion_angle: float
    x: np.ndarray  # (l1, u1, l2, u2, phi2) at the pitch point, aligned


@functools.lru_cache(maxsize=64)
def reference_contact(geom: PairGeometry, flank: str) -> Reference:
    """Contact of the aligned pair at the pitch point P (the TE reference); cached per geometry."""
    p, g = geom.pinion, geom.gear
    l1, u1, psi1 = _point_at_radius(geom, "pinion", flank, p.working_pitch_radius_mm, p.reference_section_offset_mm)
    l2, u2, psi2 = _point_at_radius(geom, "gear", flank, g.working_pitch_radius_mm, g.reference_section_offset_mm)
    phi1 = p.pitch_point_angle - psi1
    phi2 = g.pitch_point_angle - psi2
    x0 = np.array([l1, u1, l2, u2, phi2])
    sol = newton(geom, flank, x0[None], np.array([phi1]), np.zeros((1, 5)))
    if not sol.converged[0]:
        raise RuntimeError(f"no contact at the pitch point on the {flank} flank (residual {sol.residual_norm[0]:.2e} mm)")
    return Reference(flank, phi1, sol.x[0])


# --------------------------------------------------------------------------------------------
# continuation and flank boundaries
# --------------------------------------------------------------------------------------------
def tangent(geom, flank, x, phi1, errors):
    """dx/dphi1 and dx/derrors at solutions x (implicit function theorem, exact Jacobians)."""
    F, J, Je, Jp = evaluate(geom, flank, x, phi1, errors)
    dphi = -np.linalg.solve(J, Jp[..., None])[..., 0]
    derr = -np.linalg.solve(J, Je)
    return dphi, derr


def solve_errors_homotopy(geom, flank, ref: Reference, errors, steps=4):
    """Carry the aligned pitch-point contact to the given error sets (B, 5) at phi1_ref."""
    errors = np.atleast_2d(errors_array(errors))
    B = errors.shape[0]
    x = np.broadcast_to(ref.x, (B, 5)).copy()
    phi1 = np.full(B, ref.pinion_angle)
    prev = np.zeros((B, 5))
    conv = np.ones(B, dtype=bool)
    for k in range(1, steps + 1):
        target = errors * (k / steps)
        _, derr = tangent(geom, flank, x, phi1, prev)
        guess = x + np.einsum("bij,bj->bi", derr, target - prev)
        sol = newton(geom, flank, guess, phi1, target)
        conv &= sol.converged
        x = np.where(sol.converged[:, None], sol.x, guess)
        prev = target
    return x, conv


def boundary_margins(geom, flank, x):
    """Signed distance (mm) of each contact point inside its flanks: min over both members.

    Returns (margin, which) where margin > 0 is inside, and which names the nearest boundary.
    """
    margins = []
    labels = []
    for which, lcol, ucol in (("pinion", 0, 1), ("gear", 2, 3)):
        m = geom.pinion if which == "pinion" else geom.gear
        p, _, _ = surface(geom, which, flank, x[..., lcol], x[..., ucol])
        z = p[..., 2]
        rad = np.hypot(p[..., 0], p[..., 1])
        toe, heel = m.face_limits
        lo, hi = min(toe, heel), max(toe, heel)
        margins += [x[..., lcol], m.tip_radius(z) - rad, z - lo, hi - z]
        labels += [f"{which} root/form", f"{which} tip", f"{which} {'toe' if toe < heel else 'heel'}",
                   f"{which} {'heel' if toe < heel else 'toe'}"]
    M = np.stack(margins, axis=-1)
    k = np.argmin(M, axis=-1)
    return np.take_along_axis(M, k[..., None], -1)[..., 0], np.asarray(labels)[k]


def classify(geom, flank, x, converged, edge_tol_mm=0.01):
    """Status codes: 0 ok, 1 edge, 2 outside, 3 failed."""
    margin, _ = boundary_margins(geom, flank, x)
    code = np.where(margin > edge_tol_mm, 0, np.where(margin >= -edge_tol_mm, 1, 2))
    code = np.where(converged & np.isfinite(margin), code, 3)
    return code


# --------------------------------------------------------------------------------------------
# path over the mesh
# --------------------------------------------------------------------------------------------
def solve_path(geom, flank, ref: Reference, x_start, errors, phi1_grid, coarse_step=None):
    """Solve pair 0 at the pinion angles phi1_grid (..., N) for error sets errors (..., 5).

    Continuation from phi1_ref outward in coarse steps (tangent predictor), then one batched
    Newton for all grid points from interpolated guesses.  x_start (..., 5) is the solution at
    phi1_ref for these errors.
    """
    errors = np.atleast_2d(errors_array(errors))
    B = errors.shape[0]
    grid = np.asarray(phi1_grid, float)
    N = grid.shape[-1]
    p1, _ = geom.pitch_angles
    step = coarse_step or p1 / 3
    lo, hi = grid.min() - ref.pinion_angle, grid.max() - ref.pinion_angle
    nodes_neg = np.arange(0.0, lo - step, -step)[1:] if lo < 0 else np.array([])
    nodes_pos = np.arange(0.0, hi + step, step)[1:] if hi > 0 else np.array([])
    nodes = {0.0: x_start}
    conv_nodes = {0.0: np.ones(B, bool)}
    for seq in (nodes_pos, nodes_neg):
        x = x_start.copy()
        prev = 0.0
        for t in seq:
            dphi, _ = tangent(geom, flank, x, np.full(B, ref.pinion_angle + prev), errors)
            guess = x + dphi * (t - prev)
            sol = newton(geom, flank, guess, np.full(B, ref.pinion_angle + t), errors)
            x = np.where(sol.converged[:, None], sol.x, guess)
            nodes[t] = x
            conv_nodes[t] = sol.converged
            prev = t
    keys = np.array(sorted(nodes))
    X = np.stack([nodes[k] for k in keys], axis=1)  # (B, K, 5)
    rel = grid - ref.pinion_angle
    rel = np.broadcast_to(rel, (B, N))
    guess = np.empty((B, N, 5))
    for b in range(B):
        for c in range(5):
            guess[b, :, c] = np.interp(rel[b], keys, X[b, :, c])
    sol = newton(geom, flank, guess, rel + ref.pinion_angle, errors[:, None, :])
    return sol


def _limits(geom):
    """Blank data per member for the compiled boundary check (see compiled._margin)."""
    rows = []
    for m in (geom.pinion, geom.gear):
        lo, hi = sorted(m.face_limits)
        rows.append([m.pitch_radius_mm, m.tip_height_mm + m.rack_shift_mm, math.cos(m.cone_angle),
                     math.tan(m.cone_angle), lo, hi, m.helix_angle, m.cone_angle, m.cutter_addendum_mm,
                     m.rack_shift_mm])
    return np.array(rows)


def newton_tolerance(geom, tol_mm=1e-12):
    """1e-12 mm, or the round-off floor of the position residual for large coordinates."""
    scale = geom.gear.working_pitch_radius_mm
    return max(tol_mm, 64 * np.finfo(float).eps * (abs(geom.gear.axial_placement_mm) + geom.offset_mm + scale))


def resolve_backend(backend):
    """'auto' -> 'compiled' when numba is installed, else 'numpy'."""
    from . import compiled
    from .errors import UserError

    if backend == "auto":
        return "compiled" if compiled.AVAILABLE else "numpy"
    if backend == "compiled" and not compiled.AVAILABLE:
        raise UserError("backend = compiled: numba is not installed; use backend numpy or pip install numba")
    if backend not in ("compiled", "numpy"):
        raise ValueError(f"backend must be auto, compiled or numpy, got {backend!r}")
    return backend


def solve_grid(geom, flank, errors, phi_grid, backend="auto", edge_tol_mm=0.01, max_iter=25, homotopy_steps=3):
    """Pair 0 for error sets (K, 5) x pinion angles (N,), any order.

    Returns unknowns (K, N, 5), status codes (K, N) (0 ok, 1 edge, 2 outside, 3 failed) and
    Newton iterations (K, N).  Both backends solve the same generated equations.  Error sets
    whose every point failed (the homotopy from the aligned contact lost track) are solved
    again with 4x, then 16x, as many homotopy steps.
    """
    errors = np.ascontiguousarray(np.atleast_2d(errors), dtype=float)
    x, code, iters = _solve_grid_once(geom, flank, errors, phi_grid, backend, edge_tol_mm, max_iter, homotopy_steps)
    for factor in (4, 16):
        lost = np.nonzero((code == 3).all(axis=1))[0]
        if lost.size == 0:
            break
        x2, c2, i2 = _solve_grid_once(geom, flank, errors[lost], phi_grid, backend, edge_tol_mm, max_iter,
                                      homotopy_steps * factor)
        x[lost], code[lost], iters[lost] = x2, c2, i2
    return x, code, iters


def _solve_grid_once(geom, flank, errors, phi_grid, backend, edge_tol_mm, max_iter, homotopy_steps):
    ref = reference_contact(geom, flank)
    phi_grid = np.asarray(phi_grid, dtype=float)
    order = np.argsort(phi_grid, kind="stable")
    grid = np.ascontiguousarray(phi_grid[order])
    K, N = errors.shape[0], grid.shape[0]
    if resolve_backend(backend) == "compiled":
        from . import compiled

        x = np.empty((K, N, 5))
        code = np.empty((K, N), dtype=np.int64)
        iters = np.empty((K, N), dtype=np.int64)
        compiled.sweep_paths(FLANKS.index(flank), np.ascontiguousarray(ref.x), ref.pinion_angle, errors, grid,
                             np.array(geom.kernel_params(), dtype=float), _limits(geom),
                             geom.gear.working_pitch_radius_mm, newton_tolerance(geom), max_iter, homotopy_steps,
                             edge_tol_mm, x, code, iters)
    else:
        x0, conv0 = solve_errors_homotopy(geom, flank, ref, errors, steps=homotopy_steps)
        sol = solve_path(geom, flank, ref, x0, errors, np.broadcast_to(grid, (K, N)))
        x, iters = sol.x, sol.iterations
        code = classify(geom, flank, x, sol.converged & conv0[:, None], edge_tol_mm)
    inv = np.empty_like(order)
    inv[order] = np.arange(N)
    return x[:, inv], code[:, inv], iters[:, inv]


@dataclass
class FlankResult:
    """One flank over the mesh: pairs x positions, flattened in pair-major order."""

    flank: str
    pinion_angle: np.ndarray
    gear_angle: np.ndarray
    transmission_error: np.ndarray
    pinion_contact: np.ndarray  # (n, 3) in S1
    gear_contact: np.ndarray  # (n, 3) in S2
    status: list
    tooth_pair: np.ndarray
    active: np.ndarray  # carries the contact (envelope of all pairs) at its pinion angle
    iterations: np.ndarray
    nearest_boundary: list
    te_peak_to_peak: float  # rad, over the active points; nan if none
    unknowns: np.ndarray = None  # (n, 5) pair 0's (l1, u1, l2, u2, phi'_2) as solved, for every point

    def to_json_dict(self):
        nan_to_none = lambda a: [None if not np.isfinite(v) else float(v) for v in a]  # noqa: E731
        pts = lambda P: [None if not np.all(np.isfinite(p)) else [float(c) for c in p] for p in P]  # noqa: E731
        return {
            "pinion_angle_rad": [float(v) for v in self.pinion_angle],
            "gear_angle_rad": nan_to_none(self.gear_angle),
            "transmission_error_rad": nan_to_none(self.transmission_error),
            "pinion_contact_mm": pts(self.pinion_contact),
            "gear_contact_mm": pts(self.gear_contact),
            "status": list(self.status),
            "tooth_pair": [int(k) for k in self.tooth_pair],
            "active": [bool(a) for a in self.active],
            "nearest_boundary": list(self.nearest_boundary),
        }


def _rotate_z(P, angle):
    c, s = np.cos(angle), np.sin(angle)
    out = P.copy()
    out[..., 0] = c * P[..., 0] - s * P[..., 1]
    out[..., 1] = s * P[..., 0] + c * P[..., 1]
    return out


def mesh_flank(geom: PairGeometry, flank: str, errors=(0, 0, 0, 0, 0), positions=200, pairs=3,
               edge_tol_mm=0.01, window_pitches=None, backend="auto"):
    """TCA of one flank over the mesh with neighbouring tooth pairs.

    Pinion angles: ``positions`` points spread over ``window_pitches`` pinion pitches (default:
    ``pairs``) centred on the reference contact; pairs k = -(pairs//2) .. pairs//2.
    """
    e = errors_array(errors).reshape(1, 5)
    ref = reference_contact(geom, flank)
    p1, p2 = geom.pitch_angles
    N1, N2 = geom.pinion.teeth, geom.gear.teeth
    window = (window_pitches or pairs) * p1
    phi1 = ref.pinion_angle + np.linspace(-window / 2, window / 2, positions)
    ks = np.arange(pairs) - pairs // 2
    # pair k at phi1 is pair 0 at phi1 - k p1
    shifted = (phi1[None, :] - ks[:, None] * p1).ravel()
    X, C, IT = solve_grid(geom, flank, e, shifted, backend, edge_tol_mm)
    x, code, iterations = X[0], C[0], IT[0]
    _, nearest = boundary_margins(geom, flank, x)
    kk = np.repeat(ks, positions)
    phi1_all = np.tile(phi1, pairs)
    phi2 = x[:, 4] - kk * p2  # gear tooth k is turned by -k p2 relative to tooth 0
    te = phi2 - ref.x[4] + (N1 / N2) * (phi1_all - ref.pinion_angle)
    # contact points of pair k, back in place in S1 / S2
    P1, _, _ = surface(geom, "pinion", flank, x[:, 0], x[:, 1])
    P2, _, _ = surface(geom, "gear", flank, x[:, 2], x[:, 3])
    P1 = _rotate_z(P1, kk * p1)
    P2 = _rotate_z(P2, -kk * p2)
    valid = code <= 1
    te_v = np.where(valid, te, np.nan)
    P1[~valid] = np.nan
    P2[~valid] = np.nan
    phi2_v = np.where(valid, phi2, np.nan)
    # envelope: the pair that constrains the gear most carries the contact
    sign = _gap_sign(geom, flank, ref)
    TE = te_v.reshape(pairs, positions)
    with np.errstate(invalid="ignore"):
        if sign > 0:
            env = np.nanmax(np.where(np.isnan(TE), -np.inf, TE), axis=0)
        else:
            env = np.nanmin(np.where(np.isnan(TE), np.inf, TE), axis=0)
    env = np.where(np.isfinite(env), env, np.nan)
    active = (np.abs(TE - env[None, :]) <= 1e-12 + 1e-9 * np.abs(env)[None, :]) & np.isfinite(TE)
    env_ok = env[np.isfinite(env)]
    ptp = float(env_ok.max() - env_ok.min()) if env_ok.size else float("nan")
    status = [_STATUS_CODES[int(c)] for c in code]
    return FlankResult(flank, phi1_all, phi2_v, te_v, P1, P2, status, kk, active.ravel(), iterations,
                       list(nearest), ptp, x)


def _gap_sign(geom, flank, ref):
    """+1 if turning the gear by +dphi2 opens the contact (so the contact pair is the max TE)."""
    F0, J, _, _ = evaluate(geom, flank, ref.x, ref.pinion_angle, np.zeros(5))
    # d(R_f1 - R_f2)/dphi2 is column 4 of the position rows; the gap grows along n_f1 when
    # R_f2 moves along +n_f1, i.e. (R_f1 - R_f2) moves along -n_f1
    _, n1, _ = surface(geom, "pinion", flank, ref.x[0], ref.x[1])
    c, s = math.cos(ref.pinion_angle), math.sin(ref.pinion_angle)
    nf1 = np.array([c * n1[0] - s * n1[1], s * n1[0] + c * n1[1], n1[2]])
    dgap = -J[:3, 4] @ nf1
    return 1.0 if dgap > 0 else -1.0


@dataclass
class TCAResult:
    geometry: PairGeometry
    errors: np.ndarray
    flanks: dict = field(default_factory=dict)
    backlash_um: float | None = None
    notes: list = field(default_factory=list)

    def to_json_dict(self):
        out = {
            "errors": dict(zip(("dx_mm", "dy_mm", "dz_mm", "vertical_deg", "horizontal_deg"),
                               [float(self.errors[0]), float(self.errors[1]), float(self.errors[2]),
                                math.degrees(self.errors[3]), math.degrees(self.errors[4])])),
            "flanks": {k: v.to_json_dict() for k, v in self.flanks.items()},
            "te_peak_to_peak_urad": {k: (None if not np.isfinite(v.te_peak_to_peak) else v.te_peak_to_peak * 1e6)
                                     for k, v in self.flanks.items()},
        }
        if self.backlash_um is not None:
            out["backlash_um"] = None if not np.isfinite(self.backlash_um) else self.backlash_um
        out["notes"] = list(self.notes)
        return out


def pitch_point_notes(geom: PairGeometry, flank: str, edge_tol_mm=0.01):
    """Why an aligned flank may show no contact: the pitch point P lies off a member's active flank."""
    ref = reference_contact(geom, flank)
    margin, which = boundary_margins(geom, flank, ref.x[None])
    if margin[0] >= -edge_tol_mm:
        return []
    return [f"{flank} flank: the pitch point P lies {-margin[0]:.3f} mm beyond the {which[0]} boundary, so the "
            f"aligned contact near P is off the active flank (the working pitch circle is outside the active "
            f"profile: check the profile shifts and the working pressure angle of the design)"]


def backlash(geom: PairGeometry, errors=(0, 0, 0, 0, 0), backend="auto"):
    """Circumferential backlash (um) at the gear's working pitch radius, from a two-flank TCA.

    Left and right contacts are solved at the same pinion angle; the free angle of the gear
    between them, reduced modulo the gear pitch, times r_w2.  Positive: play; negative:
    the flanks would interfere.
    """
    e = errors_array(errors).reshape(1, 5)
    _, p2 = geom.pitch_angles
    angles = {}
    signs = {}
    refs = {fl: reference_contact(geom, fl) for fl in FLANKS}
    phi1 = refs["left"].pinion_angle
    for fl in FLANKS:
        ref = refs[fl]
        X, C, _ = solve_grid(geom, fl, e, np.array([phi1]), backend)
        if C[0, 0] == 3:  # not converged; off-flank points still define the surfaces' play
            return float("nan")
        angles[fl] = X[0, 0, 4]
        signs[fl] = _gap_sign(geom, fl, ref)
    if signs["left"] == signs["right"]:
        raise RuntimeError("both flanks open in the same direction: flank orientation is inconsistent")
    # left contact allows the gear to move toward sign_left; the right contact stops it
    play = (angles["right"] - angles["left"]) * signs["left"]
    play = (play + p2 / 2) % p2 - p2 / 2
    return play * geom.gear.working_pitch_radius_mm * 1e3


def analyze(geom: PairGeometry, errors=(0, 0, 0, 0, 0), flanks=FLANKS, positions=200, pairs=3, edge_tol_mm=0.01,
            backend="auto"):
    """TCA of the given flanks over the mesh; the two-flank backlash when both flanks are solved."""
    e = errors_array(errors)
    res = TCAResult(geom, e)
    for fl in flanks:
        res.flanks[fl] = mesh_flank(geom, fl, e, positions=positions, pairs=pairs, edge_tol_mm=edge_tol_mm,
                                    backend=backend)
        res.notes += pitch_point_notes(geom, fl, edge_tol_mm)
    if set(flanks) == set(FLANKS):
        res.backlash_um = backlash(geom, e, backend=backend)
    return res


def sensitivity(geom: PairGeometry, flank: str, errors=(0, 0, 0, 0, 0), pinion_angle=None):
    """Exact first-order derivatives at one mesh position (implicit function theorem).

    Returns dict with 'unknowns_D_errors' (5x5: d(l1,u1,l2,u2,phi2)/d(errors)),
    'pinion_contact_D_errors' (3x5, mm per error unit), 'gear_contact_D_errors' (3x5) and
    'gear_angle_D_errors' (5,), at the contact for the given errors and pinion angle
    (default: the reference pinion angle).
    """
    e = errors_array(errors).reshape(1, 5)
    ref = reference_contact(geom, flank)
    x0, conv = solve_errors_homotopy(geom, flank, ref, e)
    phi1 = ref.pinion_angle if pinion_angle is None else pinion_angle
    sol = solve_path(geom, flank, ref, x0, e, np.array([[phi1]]))
    x = sol.x[0, 0]
    _, derr = tangent(geom, flank, x[None], np.array([phi1]), e)
    derr = derr[0]
    J1 = surface_jacobian(geom, "pinion", flank, x[0], x[1])
    J2 = surface_jacobian(geom, "gear", flank, x[2], x[3])
    return {
        "x": x, "pinion_angle": phi1, "converged": bool(sol.converged[0, 0] and conv[0]),
        "unknowns_D_errors": derr,
        "pinion_contact_D_errors": J1 @ derr[0:2],
        "gear_contact_D_errors": J2 @ derr[2:4],
        "gear_angle_D_errors": derr[4],
    }
