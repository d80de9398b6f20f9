"""Linear elasticity on a sector mesh: P2 tets, one factorisation, many load cases.

The stiffness is that of isoparametric 10-node (P2) vector elements: the quadratic map through
all ten nodes, so the curved mid-nodes that fe/mesh.py puts onto the faces (fillets, flanks) shape
the elements, its Jacobian taken at each quadrature point (a tet whose map would fold keeps
straight edges: :func:`element_geometry`), assembled vectorised (:func:`stiffness`, held equal
to scikit-fem's ``linear_elasticity`` by a test).  The rim and both radial cuts are clamped.
``Elastic.solve(loads)`` solves all load cases by one factorisation: MKL PARDISO (pypardiso)
where installed, else scipy's SuperLU (measured in docs/performance.md).

The field is evaluated by the P2 shape functions in each tet's barycentric coordinates
(:func:`shape_values`, :func:`shape_gradients`), with the gmsh node order of :class:`SectorMesh`
(corners 0-3, mid-nodes of edges 01, 12, 20, 03, 23, 13).
"""
from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
import scipy.sparse
import scipy.sparse.linalg
from scipy.spatial import cKDTree

__all__ = ["CLAMPED", "EDGES", "Elastic", "MIN_JACOBIAN_RATIO", "element_geometry", "Located", "PardisoFactor", "QUADRATURE", "displacement_operator",
           "factorise", "iso_gradients", "locate", "principal_stresses", "shape_gradients", "shape_values", "sparse_solver",
           "stiffness", "stress_operator", "tet_geometry", "tet_volumes"]

#: the surfaces held fixed
CLAMPED = ("rim", "side_lo", "side_hi")
#: gmsh's mid-node edges of a 10-node tet
EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (2, 3), (1, 3))
#: the tets nearest a point by their centres, searched besides those whose bounding ball holds it
#: (the reading of a point outside the mesh)
_CANDIDATES = 24
#: a candidate tet is searched when a point's straight barycentric coordinates in it are all above
#: minus this (a curved tet holds points of its straight one's neighbourhood only; measured: a point
#: inside a curved tet of case 1's sectors lies at most 0.024 outside its straight tet)
_STRAIGHT_SLACK = 0.25
#: the tets searched for a point outside them all: its best by straight barycentric coordinates
_OUTSIDE_CANDIDATES = 8
#: Newton steps of the inverse isoparametric map (from the straight tet's coordinates; quadratic)
_NEWTON_STEPS = 6
#: a point read nearer than this to where it was asked is inside
_INSIDE_MM = 1e-9


@dataclass(frozen=True)
class Elastic:
    """One factorised sector: ``node_dofs`` (n, 3) global dof of each mesh node's x, y, z."""

    mesh: object  # SectorMesh
    node_dofs: np.ndarray
    free: np.ndarray  # free dof indices
    ndofs: int
    e_mpa: float
    nu: float
    lu: object  # a factorisation of K[free, free] with .solve(rhs)
    timings_s: dict
    geometry: np.ndarray | None = None  # (tets, 10, 3) :func:`element_geometry` of every tet (None: computed where needed)

    def solve(self, loads) -> np.ndarray:
        """Displacements (ndofs, m) (mm) for load vectors (ndofs, m) (N)."""
        loads = np.asarray(loads, dtype=float)
        u = np.zeros_like(loads)
        u[self.free] = self.lu.solve(np.ascontiguousarray(loads[self.free]))
        return u


#: 4-point quadrature of degree 2 on a tet (barycentric points, weights summing to 1): exact for
#: the P2 stiffness on straight tets (products of linear gradients)
_QA, _QB = 0.5854101966249685, 0.1381966011250105
QUADRATURE = np.array([[_QA, _QB, _QB, _QB], [_QB, _QA, _QB, _QB], [_QB, _QB, _QA, _QB], [_QB, _QB, _QB, _QA]])


def tet_volumes(mesh) -> np.ndarray:
    p = mesh.nodes[mesh.tets[:, :4]]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6.0


