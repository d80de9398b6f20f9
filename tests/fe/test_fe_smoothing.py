"""The smoothed fillet stress of the FE tooth (issue 57.5, beveloid/fe/contact.py smoothed_data): a local
linear fit over a window along the face and in height, linear in the nodes' stresses; the FE tooth's data
(fe.tooth.tooth_data) carries it, so that the LTCA's, the rating's and optimize's root stress is its maximum."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid.fe.contact import FeTooth, smoothed_data, smoothing_matrix, smoothing_window_mm

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


def test_a_quadratic_fit_across_the_fillet_reads_a_curved_peak_where_the_linear_reads_its_windows_mean():
    """A stress whose peak is curved across the fillet (benchmarks/root_stress_readout.py's candidates): the
    linear fit centred on the top reads the window's mean, below the peak by about f'' b^2 / 6; the quadratic
    fit keeps it, and still takes the scatter out."""
    rng = np.random.default_rng(571)
    p, h = _nodes(rng)
    band = 0.3
    curved = 300.0 + 2.5 * p[:, 2] - 400.0 * (h - 0.6) ** 2
    lin = smoothing_matrix(p, h, face_mm=0.9, height_band_mm=band)
    quad = smoothing_matrix(p, h, face_mm=0.9, height_band_mm=band, height_order=2)
    assert np.allclose(quad @ curved, curved, rtol=0, atol=1e-8)
    top = np.abs(h - 0.6) < 0.02
    drop = np.mean((curved - lin @ curved)[top])
    assert drop == pytest.approx(400.0 * band ** 2 / 3.0, rel=0.15)  # the mean of dh^2 over +-band: band^2 / 3
    noisy = curved + rng.normal(0.0, 6.0, len(h))
    assert np.std(quad @ noisy - curved) < 0.6 * 6.0
    with pytest.raises(ValueError, match="height_order = 3"):
        smoothing_matrix(p, h, face_mm=0.9, height_band_mm=band, height_order=3)


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


def test_the_fe_tooths_data_carries_the_smoothed_fillet_stresses(coarse_teeth, raw_coarse_pinion, case1):
    """tooth_data's fillet stresses are the nodal means smoothed over the window of the member's module and its
    fillet elements at refinement 1 (fe.mesh.mesh_sizes), whatever the mesh's coarsening: what every FE
    tooth reads (the old data held the nodal means)."""
    from beveloid.fe.mesh import mesh_sizes
    from beveloid.tooth.sampling import ToothSampler

    data, raw = coarse_teeth["pinion"], raw_coarse_pinion
    face, band = smoothing_window_mm(6.0, mesh_sizes(ToothSampler(case1.geometry, "pinion"), 6.0, 1.0).fillet_mm)
    assert (face, band) == pytest.approx((0.9, 0.15 * 0.24))
    assert np.array_equal(data.smoothing_mm, [face, band]) and np.array_equal(raw.smoothing_mm, [0.0, 0.0])
    assert np.array_equal(data.stress_mpa_per_n, smoothed_data(raw, face, band).stress_mpa_per_n)
    assert not np.allclose(data.stress_mpa_per_n, raw.stress_mpa_per_n)
    with pytest.raises(ValueError, match="already smoothed"):
        smoothed_data(data, face, band)


def test_the_smoothed_tooth_reads_a_contact_without_its_largest_nodes_scatter(coarse_teeth, raw_coarse_pinion):
    data, raw_data = coarse_teeth["pinion"], raw_coarse_pinion
    raw, smooth = FeTooth(raw_data, "right"), FeTooth(data, "right")
    # the smoothed tooth's reading-depth matrix is the raw one widened by the window along the face
    assert np.all(smooth.near >= raw.near) and smooth.near.sum() > raw.near.sum()
    # a load spread over the middle columns of the flank at mid-height: the smoothed largest root stress is a
    # few percent below the raw one (the raw sits on the nodes' scatter), not a flattened peak
    pts = data.points_mm[raw.index][3, 4:9]
    forces = np.full(len(pts), 2000.0)
    a, b = raw.root_stress(pts, forces).tension_mpa, smooth.root_stress(pts, forces).tension_mpa
    assert 0.8 * a < b < a
