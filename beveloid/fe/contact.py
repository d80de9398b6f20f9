"""The FE tooth as the loaded contact sees it: compliance between flank points and root stress.

``FeTooth(data, flank)`` holds one member's :class:`beveloid.fe.tooth.ToothData` for the loaded
flank.  Flank points (member frame, tooth 0) are mapped onto the load grid by their axial position
z and their radius (bilinear weights W, points x grid nodes; outside the grid: its edge), so that

* ``line_compliance(points)`` = W C W^T (mm/N), the same interface as the plate's
  ``ltca.model.compliance.MemberTooth``: no FE solve per position, only this interpolation;
* ``root_stress(points, forces_n)``: the fillet stress tensors S W^T f superposed over the cell
  forces; the largest max-principal stress in the fillet on the loaded side (tension) with where
  it is (z, height above the root cone), and the most compressive min-principal stress in the
  other fillet.

The fillet stress tensors are the **read-out** of :func:`beveloid.fe.tooth.tooth_data`: at the points of a
read grid fixed by the geometry (:func:`read_grid`), each a local least-squares fit of the nodes' tensors
around it, quadratic along the fillet's profile (:func:`readout_matrix`): the root stress the LTCA reports,
the rating's local S_F divides by and optimize ranks by is their largest principal stress.

C is the FE compliance of :mod:`beveloid.fe.tooth` (local deformation removed) made positive
semi-definite: its eigenvalues below zero (a load at the root of a tooth on a rim stiffer than
the half-space subtracted from it) are set to zero.  Fillet nodes nearer than the reading depth to
a load-grid node that the load set loads, or to its neighbours up and down the profile, are left out
of its root stress (they see that point force's local stress); a node near only other grid nodes
counts, so a short fillet under the flank's lowest grid rows still reads the stress of loads higher up.
"""
from __future__ import annotations

import math
import typing

import numpy as np

from ..names import FLANKS
from . import lines, principal

__all__ = ["FeTooth", "READ_FACE_PER_MODULE", "READ_MIN_MESH_ELEMENTS", "READ_MIN_NODES", "READ_PROFILE_PER_FILLET_SIZE", "READ_STEP_FACE_PER_MODULE",
           "READ_STEP_PROFILE_PER_FILLET_SIZE", "RootStress", "read_grid", "readout_matrix", "readout_window_mm",
           "tooth_arrays"]

#: fillet nodes per block of fe.principal.extreme's bound (docs/performance.md, The FE tooth)
BLOCK_NODES = 32


class RootStress(typing.NamedTuple):
    tension_mpa: float  # largest max-principal stress in the loaded side's fillet
    z_mm: float
    height_mm: float
    compression_mpa: float  # most compressive min-principal stress in the other fillet


def tooth_arrays(data, flank: str) -> dict:
    """The arrays :class:`FeTooth` derives from ``data`` (a ToothData) for ``flank``: ``compliance_mm_per_n``
    (C made positive semi-definite), ``near`` (2, G, nf) uint8 and per fillet i (0 the loaded side's, 1 the
    other's) ``order_i``, ``bound_i``, ``top_i`` (:func:`beveloid.fe.principal.fillet`).  They depend on the data
    alone: :mod:`beveloid.fe.cache` keeps them in the data's entry, so that a tooth is built without them.
    The reading depth's reach is widened by the data's read-out window (``data.smoothing_mm``, along the face
    and the profile, :func:`readout_matrix`: a read point stands for the nodes within its window)."""
    index = FLANKS.index(flank)
    c = np.asarray(data.compliance_mm_per_n[index], dtype=float)
    lam, vec = np.linalg.eigh(0.5 * (c + c.T))
    out = {"compliance_mm_per_n": (vec * np.maximum(lam, 0.0)) @ vec.T}
    # a fillet node nearer a loaded load-grid node than the reading depth sees that point force's
    # local (singular) stress, not the tooth's: near[s][c, i] marks fillet node i of fillet s within
    # the reading depth of grid node c or of its neighbours up and down the profile, left out of a load
    # set that loads c.  The neighbours: a contact lumped onto c stands for a load spread over the grid
    # rows beside it, and whether its lower neighbour (the form limit's row) gets a weight depends on
    # where the contact grid's cells fall; a fillet node just beyond the depth of c then read c's point
    # force or did not (issue 57: a design's pinion root stress 1086 MPa on one contact grid, 685-814 on
    # the others)
    points = np.asarray(data.points_mm[index])
    ns, nz = points.shape[:2]
    grid = points.reshape(-1, 3)
    reach = float(np.max(data.depth_mm[index])) + float(np.hypot(*np.asarray(data.smoothing_mm, dtype=float)))
    fp = np.asarray(data.fillet_points_mm)
    within = (np.linalg.norm(fp[:, None, :, :] - grid[None, :, None, :], axis=-1) <= reach).reshape(2, ns, nz, -1)
    spread = within.copy()
    spread[:, 1:] |= within[:, :-1]
    spread[:, :-1] |= within[:, 1:]
    near = np.ascontiguousarray(spread.reshape(2, ns * nz, -1).astype(np.uint8))
    out["near"] = near
    stress = np.asarray(data.stress_mpa_per_n[index])
    for i, (s, sign) in enumerate(zip((index, 1 - index), (1.0, -1.0))):
        # the nodes along the face, then up it: a block of BLOCK_NODES neighbours
        order = np.lexsort((np.asarray(data.fillet_height_mm[s]), fp[s][:, 2])).astype(np.int64)
        f = principal.fillet(np.ascontiguousarray(stress[s]), sign, order, BLOCK_NODES, near[s])
        out[f"order_{i}"], out[f"bound_{i}"], out[f"top_{i}"] = f.order, f.bound, f.top
    return out