def stiffness(mesh, e_mpa: float, nu: float, geometry=None) -> scipy.sparse.csr_matrix:
    """The P2 linear-elastic stiffness (N/mm) of the isoparametric (curved) 10-node tets, node n's
    dofs 3 n + (0, 1, 2):

        K[(a,i),(b,j)] = sum_q w_q det J_q / 6 (lam g_ai g_bj + mu (g_aj g_bi + delta_ij g_a . g_b))

    (g the shape gradients at the quadrature points, J the Jacobian of the quadratic map there:
    :func:`iso_gradients`).  Vectorised over the tets; on straight tets it equals scikit-fem's
    ``linear_elasticity`` assembled on ``ElementVector(ElementTetP2())`` (tests/fe/test_fe_solver.py),
    which took 43 s for 24k tets against about 1 s here.  ``geometry``: :func:`element_geometry` of
    every tet, when already computed."""
    lam, mu = _lame(e_mpa, nu)
    x = tet_geometry(mesh, slice(None), geometry)
    ne = len(x)
    gd = [iso_gradients(x, np.broadcast_to(q, (ne, 4))) for q in QUADRATURE]
    g = np.stack([a for a, _ in gd], axis=1)  # (ne, q, 10, 3)
    w = np.stack([d for _, d in gd], axis=1) / (6.0 * len(QUADRATURE))  # (ne, q)
    A = np.einsum("eqai,eqbj,eq->eaibj", g, g, w, optimize=True)
    trace = np.einsum("eakbk->eab", A)
    # K = lam A + mu A^T(i <-> j) in place: each (ne, 900) temporary is 140 MB of fresh pages (case 1's
    # pinion, the first call in a process, four runs each: 1.4-2.5 s of CPU with two, 0.9-1.3 s in place;
    # the same K bit for bit)
    K = np.swapaxes(A, 2, 4) * mu
    A *= lam
    K += A
    del A
    for i in range(3):
        K[:, :, i, :, i] += mu * trace
    dofs = (3 * mesh.tets[:, :, None] + np.arange(3)).reshape(ne, 30).astype(np.int32)
    n = 3 * mesh.nodes.shape[0]
    return scipy.sparse.coo_matrix((K.reshape(-1), (np.repeat(dofs, 30, axis=1).reshape(-1),
                                                    np.tile(dofs, (1, 30)).reshape(-1))), shape=(n, n)).tocsr()


def _point_pypardiso_at_mkl():
    """pypardiso looks for MKL's runtime by a recursive glob of the environment (3 s per solver
    here); a pip-installed MKL sits in <prefix>/lib: name it (PYPARDISO_MKL_RT) when found there."""
    import glob
    import os
    import sys

    if not os.environ.get("PYPARDISO_MKL_RT"):
        found = sorted(glob.glob(os.path.join(sys.prefix, "lib", "libmkl_rt.so*")), key=len)
        if found:
            os.environ["PYPARDISO_MKL_RT"] = found[0]


class PardisoFactor:
    """Intel MKL PARDISO (pypardiso) on the upper triangle of a symmetric positive definite matrix.

    The solves skip PARDISO's iterative refinement (iparm[7] = 0; MKL's default, which the first call
    fills in, is up to 2 steps, each one more solve and a product with the matrix): on an FE tooth's
    stiffness (case 1 pinion, 108558 dofs, 91 load cases) the steps change no displacement by more
    than 3e-15 of the largest and leave the residual at 1.6e-14, while the solve takes a third of
    the time (1.4 s against 4.1 s of CPU; `python benchmarks/bench_fe_tooth.py refinement`)."""

    def __init__(self, matrix):
        _point_pypardiso_at_mkl()
        import pypardiso

        self.solver = pypardiso.PyPardisoSolver()
        self.solver.set_matrix_type(2)  # real symmetric positive definite
        self.matrix = scipy.sparse.triu(matrix, format="csr")
        # MKL keeps the factor in memory of its own until PARDISO's phase -1, which pypardiso's solver never
        # runs when it is dropped: without this every factor of a process stays (an FE tooth's ~1 GB; a rating
        # of many designs in one process grew by it until it ran out of memory). Released when the factor is
        # collected or at :meth:`close`, whichever comes first (the finaliser holds the solver, not self).
        self._release = weakref.finalize(self, self.solver.free_memory, True)
        self.solver.factorize(self.matrix)  # fills in MKL's defaults (iparm[0] = 1: they are used from now on)
        self.solver.iparm[7] = 0  # no iterative refinement (no pivot is perturbed in a positive definite matrix)

    def solve(self, rhs):
        return self.solver.solve(self.matrix, rhs)

    def close(self):
        """Release MKL's memory of the factor now rather than when the factor is collected."""
        self._release()


