"""The FE solver (beveloid.fe.solve) against closed forms and against scikit-fem's assembly."""
from __future__ import annotations

import gc

import numpy as np
import pytest

from beveloid.fe import solve
from beveloid.fe.box import box_mesh

E, NU = 2.0e5, 0.3
L, B, H = 100.0, 10.0, 10.0
P = 100.0


@pytest.fixture(scope="module")
def cantilever():
    mesh = box_mesh((L, B, H), 3.4)
    elastic = solve.factorise(mesh, E, NU, clamped=("x0",))
    # the tip load spread evenly over a 10 x 10 grid of points of the end face (a uniform shear traction)
    yy, zz = np.meshgrid(np.linspace(0.5, B - 0.5, 10), np.linspace(0.5, H - 0.5, 10))
    tip = np.column_stack([np.full(yy.size, L), yy.ravel(), zz.ravel()])
    down = np.tile([0.0, 0.0, -1.0], (len(tip), 1))
    op = solve.displacement_operator(elastic, solve.locate(mesh, tip), down)
    u = elastic.solve((op.T @ np.full(len(tip), P / len(tip)))[:, None])[:, 0]
    return mesh, elastic, op, u


def test_cantilever_tip_deflection_within_2_percent_of_timoshenko(cantilever):
    _, _, op, u = cantilever
    inertia = B * H ** 3 / 12
    shear_modulus = E / (2 * (1 + NU))
    k = 10 * (1 + NU) / (12 + 11 * NU)  # Cowper's shear coefficient of a rectangle
    closed = P * L ** 3 / (3 * E * inertia) + P * L / (k * shear_modulus * B * H)
    assert np.mean(op @ u) == pytest.approx(closed, rel=0.02)


def test_cantilever_root_bending_stress_within_2_percent_of_beam_theory(cantilever):
    mesh, elastic, _, u = cantilever
    x = mesh.nodes[:, 0]
    # the top fibre between 0.2 L and 0.4 L from the clamp (clear of its local constraint)
    top = np.flatnonzero((x > 0.2 * L) & (x < 0.4 * L) & (np.abs(mesh.nodes[:, 2] - H) < 1e-9))
    sigma = (solve.stress_operator(elastic, top) @ u).reshape(-1, 6)
    beam = P * (L - x[top]) * (H / 2) / (B * H ** 3 / 12)
    assert np.max(np.abs(sigma[:, 0] / beam - 1)) < 0.02
    # and the principal stress there is that bending stress (tension on top under a downward load)
    assert np.max(np.abs(solve.principal_stresses(sigma)[:, 2] / beam - 1)) < 0.02


def test_stiffness_equals_scikit_fem_assembly():
    from skfem import Basis, ElementTetP2, ElementVector, MeshTet, asm
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    mesh = box_mesh((4.0, 3.0, 2.0), 1.5)
    ours = solve.stiffness(mesh, E, NU)
    corners = np.unique(mesh.tets[:, :4])
    vertex = np.full(len(mesh.nodes), -1)
    vertex[corners] = np.arange(corners.size)
    sk = MeshTet(mesh.nodes[corners].T.copy(), vertex[mesh.tets[:, :4]].T.copy())
    basis = Basis(sk, ElementVector(ElementTetP2()), intorder=2)
    K = asm(linear_elasticity(*lame_parameters(E, NU)), basis).toarray()
    # skfem's dofs of every node: a corner's nodal dofs, a mid-node's dofs on the edge of its corners
    edge_of = {tuple(sorted(e)): i for i, e in enumerate(sk.edges.T.tolist())}
    perm = np.empty(3 * len(mesh.nodes), dtype=int)
    for n in range(len(mesh.nodes)):
        rows, cols = np.nonzero(mesh.tets == n)
        t, c = rows[0], cols[0]
        if c < 4:
            perm[3 * n: 3 * n + 3] = basis.nodal_dofs[:, vertex[n]]
        else:
            a, b = solve.EDGES[c - 4]
            edge = edge_of[tuple(sorted((vertex[mesh.tets[t, a]], vertex[mesh.tets[t, b]])))]
            perm[3 * n: 3 * n + 3] = basis.edge_dofs[:, edge]
    theirs = K[np.ix_(perm, perm)]
    assert np.allclose(ours.toarray(), theirs, atol=1e-9 * np.abs(theirs).max())



def _curved_tets():
    """Two 10-node tets sharing a face, their mid-edge nodes moved off the straight edges (curved)."""
    rng = np.random.default_rng(7)
    corners = np.array([[0.0, 0, 0], [3, 0, 0], [0, 3, 0], [0, 0, 3], [3, 3, 3]])
    tets = [[0, 1, 2, 3], [1, 2, 3, 4]]
    nodes, rows, mids = list(corners), [], {}
    for t in tets:
        row = list(t)
        for a, b in solve.EDGES:
            key = tuple(sorted((t[a], t[b])))
            if key not in mids:
                mids[key] = len(nodes)
                nodes.append(0.5 * (corners[t[a]] + corners[t[b]]) + rng.uniform(-0.3, 0.3, 3))
            row.append(mids[key])
        rows.append(row)
    return type("M", (), {"nodes": np.array(nodes), "tets": np.array(rows)})()


