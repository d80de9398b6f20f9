"""The FE tooth's root-stress read-out (issue 57.5, beveloid/fe/contact.py readout_matrix, read_grid): the
nodes' stress tensors fitted by moving least squares (quadratic along the fillet's profile, linear along the
face, a weight falling to zero at the window's edge) around the points of a read grid fixed by the geometry;
the FE tooth's data (fe.tooth.tooth_data) carries it, so that the LTCA's, the rating's and optimize's root
stress is its maximum, which no longer moves with where the mesh's nodes fall."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid.fe.contact import (READ_STEP_FACE_PER_MODULE, READ_STEP_PROFILE_PER_FILLET_SIZE, read_grid,
                                 readout_matrix, readout_window_mm)

pytestmark = pytest.mark.xdist_group(name="fe_case1")

FACE, PROFILE = 0.9, 0.24  # the windows' half-widths (mm)


def _plane(rng, u_rows, n_face=60, jitter=0.0):
    """Nodes on the plane x = 0 (u = y along the profile, v = z along the face) in rows of constant u, each
    row's nodes spread along the face, moved by ``jitter`` mm at random (an unstructured mesh's rows)."""
    u = np.repeat(u_rows, n_face) + rng.uniform(-jitter, jitter, len(u_rows) * n_face)
    v = np.tile(np.linspace(-3.0, 3.0, n_face), len(u_rows)) + rng.uniform(-0.02, 0.02, len(u_rows) * n_face)
    return np.stack([np.zeros_like(u), u, v], axis=1)


def _reads(u_read, v_read):
    uu, vv = np.meshgrid(u_read, v_read, indexing="ij")
    r = np.stack([np.zeros(uu.size), uu.ravel(), vv.ravel()], axis=1)
    return r, np.tile([0.0, 1.0, 0.0], (len(r), 1)), np.tile([0.0, 0.0, 1.0], (len(r), 1))


def test_the_fit_keeps_a_field_quadratic_along_the_profile_and_linear_along_the_face():
    rng = np.random.default_rng(57)
    nodes = _plane(rng, np.arange(-1.0, 1.0, 0.06), jitter=0.02)
    r, t, b = _reads(np.linspace(-0.5, 0.5, 11), np.linspace(-2.0, 2.0, 5))
    w = readout_matrix(r, t, b, nodes, FACE, PROFILE)
    field = lambda p: 300.0 + 2.5 * p[:, 2] - 40.0 * p[:, 1] - 900.0 * p[:, 1] ** 2  # noqa: E731
    assert np.allclose(w @ field(nodes), field(r), rtol=0, atol=1e-8)
    assert np.allclose(w.sum(axis=1), 1.0, atol=1e-10)


def test_the_largest_read_does_not_move_with_the_nodes_where_the_largest_node_does():
    """A peaked fillet stress (a notch's peak, its standard deviation a fillet element: the 2D sections of
    docs/validation.md 10.2 peak so, or wider) sampled by node rows half an element apart with a node-to-node
    scatter of 1 %, then by the same rows shifted by steps of a sixth of an element (every element size a
    little larger moves the nodes so): the read grid's largest value moves by about half a percent; the largest node
    by more than 1.2 %, and the same fit read at the nodes (where the read-out before FE_DATA_VERSION 4 read: a fit
    at each node) by more than 1.5 %."""
    rng = np.random.default_rng(5701)
    peak = lambda p: 500.0 * np.exp(-0.5 * ((p[:, 1] - 0.013) / PROFILE) ** 2) * (1.0 + 0.002 * p[:, 2])  # noqa: E731
    r, t, b = _reads(np.arange(-0.3, 0.3, 0.15 * PROFILE), np.arange(-2.0, 2.0, 0.6))
    reads, tops, at_nodes = [], [], []
    for shift in np.linspace(0.0, 0.5 * PROFILE, 4):
        nodes = _plane(rng, np.arange(-1.0, 1.0, 0.5 * PROFILE) + shift, jitter=0.01)
        values = peak(nodes) * (1.0 + rng.normal(0.0, 0.01, len(nodes)))
        reads.append(np.max(readout_matrix(r, t, b, nodes, FACE, PROFILE) @ values))
        mid = (np.abs(nodes[:, 2]) < 2.0) & (np.abs(nodes[:, 1]) < 0.3)
        tops.append(np.max(values[mid]))
        at_nodes.append(np.max(readout_matrix(nodes[mid], t[:1].repeat(mid.sum(), 0), b[:1].repeat(mid.sum(), 0), nodes,
                                              FACE, PROFILE) @ values))
    assert max(reads) / min(reads) - 1.0 < 0.008
    assert max(tops) / min(tops) - 1.0 > 0.012
    assert max(at_nodes) / min(at_nodes) - 1.0 > 0.015
    assert abs(np.mean(reads) / 500.0 - 1.0) < 0.005


def test_a_read_point_with_too_few_nodes_takes_its_nearest_nodes_value():
    rng = np.random.default_rng(5)
    nodes = _plane(rng, np.arange(-1.0, 1.0, 0.06), n_face=50)
    far = np.array([[0.0, 0.0, 50.0]])
    nodes = np.vstack([nodes, far])
    w = readout_matrix(far, np.array([[0.0, 1.0, 0.0]]), np.array([[0.0, 0.0, 1.0]]), nodes, FACE, PROFILE)
    f = rng.normal(size=len(nodes))
    assert (w @ f)[0] == f[-1]


def test_the_fe_tooths_data_is_read_on_the_members_grid(coarse_teeth, raw_coarse_pinion, case1):
    """tooth_data's fillet stresses are read at the points of the member's read grid (its module and its fillet
    elements at refinement 1: the same points whatever the mesh), over a window widened where it would be
    narrower than 0.75 of the coarsened mesh's elements; the nodal means (smooth=False) stay at the fillet's
    nodes."""
    from beveloid.fe.mesh import mesh_sizes
    from beveloid.tooth.sampling import ToothSampler

    sampler = ToothSampler(case1.geometry, "pinion")
    fe1 = mesh_sizes(sampler, 6.0, 1.0).fillet_mm
    data, raw = coarse_teeth["pinion"], raw_coarse_pinion
    assert np.allclose(data.smoothing_mm, readout_window_mm(6.0, fe1, 3.0 * fe1))
    assert np.allclose(data.smoothing_mm, (2.25 * 0.15 * 6.0, 2.25 * fe1))  # +-0.75 of its elements (x 3)
    assert np.allclose(readout_window_mm(6.0, fe1, 1.25 * fe1), (0.9, fe1))  # x 1.25: the physical window
    for i, flank in enumerate(("left", "right")):
        p = read_grid(sampler, flank, READ_STEP_FACE_PER_MODULE * 6.0, READ_STEP_PROFILE_PER_FILLET_SIZE * fe1)[0]
        assert np.array_equal(data.fillet_points_mm[i][:len(p)], p)
        assert np.all(data.fillet_points_mm[i][len(p):] == p[-1])
    assert np.array_equal(raw.smoothing_mm, [0.0, 0.0])
    assert raw.fillet_points_mm.shape != data.fillet_points_mm.shape