def sparse_solver() -> str:
    """"pardiso" when pypardiso imports (measured: docs/performance.md), else "splu"."""
    _point_pypardiso_at_mkl()  # before the import: pypardiso makes a solver as it is imported
    try:
        import pypardiso  # noqa: F401
    except ImportError:
        return "splu"
    return "pardiso"


def factorise(mesh, e_mpa: float, nu: float, clamped=CLAMPED, solver: str | None = None) -> Elastic:
    """Assemble K (:func:`stiffness`), clamp the named surfaces ``clamped``, factor K[free, free]."""
    import time

    t0 = time.perf_counter()
    geometry = element_geometry(mesh.nodes[mesh.tets])  # also the stresses' and the located points'
    K = stiffness(mesh, e_mpa, nu, geometry)
    node_dofs = 3 * np.arange(mesh.nodes.shape[0])[:, None] + np.arange(3)
    t1 = time.perf_counter()
    fixed = np.unique(np.concatenate([node_dofs[mesh.node_sets[name]].ravel() for name in clamped]))
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    Kf = K[free][:, free]
    solver = solver or sparse_solver()
    if solver == "pardiso":
        lu = PardisoFactor(Kf)
    else:
        lu = scipy.sparse.linalg.splu(Kf.tocsc(), permc_spec="MMD_AT_PLUS_A")
    t2 = time.perf_counter()
    return Elastic(mesh, node_dofs, free, K.shape[0], float(e_mpa), float(nu), lu,
                   {"assemble_s": t1 - t0, "factor_s": t2 - t1, "free_dofs": int(free.size), "solver": solver},
                   geometry)


@dataclass(frozen=True)
class Located:
    """Points located in the mesh: the tet of each and its reference (barycentric) coordinates in it,
    clipped to the tet."""

    tet: np.ndarray  # (n,)
    bary: np.ndarray  # (n, 4)
    outside_mm: np.ndarray  # (n,) the distance from the point to where it is read (0 inside a tet)

    def __getitem__(self, rows) -> "Located":
        return Located(self.tet[rows], self.bary[rows], self.outside_mm[rows])


def _barycentric(corners, x):
    """(..., 4) barycentric coordinates of points x (..., 3) in tets corners (..., 4, 3)."""
    a = corners[..., 1:, :] - corners[..., :1, :]
    lam = np.linalg.solve(np.swapaxes(a, -1, -2), (x - corners[..., 0, :])[..., None])[..., 0]
    return np.concatenate([1.0 - lam.sum(axis=-1, keepdims=True), lam], axis=-1)


def _candidates(mesh, pts):
    """(point index, tet index) pairs: every tet whose bounding ball holds the point (a ball about the
    corners' centre through its corners and the Bezier control points of its curved edges, which
    hold the curved tet), and the :data:`_CANDIDATES` tets whose centres are nearest (for a point
    outside them all)."""
    x = mesh.nodes[mesh.tets]
    centre = x[:, :4].mean(axis=1)
    control = np.concatenate([x[:, :4], 2.0 * x[:, 4:] - 0.5 * (x[:, [a for a, _ in EDGES]] + x[:, [b for _, b in EDGES]])],
                             axis=1)
    radius = np.max(np.linalg.norm(control - centre[:, None, :], axis=-1), axis=1)
    tree = cKDTree(centre)
    pairs = cKDTree(pts).sparse_distance_matrix(tree, float(radius.max()), output_type="ndarray")
    rows, cols = pairs["i"].astype(np.int64), pairs["j"].astype(np.int64)
    held = pairs["v"] <= radius[cols]
    _, near = tree.query(pts, k=min(_CANDIDATES, len(centre)))
    near = np.asarray(near).reshape(len(pts), -1)
    rows = np.concatenate([rows[held], np.repeat(np.arange(len(pts)), near.shape[1])])
    cols = np.concatenate([cols[held], near.ravel()])
    pairs = np.unique(np.stack([rows, cols], axis=1), axis=0)
    rows, cols = pairs[:, 0], pairs[:, 1]
    # a curved tet departs from its straight one by a fraction of its size: the pairs whose point is
    # far outside the straight tet are dropped, but for each point's _OUTSIDE_CANDIDATES best (where
    # a point outside them all is read: the nearest reading of these)
    worst = _barycentric(x[cols, :4], pts[rows]).min(axis=1)
    order = np.lexsort((-worst, rows))
    start = np.r_[0, np.flatnonzero(np.diff(rows[order])) + 1]
    rank = np.empty(rows.size, dtype=np.int64)
    rank[order] = np.arange(rows.size) - np.repeat(start, np.diff(np.r_[start, rows.size]))
    keep = (rank < _OUTSIDE_CANDIDATES) | (worst >= -_STRAIGHT_SLACK)
    return rows[keep], cols[keep]