#: the read-out's windows (:func:`readout_matrix`): along the face +- READ_FACE_PER_MODULE m_n, along the
#: fillet's profile +- READ_PROFILE_PER_FILLET_SIZE fillet elements at refinement 1 (``fe.mesh.mesh_sizes``),
#: the same physical window at every refinement ...
READ_FACE_PER_MODULE = 0.15
READ_PROFILE_PER_FILLET_SIZE = 1.0
#: ... but at least +- READ_MIN_MESH_ELEMENTS of the mesh's own fillet elements along the profile (a coarsened
#: mesh's window widens, both ways, so that the P2 node rows half an element apart at 0 and +-0.5 element
#: carry weight: three rows for the quadratic)
READ_MIN_MESH_ELEMENTS = 0.75
#: the read grid's steps (:func:`read_grid`): along the face READ_STEP_FACE_PER_MODULE m_n, along the
#: profile READ_STEP_PROFILE_PER_FILLET_SIZE fillet elements at refinement 1
READ_STEP_FACE_PER_MODULE = 0.1
READ_STEP_PROFILE_PER_FILLET_SIZE = 0.15
#: a read point with fewer nodes of positive weight in its window than this takes its nearest node's value
READ_MIN_NODES = 6
#: fine samples along each section's fillet profile that the read grid is placed on
_PROFILE_SAMPLES = 513


def readout_window_mm(normal_module_mm: float, fillet_size_mm: float, mesh_fillet_mm: float | None = None) -> tuple:
    """(along the face, along the profile) mm: the half-widths of the read-out's window of a member of normal
    module ``normal_module_mm`` whose fillet elements are ``fillet_size_mm`` at refinement 1 (``fe.mesh.mesh_sizes``):
    :data:`READ_FACE_PER_MODULE` m_n and :data:`READ_PROFILE_PER_FILLET_SIZE` times that size, the same physical
    window at every refinement; both widened where the profile's would be narrower than
    :data:`READ_MIN_MESH_ELEMENTS` of the mesh's own fillet elements ``mesh_fillet_mm`` (a coarsened tooth: its
    window still holds three node rows)."""
    widen = 1.0 if mesh_fillet_mm is None else max(1.0, READ_MIN_MESH_ELEMENTS * float(mesh_fillet_mm)
                                                    / (READ_PROFILE_PER_FILLET_SIZE * float(fillet_size_mm)))
    return (widen * READ_FACE_PER_MODULE * float(normal_module_mm),
            widen * READ_PROFILE_PER_FILLET_SIZE * float(fillet_size_mm))