def test_curved_tets_hold_linear_fields_and_rigid_motions():
    """Isoparametric P2: a linear field through the (curved) nodes has its exact gradient everywhere
    in the element, and a rigid rotation strains nothing (K u = 0); the straight-sided gradients
    through the corners would not do either."""
    mesh = _curved_tets()
    a = np.array([[1.0, -2.0, 0.5], [0.3, 0.7, -1.1], [2.0, 0.1, 0.4]])  # grad of a vector field
    bary = np.random.default_rng(3).dirichlet(np.ones(4), size=(2, 5))
    g, det = solve.iso_gradients(mesh.nodes[mesh.tets][:, None], bary)
    u_nodes = mesh.nodes @ a.T  # (n, 3)
    grad = np.einsum("eqai,eac->eqci", g, u_nodes[mesh.tets])
    assert np.allclose(grad, a, atol=1e-10) and np.all(det > 0)
    straight = solve.shape_gradients(mesh.nodes[mesh.tets[:, :4]][:, None], bary)
    assert not np.allclose(np.einsum("eqai,eac->eqci", straight, u_nodes[mesh.tets]), a, atol=1e-3)
    K = solve.stiffness(mesh, E, NU)
    w = np.array([0.2, -0.5, 0.3])
    rot = np.cross(w, mesh.nodes).ravel()
    assert np.abs(K @ rot).max() < 1e-8 * np.abs(K).max() * np.abs(rot).max()


def test_pardiso_solves_without_iterative_refinement_to_round_off():
    """PardisoFactor turns off PARDISO's iterative refinement (MKL's default takes 2 steps a solve, each a
    further solve and a product with the matrix, for no accuracy the FE tooth needs): no step is taken
    and the solution is that of a direct solve to round-off."""
    import scipy.sparse
    import scipy.sparse.linalg

    n = 300
    K = scipy.sparse.diags([-np.ones(n - 1), 2.5 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csr")
    rhs = np.random.default_rng(0).standard_normal((n, 4))
    factor = solve.PardisoFactor(K)
    x = factor.solve(rhs)
    assert factor.solver.iparm[7] == 0 and factor.solver.iparm[6] == 0  # no refinement step taken
    assert np.abs(K @ x - rhs).max() < 1e-12 * np.abs(rhs).max()
    assert np.allclose(x, scipy.sparse.linalg.spsolve(K.tocsc(), rhs), rtol=0, atol=1e-12)


def test_a_dropped_or_closed_pardiso_factor_gives_mkls_memory_back(monkeypatch):
    """MKL keeps a PARDISO factor in memory of its own until PARDISO's phase -1 (pypardiso's
    ``free_memory(everything=True)``), which pypardiso's solver does not run when it is dropped: every FE tooth's
    factor stayed (a rating of many designs in one process ran out of memory; benchmarks/memory_many_designs.py
    measures the resident memory).  A factor runs it once when it is collected, or at ``close()`` (once, however
    often it is closed).  Checked on the calls themselves: the process's resident memory after a release depends on
    the allocator (a freed factor's pages may be reused by the next one without the memory ever shrinking)."""
    import pypardiso
    import scipy.sparse

    released = []
    real = pypardiso.PyPardisoSolver.free_memory

    def spy(self, everything=False):
        if everything:
            released.append(id(self))
        return real(self, everything)

    monkeypatch.setattr(pypardiso.PyPardisoSolver, "free_memory", spy)
    n = 12
    eye = scipy.sparse.identity(n)
    t = scipy.sparse.diags([-1.0, 2.01, -1.0], [-1, 0, 1], shape=(n, n))
    K = (scipy.sparse.kron(scipy.sparse.kron(t, eye), eye) + scipy.sparse.kron(scipy.sparse.kron(eye, t), eye)
         + scipy.sparse.kron(scipy.sparse.kron(eye, eye), t)).tocsr()
    rhs = np.ones(K.shape[0])
    factor = solve.PardisoFactor(K)
    x = factor.solve(rhs)
    assert np.allclose(K @ x, rhs)
    dropped = id(factor.solver)
    del factor
    gc.collect()
    assert released == [dropped]
    closed = solve.PardisoFactor(K)
    closed.solve(rhs)
    closed.close()
    closed.close()
    assert released == [dropped, id(closed.solver)]
    del closed
    gc.collect()
    assert len(released) == 2