def _inverse_map(x10, pts):
    """(k, 4) reference coordinates of points (k, 3) in isoparametric tets (k, 10, 3): Newton on
    x(xi) = pts from the straight tet's barycentric coordinates (exact on a straight tet)."""
    lam = _barycentric(x10[:, :4], pts)
    with np.errstate(all="ignore"):
        for _ in range(_NEWTON_STEPS):
            residual = pts - np.einsum("ka,kai->ki", shape_values(lam), x10)
            jac = np.einsum("kai,kaj->kij", x10, _reference_derivatives(lam))
            ok = np.isfinite(jac).all(axis=(1, 2)) & (np.abs(np.linalg.det(np.where(np.isfinite(jac), jac, 0.0))) > 0)
            step = np.full_like(residual, np.nan)
            step[ok] = np.linalg.solve(jac[ok], residual[ok][..., None])[..., 0]
            lam = lam + np.concatenate([-step.sum(axis=1, keepdims=True), step], axis=1)
    return lam


def locate(mesh, points, max_outside_mm=None, label="point", geometry=None) -> Located:
    """The (curved, isoparametric) tet holding each point and the point's reference coordinates in it,
    by Newton on the tet's quadratic map (:func:`element_geometry`, as the stiffness takes it), so a
    point on a curved face is read where it is.  A point outside every tet is read in the tet nearest
    to it at its coordinates clipped to >= 0 (a point of that tet); ``outside_mm`` is its distance
    to that reading point (at least its distance to the solid; below 1e-9 mm it counts as inside).
    ``max_outside_mm``: a point read further than this from where it was asked raises ValueError
    (one line: ``label`` (one for all points, or one per point), the point, the distance, the limit);
    None reads every point (the caller checks ``outside_mm``).  ``geometry``: :func:`element_geometry`
    of every tet, when already computed (:attr:`Elastic.geometry`)."""
    pts = np.atleast_2d(np.asarray(points, dtype=float))
    rows, cols = _candidates(mesh, pts)
    tets, which = np.unique(cols, return_inverse=True)
    x10 = tet_geometry(mesh, tets, geometry)[which]
    lam = _inverse_map(x10, pts[rows])
    clipped = np.clip(np.nan_to_num(lam, nan=-1.0), 0.0, None)
    clipped /= np.maximum(clipped.sum(axis=1, keepdims=True), 1e-300)
    read = np.einsum("ka,kai->ki", shape_values(clipped), x10)
    dist = np.where(np.isfinite(lam).all(axis=1), np.linalg.norm(read - pts[rows], axis=1), np.inf)
    dist = np.where(dist < _INSIDE_MM, 0.0, dist)
    worst = np.nan_to_num(lam.min(axis=1), nan=-np.inf)
    order = np.lexsort((-worst, dist, rows))  # per point: the nearest reading, then the deepest inside
    first = order[np.r_[True, rows[order][1:] != rows[order][:-1]]]
    tet, bary, outside = cols[first], clipped[first], dist[first]
    if max_outside_mm is not None and np.any(outside > max_outside_mm):
        i = int(np.argmax(outside))
        name = label if isinstance(label, str) else label[i]
        raise ValueError(f"{name} {np.round(pts[i], 4).tolist()} mm lies {outside[i]:.4f} mm outside the mesh: "
                         f"must be inside the solid or within {max_outside_mm:g} mm of it")
    return Located(tet, bary, outside)


def shape_values(bary) -> np.ndarray:
    """(..., 10) P2 shape functions at barycentric coordinates (..., 4), gmsh order."""
    lam = np.asarray(bary, dtype=float)
    out = [lam[..., i] * (2 * lam[..., i] - 1) for i in range(4)]
    out += [4 * lam[..., a] * lam[..., b] for a, b in EDGES]
    return np.stack(out, axis=-1)