def read_grid(sampler, flank: str, step_face_mm: float, step_profile_mm: float) -> tuple:
    """(points (n, 3), profile tangents (n, 3), face tangents (n, 3)) mm, unit: the read grid of the ``flank``
    fillet of tooth 0 (member frame): sections along the face ``step_face_mm`` apart (toe and heel included),
    in each section points ``step_profile_mm`` apart in arc length along the fillet's profile from the root
    cone (s = 0) to the form limit (s = 1), both ends included.  Fixed by the geometry and the member's module
    and fillet size, not by the mesh: every mesh of the member is read at the same points.  The profile
    tangent points up the fillet; the face tangent is the surface's direction across the sections, orthogonal
    to it."""
    z0, z1 = sampler.z_range_mm
    z = np.linspace(z0, z1, int(math.ceil((z1 - z0) / step_face_mm - 1e-9)) + 1)
    s = np.linspace(0.0, 1.0, _PROFILE_SAMPLES)
    dz = 1e-3 * step_face_mm
    prof = sampler.fillet_points(flank, s, z)  # (ns, nz, 3)
    ahead = sampler.fillet_points(flank, s, z + dz)
    arc = np.concatenate([np.zeros((1, len(z))), np.cumsum(np.linalg.norm(np.diff(prof, axis=0), axis=-1), axis=0)])
    points, tangents, across = [], [], []
    for k in range(len(z)):
        a = arc[:, k]
        at = np.linspace(0.0, a[-1], int(math.ceil(a[-1] / step_profile_mm - 1e-9)) + 1)
        p = np.stack([np.interp(at, a, prof[:, k, c]) for c in range(3)], axis=1)
        q = np.stack([np.interp(at, a, ahead[:, k, c]) for c in range(3)], axis=1)
        i = np.clip(np.searchsorted(a, at, side="right") - 1, 0, len(a) - 2)
        t = prof[i + 1, k] - prof[i, k]
        t /= np.linalg.norm(t, axis=1)[:, None]
        b = (q - p) / dz
        b -= np.einsum("ij,ij->i", b, t)[:, None] * t
        b /= np.linalg.norm(b, axis=1)[:, None]
        points.append(p), tangents.append(t), across.append(b)
    return np.concatenate(points), np.concatenate(tangents), np.concatenate(across)


def readout_matrix(read_points_mm, profile_tangents, face_tangents, node_points_mm, face_mm: float, profile_mm: float):
    """(n_read, n_nodes) scipy CSR: row r the weights of a local least-squares fit (moving least squares) of the
    nodes' values around read point r, evaluated there: s(u, v) = c0 + c1 u + c2 u^2 + c3 v in the read point's
    tangent frame (u along the fillet's profile, v along the face: the nodes' offsets projected on
    ``profile_tangents`` and ``face_tangents``), over the nodes with |u| < ``profile_mm`` and |v| < ``face_mm``
    (and within ``profile_mm`` of the tangent plane), each weighted by (1 - (u / profile_mm)^2)^2 (1 - (v /
    face_mm)^2)^2, a weight that falls to zero at the window's edge, so that the fit moves continuously as nodes
    move in and out of it.  Linear in the nodes' values (superposition holds); exact for a field quadratic along
    the profile and linear along the face.  A read point with fewer than :data:`READ_MIN_NODES` nodes of
    positive weight takes its nearest node's value."""
    import scipy.sparse
    from scipy.spatial import cKDTree

    r = np.asarray(read_points_mm, dtype=float)
    x = np.asarray(node_points_mm, dtype=float)
    t, b = np.asarray(profile_tangents, dtype=float), np.asarray(face_tangents, dtype=float)
    tree = cKDTree(x)
    pairs = cKDTree(r).sparse_distance_matrix(tree, math.hypot(face_mm, profile_mm) * (1.0 + 1e-9), output_type="ndarray")
    i, j = pairs["i"].astype(np.int64), pairs["j"].astype(np.int64)
    d = x[j] - r[i]
    u = np.einsum("ij,ij->i", d, t[i]) / profile_mm
    v = np.einsum("ij,ij->i", d, b[i]) / face_mm
    off = np.linalg.norm(d - (u * profile_mm)[:, None] * t[i] - (v * face_mm)[:, None] * b[i], axis=1)
    inside = (np.abs(u) < 1.0) & (np.abs(v) < 1.0) & (off <= profile_mm)
    i, j, u, v = i[inside], j[inside], u[inside], v[inside]
    w = (1.0 - u * u) ** 2 * (1.0 - v * v) ** 2
    a = np.column_stack([np.ones(len(i)), u, u * u, v])
    normal = np.stack([np.bincount(i, weights=w * a[:, p] * a[:, q], minlength=len(r))
                       for p in range(4) for q in range(4)], axis=1).reshape(len(r), 4, 4)
    # the fit's value at the read point: row 0 of (A^T W A)^+ A^T W, rank-deficient windows included
    coef = np.einsum("pk,pk->p", np.linalg.pinv(normal, rcond=1e-10)[i, 0], a) * w
    alone = np.bincount(i, minlength=len(r)) < READ_MIN_NODES
    keep = ~alone[i]
    nearest = tree.query(r[alone])[1]
    rows = np.concatenate([i[keep], np.flatnonzero(alone)])
    cols = np.concatenate([j[keep], np.asarray(nearest, dtype=np.int64).reshape(-1)])
    vals = np.concatenate([coef[keep], np.ones(int(alone.sum()))])
    return scipy.sparse.csr_matrix((vals, (rows, cols)), shape=(len(r), len(x)))


