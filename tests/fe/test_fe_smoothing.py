"""The smoothed read-out of the FE tooth's fillet stress (issue 57.5, beveloid/fe/contact.py smoothed_data):
a local linear fit over a window along the face and in height, linear in the nodes' stresses."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid.fe.contact import FeTooth, smoothed_data, smoothing_matrix, tooth_arrays

pytestmark = pytest.mark.xdist_group(name="fe_case1")


def _nodes(rng, n=4000):
    z = rng.uniform(-20.0, 20.0, n)
    h = rng.uniform(0.0, 1.5, n)
    return np.stack([np.zeros(n), np.zeros(n), z], axis=1), h


def test_the_fit_keeps_a_stress_linear_along_the_face_and_in_height_and_takes_the_scatter_out():
    rng = np.random.default_rng(57)
    p, h = _nodes(rng)
    w = smoothing_matrix(p, h, face_mm=0.9, height_band_mm=0.05)
    linear = 300.0 + 2.5 * p[:, 2] - 40.0 * h
    assert np.allclose(w @ linear, linear, rtol=0, atol=1e-9)
    noisy = linear + rng.normal(0.0, 6.0, len(h))  # a few percent of node-to-node scatter
    left = w @ noisy - linear
    assert np.std(left) < 0.5 * 6.0
    # its largest value no longer sits on the scatter: the largest of the smoothed field is within
    # the scatter's spread of the true largest, the raw one above it
    excess = np.max(noisy) - np.max(linear)
    assert excess > 1.5 * 6.0
    assert abs(np.max(w @ noisy) - np.max(linear)) < 0.25 * excess


def test_a_padding_repeat_takes_the_last_nodes_row_and_a_lonely_node_keeps_its_value():
    rng = np.random.default_rng(5)
    p, h = _nodes(rng, 500)
    p = np.vstack([p, np.array([[0.0, 0.0, 100.0]]), np.repeat(np.array([[0.0, 0.0, 100.0]]), 3, axis=0)])
    h = np.concatenate([h, [0.5, 0.5, 0.5, 0.5]])
    w = smoothing_matrix(p, h, face_mm=0.9, height_band_mm=0.05).toarray()
    f = rng.normal(size=len(h))
    out = w @ f
    assert out[500] == f[500]  # alone in its window: its own value
    assert np.all(out[501:] == out[500])


def test_the_smoothed_tooth_reads_a_contact_on_the_coarse_tooth_without_its_largest_nodes_scatter(coarse_teeth, case1):
    data = coarse_teeth["pinion"]
    face, band = 0.15 * 6.0, 0.15 * 0.24
    s = smoothed_data(data, face, band)
    assert s.stress_mpa_per_n.shape == data.stress_mpa_per_n.shape
    raw = FeTooth(data, "right")
    smooth = FeTooth(s, "right", tooth_arrays(s, "right", widen_mm=face))
    # the smoothed tooth's reading-depth matrix is the raw one widened
    assert np.all(smooth.near >= raw.near) and smooth.near.sum() > raw.near.sum()
    # a load spread over the middle columns of the flank at mid-height: the smoothed largest root stress is a
    # few percent below the raw one (the raw sits on the nodes' scatter), not a flattened peak
    pts = data.points_mm[raw.index][3, 4:9]
    forces = np.full(len(pts), 2000.0)
    a, b = raw.root_stress(pts, forces).tension_mpa, smooth.root_stress(pts, forces).tension_mpa
    assert 0.8 * a < b < a