def shape_gradients(corners, bary) -> np.ndarray:
    """(..., 10, 3) gradients (1/mm) of the P2 shape functions in straight tets (..., 4, 3)."""
    a = corners[..., 1:, :] - corners[..., :1, :]  # (..., 3, 3) rows: edge vectors
    inv = np.linalg.inv(a)  # columns: gradients of lambda_1..3
    g123 = np.swapaxes(inv, -1, -2)
    grad = np.concatenate([-g123.sum(axis=-2, keepdims=True), g123], axis=-2)  # (..., 4, 3)
    lam = np.asarray(bary, dtype=float)[..., None]
    out = [(4 * lam[..., i, :] - 1) * grad[..., i, :] for i in range(4)]
    out += [4 * (lam[..., a, :] * grad[..., b, :] + lam[..., b, :] * grad[..., a, :]) for a, b in EDGES]
    return np.stack(out, axis=-2)


def _reference_derivatives(bary) -> np.ndarray:
    """(..., 10, 3) derivatives of the P2 shape functions by the reference coordinates
    (lambda_1, lambda_2, lambda_3), lambda_0 = 1 - their sum, gmsh order."""
    lam = np.asarray(bary, dtype=float)
    dl = np.zeros(lam.shape[:-1] + (10, 4))  # d N_a / d lambda_k, the lambdas taken independent
    for i in range(4):
        dl[..., i, i] = 4 * lam[..., i] - 1
    for m, (a, b) in enumerate(EDGES, start=4):
        dl[..., m, a] = 4 * lam[..., b]
        dl[..., m, b] = 4 * lam[..., a]
    return dl[..., 1:] - dl[..., :1]


#: a curved tet whose Jacobian determinant falls below this fraction of its straight one at a
#: quadrature point or a corner (a mid-node moved far onto a strongly curved face) is taken straight
MIN_JACOBIAN_RATIO = 0.2


def element_geometry(nodes10) -> np.ndarray:
    """The tets' geometry nodes (k, 10, 3) for the isoparametric map: the mesh's curved mid-nodes,
    except in a tet whose map would fold or nearly so (:data:`MIN_JACOBIAN_RATIO`), which keeps the
    straight mid-points of its edges (the field's mid-node dofs are shared all the same)."""
    x = np.array(nodes10, dtype=float)
    straight = x.copy()
    for m, (a, b) in enumerate(EDGES, start=4):
        straight[:, m] = 0.5 * (x[:, a] + x[:, b])
    pts = np.vstack([QUADRATURE, np.eye(4)])
    det0 = iso_gradients(straight, np.broadcast_to(pts[0], (len(x), 4)))[1]
    ratio = np.min([iso_gradients(x, np.broadcast_to(q, (len(x), 4)))[1] for q in pts], axis=0) / det0
    bad = ~(ratio > MIN_JACOBIAN_RATIO)
    x[bad] = straight[bad]
    return x


def tet_geometry(mesh, tets, geometry=None) -> np.ndarray:
    """:func:`element_geometry` of the tets ``tets`` (indices or a slice): rows of ``geometry``, that of
    every tet, when given (the same numbers: each tet's is its own)."""
    return element_geometry(mesh.nodes[mesh.tets[tets]]) if geometry is None else geometry[tets]


def iso_gradients(nodes10, bary):
    """(gradients (..., 10, 3) (1/mm), det J (...)) of the P2 shape functions of isoparametric
    10-node tets with nodes (..., 10, 3) at barycentric coordinates (..., 4): J = sum_a x_a dN_a/dxi
    at the point, gradients J^-T dN/dxi (on a straight tet, :func:`shape_gradients`)."""
    dxi = _reference_derivatives(bary)  # (..., 10, 3)
    jac = np.einsum("...ai,...ak->...ik", nodes10, dxi)  # (..., 3 x, 3 xi)
    grads = np.einsum("...ak,...ki->...ai", dxi, np.linalg.inv(jac))
    return grads, np.linalg.det(jac)


