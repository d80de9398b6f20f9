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

The fillet stress tensors are the **smoothed** ones of :func:`beveloid.fe.tooth.tooth_data` (each fillet
node's tensor a local linear fit over its neighbours, :func:`smoothed_data`): the root stress the LTCA
reports, the rating's local S_F divides by and optimize ranks by is their largest principal stress.

C is the FE compliance of :mod:`beveloid.fe.tooth` (local deformation removed) made positive
semi-definite: its eigenvalues below zero (a load at the root of a tooth on a rim stiffer than
the half-space subtracted from it) are set to zero.  Fillet nodes nearer than the reading depth to
a load-grid node that the load set loads, or to its neighbours up and down the profile, are left out
of its root stress (they see that point force's local stress); a node near only other grid nodes
counts, so a short fillet under the flank's lowest grid rows still reads the stress of loads higher up.
"""
from __future__ import annotations

import typing

import numpy as np

from ..names import FLANKS
from . import lines, principal

__all__ = ["FeTooth", "RootStress", "SMOOTH_FACE_PER_MODULE", "SMOOTH_HEIGHT_PER_FILLET_SIZE", "SMOOTH_MIN_NODES",
           "smooth_stress", "smoothed_data", "smoothing_matrix", "smoothing_window_mm", "tooth_arrays"]

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
    The reading depth's reach is widened by the data's smoothing window along the face
    (``data.smoothing_mm[0]``, :func:`smoothed_data`: a smoothed node stands for its neighbours within that
    distance along the face)."""
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
    reach = float(np.max(data.depth_mm[index])) + float(np.asarray(data.smoothing_mm)[0])
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


#: the smoothed read-out's window (:func:`smoothed_data`): along the face +- this times m_n, and in
#: height +- SMOOTH_HEIGHT_PER_FILLET_SIZE times the fillet's element size at refinement 1
#: (``fe.mesh.mesh_sizes``), the same physical window at every refinement
SMOOTH_FACE_PER_MODULE = 0.15
SMOOTH_HEIGHT_PER_FILLET_SIZE = 0.15
#: a node with fewer neighbours in its window than this keeps its own stress
SMOOTH_MIN_NODES = 4


def smoothing_window_mm(normal_module_mm: float, fillet_size_mm: float) -> tuple:
    """(along the face, in height) mm: the half-widths of the smoothing window of a member of normal module
    ``normal_module_mm`` whose fillet elements are ``fillet_size_mm`` at refinement 1
    (``fe.mesh.mesh_sizes``): :data:`SMOOTH_FACE_PER_MODULE` m_n and :data:`SMOOTH_HEIGHT_PER_FILLET_SIZE`
    times that size, the same physical window at every refinement and coarsening."""
    return SMOOTH_FACE_PER_MODULE * float(normal_module_mm), SMOOTH_HEIGHT_PER_FILLET_SIZE * float(fillet_size_mm)


def smoothing_matrix(points_mm, height_mm, face_mm: float, height_band_mm: float, height_order: int = 1):
    """(nf, nf) scipy CSR: row i the weights of a local linear least-squares fit, s(z, h) = c0 + c1 dz + c2 dh
    over the fillet nodes j within |z_j - z_i| <= ``face_mm`` and |h_j - h_i| <= ``height_band_mm`` (h the
    height above the root cone), evaluated at node i (c0).  Linear in the nodes' stresses, so that the
    smoothed tensors of a load set are the smoothed sum of its columns' (fe.principal's bounds hold), and
    exact for a stress that varies linearly along the face and in height.  ``height_order`` 2 adds c3 dh^2:
    exact for a stress quadratic across the fillet, a curved peak's top not read as its window's mean
    (``benchmarks/root_stress_readout.py`` measures it against the linear fit; it needs nodes at three
    heights in a window, and the FE tooth's data uses the linear fit).  Padding repeats of the last
    node (``ToothData.fillet_points_mm``) take the last node's row; a node with fewer than
    :data:`SMOOTH_MIN_NODES` in its window keeps its own value."""
    import scipy.sparse
    from scipy.spatial import cKDTree

    if height_order not in (1, 2):
        raise ValueError(f"height_order = {height_order!r}: must be 1 (linear across the fillet) or 2 (quadratic)")
    p = np.asarray(points_mm, dtype=float)
    h = np.asarray(height_mm, dtype=float)
    nf = len(p)
    n = nf
    while n > 1 and np.array_equal(p[n - 2], p[-1]) and h[n - 2] == h[-1]:
        n -= 1
    x = np.stack([p[:n, 2] / face_mm, h[:n] / height_band_mm], axis=1)
    pairs = cKDTree(x).query_pairs(r=1.0, p=np.inf, output_type="ndarray")
    i = np.concatenate([np.arange(n), pairs[:, 0], pairs[:, 1]])  # each node with itself and its neighbours
    j = np.concatenate([np.arange(n), pairs[:, 1], pairs[:, 0]])
    d = x[j] - x[i]
    a = np.column_stack([np.ones(len(i)), d] + ([d[:, 1] ** 2] if height_order == 2 else []))
    k = a.shape[1]
    normal = np.zeros((n, k, k))
    np.add.at(normal, i, a[:, :, None] * a[:, None, :])
    # the fit's value at the node: row 0 of pinv(A) = (A^T A)^+ A^T, rank-deficient windows included
    w = np.einsum("pk,pk->p", np.linalg.pinv(normal, rcond=1e-12)[i, 0], a)
    alone = np.bincount(i, minlength=n) < SMOOTH_MIN_NODES
    keep = ~alone[i]
    rows = [i[keep], np.flatnonzero(alone), np.arange(n, nf)]
    cols = [j[keep], np.flatnonzero(alone), np.full(nf - n, n - 1)]
    vals = [w[keep], np.ones(int(alone.sum())), np.ones(nf - n)]
    return scipy.sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                   shape=(nf, nf))


def smooth_stress(stress, fillet_points_mm, fillet_height_mm, face_mm: float, height_band_mm: float,
                  height_order: int = 1) -> None:
    """Smooth ``stress`` (2 flanks loaded, 2 fillets, nf, 6, G; MPa per N) in place: every fillet node's
    tensor per load-grid node replaced by its local fit (:func:`smoothing_matrix`, ``height_order`` its
    order across the fillet), one (flank, fillet) slice at a time (no second copy of the whole operator)."""
    nf = stress.shape[2]
    for side in range(2):
        w = smoothing_matrix(fillet_points_mm[side], fillet_height_mm[side], face_mm, height_band_mm, height_order)
        for f in range(2):
            stress[f, side] = (w @ stress[f, side].reshape(nf, -1)).reshape(stress.shape[2:])


def smoothed_data(data, face_mm: float, height_band_mm: float, height_order: int = 1):
    """``data`` (a ToothData, unsmoothed: ``tooth_data(..., smooth=False)``) with every fillet node's stress
    tensor (per unit load on each load-grid node) replaced by its local fit over the window
    (:func:`smoothing_matrix`), and the window in ``smoothing_mm``.  Each node's stress is the mean of its
    tets' P2 stresses at the node and scatters from node to node by a few percent on an unstructured mesh;
    the largest of thousands of nodes sits on that scatter (docs/validation.md 12.2).  The window is narrow
    in height (the notch's peak at the bottom of the fillet is kept) and short along the face against the
    root stress of a contact patch (several mm wide).  :func:`beveloid.fe.tooth.tooth_data` returns its
    data smoothed this way."""
    import dataclasses

    if np.any(np.asarray(data.smoothing_mm) != 0.0):
        raise ValueError(f"smoothing_mm = {list(np.asarray(data.smoothing_mm))}: the data is already smoothed")
    st = np.array(data.stress_mpa_per_n, dtype=float)
    smooth_stress(st, data.fillet_points_mm, data.fillet_height_mm, face_mm, height_band_mm, height_order)
    return dataclasses.replace(data, stress_mpa_per_n=st, smoothing_mm=np.array([face_mm, height_band_mm], dtype=float))


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