class FeTooth:
    """One member's FE tooth on one flank (see the module docstring)."""

    def __init__(self, data, flank: str, arrays: dict | None = None):
        if flank not in FLANKS:
            raise ValueError(f"flank = {flank!r}: must be one of {', '.join(FLANKS)}")
        self.data = data
        self.index = FLANKS.index(flank)
        a = tooth_arrays(data, flank) if arrays is None else arrays
        self.compliance_mm_per_n = a["compliance_mm_per_n"]
        self.radius_mm = np.asarray(data.radius_mm[self.index])  # (ns, nz)
        self.z_mm = np.asarray(data.z_mm)
        # as fe.lines.corners reads them
        self._radius, self._z = np.ascontiguousarray(self.radius_mm, dtype=float), np.ascontiguousarray(self.z_mm, dtype=float)
        self._spare = np.ascontiguousarray(data.points_mm[self.index][0, 0], dtype=float)
        self.stress = np.asarray(data.stress_mpa_per_n[self.index])  # (2, nf, 6, G)
        self.near = a["near"]
        # the stress operators (rows node-major, 6 components, G columns) of the loaded side's fillet (0)
        # and the other's (1), with their bounds, blocks and near-matrices (fe.principal.extreme)
        self.sides = (self.index, 1 - self.index)
        self.fillets = tuple(principal.Fillet(np.ascontiguousarray(self.stress[s]), a[f"bound_{i}"], a[f"top_{i}"],
                                              a[f"order_{i}"], BLOCK_NODES, self.near[s])
                             for i, s in enumerate(self.sides))

    def corners(self, points) -> tuple:
        """(nodes (n, 4) int, weights (n, 4)): the four load-grid nodes (profile-major) of each point (n, 3) and
        their bilinear weights (:func:`beveloid.fe.lines.corners`); weights of zero for a point that is not
        finite."""
        p = np.ascontiguousarray(points, dtype=float).reshape(-1, 3)
        nodes, w = np.empty((p.shape[0], 4), dtype=np.int64), np.empty((p.shape[0], 4))
        # a point off the surfaces (NaN: a cell of a pair without contact) carries no load: zero weights,
        # placed anywhere finite so that no index is made of a NaN
        lines.functions().corners(p, self._radius, self._z, self._spare, nodes, w)
        return nodes, w

    def weights(self, points) -> np.ndarray:
        """(n, G) the bilinear weights of the load grid's nodes for points (n, 3) (:meth:`corners`)."""
        nodes, w = self.corners(points)
        W = np.zeros((nodes.shape[0], self.radius_mm.size))
        W[np.arange(nodes.shape[0])[:, None], nodes] = w
        return W

    def line_compliance(self, points) -> np.ndarray:
        return self.line_compliances(np.asarray(points, dtype=float)[None])[0]

    def line_compliances(self, points) -> np.ndarray:
        """(Q, n, n) W C W^T of Q point sets (Q, n, 3): each point's four load-grid nodes gather their rows
        and entries of C (:mod:`beveloid.fe.lines`: the dense product's sums, in another order)."""
        p = np.asarray(points, dtype=float)
        Q, n = p.shape[:2]
        nodes, w = self.corners(p.reshape(-1, 3))
        out = np.empty((Q, n, n))
        lines.functions().line_compliances(np.ascontiguousarray(self.compliance_mm_per_n), nodes.reshape(Q, n, 4),
                                           w.reshape(Q, n, 4), out)
        return out

    def loads(self, points, forces_n) -> np.ndarray:
        """(Q, G) the load-grid node forces g = W^T f of Q load sets: ``points`` (Q, n, 3), ``forces_n``
        (Q, n) (a non-finite force is none)."""
        p = np.asarray(points, dtype=float)
        Q, G = p.shape[0], self.radius_mm.size
        f = np.nan_to_num(np.asarray(forces_n, dtype=float)).reshape(Q, -1)
        # the points that carry a force only (a contact grid's loaded cells, a third of them or fewer): a
        # point of no force adds zeros to its nodes, so the sums are the same, bit for bit (issue 59)
        live = f != 0.0
        nodes, w = self.corners(p.reshape(Q, -1, 3)[live])
        at = (nodes + G * np.nonzero(live)[0][:, None]).ravel()
        return np.bincount(at, weights=(w * f[live][:, None]).ravel(), minlength=Q * G).reshape(Q, G)

    def counted(self, g) -> np.ndarray:
        """(2, nf) the fillet nodes (0 the loaded side's fillet, 1 the other's) that count in the root
        stress of one load set g (G,): those not within the reading depth of a grid node it loads."""
        loaded = np.asarray(g, dtype=float) != 0.0
        return np.stack([~np.any(self.near[s][loaded], axis=0) for s in self.sides])

    def along_face(self, points, forces_n, bins: int = 24):
        """(z_mm (bins,), stress (bins,)): the loaded fillet's largest max-principal stress in each of
        ``bins`` equal slices of the face (nan where a slice holds no counted node)."""
        g = np.ascontiguousarray(self.loads(np.asarray(points, dtype=float)[None],
                                            np.asarray(forces_n, dtype=float)[None]))
        counted = self.counted(g[0])[0]
        z = self.data.fillet_points_mm[self.index][:, 2]
        edges = np.linspace(self.z_mm[0], self.z_mm[-1], bins + 1)
        slot = np.clip(np.searchsorted(edges, z) - 1, 0, bins - 1).astype(np.int64)
        out = np.empty(bins)
        principal.functions().slice_extremes(self.fillets[0], g, 0, 1.0, counted, slot, out)
        return 0.5 * (edges[1:] + edges[:-1]), out

    def root_stress(self, points, forces_n) -> RootStress:
        """The root stress of this tooth under normal forces (N) at flank points (see the module docstring)."""
        r = self.root_stresses(np.asarray(points, dtype=float)[None], np.asarray(forces_n, dtype=float)[None])
        return RootStress(*(float(v[0]) for v in r))

    def root_stresses(self, points, forces_n, compression=True) -> RootStress:
        """:meth:`root_stress` of Q load sets at once (``points`` (Q, n, 3), ``forces_n`` (Q, n)): a
        RootStress of (Q,) arrays: the extreme principal stresses by :func:`beveloid.fe.principal.extreme`
        (each set's tensors over its non-zero node loads, only at the nodes whose bound can reach them);
        NaN (and no place) for a set whose every fillet node lies within the reading depth of its loads.
        ``compression=False``: the other fillet's compressive extreme is not sought (NaN; the tolerance box
        and optimize read the tension alone), the rest the same to the last bit."""
        g = np.ascontiguousarray(self.loads(points, forces_n))
        Q = g.shape[0]
        fn = principal.functions()
        out = []
        for side, sign in ((0, 1.0), (1, -1.0))[:2 if compression else 1]:
            node, value = np.zeros(Q, dtype=np.int64), np.full(Q, np.nan)
            fn.extreme(self.fillets[side], g, sign, node, value)
            out.append((node, value))
        (k, tension), compression = out[0], (out[1][1] if compression else np.full(Q, np.nan))
        found = k >= 0
        where = np.where(found[:, None], self.data.fillet_points_mm[self.index][np.maximum(k, 0)], np.nan)
        height = np.where(found, np.asarray(self.data.fillet_height_mm[self.index])[np.maximum(k, 0)], np.nan)
        return RootStress(tension, where[:, 2], height, compression)