def displacement_operator(elastic: Elastic, located: Located, directions) -> scipy.sparse.csr_matrix:
    """(n, ndofs): the displacement along ``directions`` (n, 3) at the located points.  Its transpose
    maps unit forces along the directions at the points to consistent load vectors."""
    n = located.tet.size
    nodes = elastic.mesh.tets[located.tet]  # (n, 10)
    w = shape_values(located.bary)  # (n, 10)
    d = np.asarray(directions, dtype=float)
    vals = w[:, :, None] * d[:, None, :]
    cols = elastic.node_dofs[nodes]  # (n, 10, 3)
    rows = np.broadcast_to(np.arange(n)[:, None, None], cols.shape)
    return scipy.sparse.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(n, elastic.ndofs))


def stress_operator(elastic: Elastic, node_ids) -> scipy.sparse.csr_matrix:
    """(6 n, ndofs): the stress (MPa; xx, yy, zz, xy, yz, zx, point-major) at mesh nodes, the mean over
    the tets that share each node of the P2 field's stress there (isoparametric gradients evaluated
    at the node itself: no extrapolation from Gauss points)."""
    mesh = elastic.mesh
    node_ids = np.asarray(node_ids)
    want = np.full(mesh.nodes.shape[0], -1, dtype=np.int64)
    want[node_ids] = np.arange(node_ids.size)
    tet_local = np.argwhere(want[mesh.tets] >= 0)  # (k, 2): tet, local node
    tets, local = tet_local[:, 0], tet_local[:, 1]
    bary = np.zeros((tets.size, 4))
    for i in range(4):
        bary[local == i, i] = 1.0
    for m, (a, b) in enumerate(EDGES, start=4):
        bary[local == m, a] = 0.5
        bary[local == m, b] = 0.5
    grads, _ = iso_gradients(tet_geometry(mesh, tets, elastic.geometry), bary)  # (k, 10, 3)
    lam_, mu = _lame(elastic.e_mpa, elastic.nu)
    # stress from grad u: sigma_ij = lam div u delta_ij + mu (u_i,j + u_j,i); dof c of node q:
    # u_c,j = g_qj, so d sigma / d u_qc
    k = tets.size
    sig = np.zeros((k, 10, 3, 6))  # per (node q, component c): 6 stress components
    for c in range(3):
        g = grads  # (k, 10, 3)
        sig[:, :, c, 0] = lam_ * g[..., c] + (2 * mu * g[..., 0] if c == 0 else 0.0)
        sig[:, :, c, 1] = lam_ * g[..., c] + (2 * mu * g[..., 1] if c == 1 else 0.0)
        sig[:, :, c, 2] = lam_ * g[..., c] + (2 * mu * g[..., 2] if c == 2 else 0.0)
        sig[:, :, c, 3] = mu * (g[..., 1] if c == 0 else g[..., 0] if c == 1 else 0.0)
        sig[:, :, c, 4] = mu * (g[..., 2] if c == 1 else g[..., 1] if c == 2 else 0.0)
        sig[:, :, c, 5] = mu * (g[..., 0] if c == 2 else g[..., 2] if c == 0 else 0.0)
    share = np.bincount(want[mesh.tets[tets, local]], minlength=node_ids.size).astype(float)
    point = want[mesh.tets[tets, local]]
    weight = 1.0 / share[point]
    cols = elastic.node_dofs[mesh.tets[tets]]  # (k, 10, 3)
    rows = 6 * point[:, None, None, None] + np.arange(6)[None, None, None, :]
    vals = sig * weight[:, None, None, None]
    cols4 = np.broadcast_to(cols[..., None], sig.shape)
    rows4 = np.broadcast_to(rows, sig.shape)
    return scipy.sparse.csr_matrix((vals.ravel(), (rows4.ravel(), cols4.ravel())),
                                   shape=(6 * node_ids.size, elastic.ndofs))


def _lame(e, nu):
    return e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))


def principal_stresses(voigt) -> np.ndarray:
    """(..., 3) ascending principal stresses of (..., 6) stresses (xx, yy, zz, xy, yz, zx)."""
    s = np.asarray(voigt, dtype=float)
    t = np.stack([np.stack([s[..., 0], s[..., 3], s[..., 5]], -1), np.stack([s[..., 3], s[..., 1], s[..., 4]], -1),
                  np.stack([s[..., 5], s[..., 4], s[..., 2]], -1)], -2)
    return np.linalg.eigvalsh(t)
