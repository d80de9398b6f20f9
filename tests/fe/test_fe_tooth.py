"""The FE tooth's compliance: the local (mesh-dependent) deformation removed, counted once."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid.fe import solve
from beveloid.fe.box import box_mesh
from beveloid.fe.contact import FeTooth
from beveloid.fe.tooth import flank_compliance

pytestmark = pytest.mark.xdist_group(name="fe_case1")

E, NU = 2.06e5, 0.3
#: a block "tooth": face 14 mm (x), thickness 6 mm (y), height 10 mm (z), clamped at its root z = 0
BLOCK = (14.0, 6.0, 10.0)
DEPTH_MM = 3.0


def _block_reading(element_mm):
    """(surface reading, raw reading at DEPTH_MM, corrected) compliance (mm/N) under a point force."""
    mesh = box_mesh(BLOCK, element_mm)
    elastic = solve.factorise(mesh, E, NU, clamped=("z0",))
    point = np.array([[7.0, 6.0, 6.0]])  # on the flank y = 6, mid-face, 0.6 of the height
    normal = np.array([[0.0, 1.0, 0.0]])
    raw, corrected, u = flank_compliance(elastic, point, normal, np.array([DEPTH_MM]))
    surface = solve.displacement_operator(elastic, solve.locate(mesh, point), -normal) @ u
    return float(surface[0, 0]), float(raw[0, 0]), float(corrected[0, 0])


@pytest.fixture(scope="module")
def readings():
    return {h: _block_reading(h) for h in (1.4, 1.0)}


def test_the_reading_at_the_load_point_depends_on_the_mesh_and_the_corrected_one_does_not(readings):
    # at the load point the FE displacement under a point force is singular: a finer mesh (elements
    # 1.4 -> 1 mm) changes it by far more than 3 %
    assert readings[1.0][0] / readings[1.4][0] - 1 > 0.08
    # read at a depth and minus the half-space's displacement there: within 3 %
    assert abs(readings[1.0][2] / readings[1.4][2] - 1) < 0.03


def test_the_correction_removes_boussinesq_at_the_reading_depth(readings):
    _, raw, corrected = readings[1.0]
    boussinesq = (1 + NU) / (2 * np.pi * E * DEPTH_MM) * (2 * (1 - NU) + 1.0)
    assert raw - corrected == pytest.approx(boussinesq, rel=1e-12)
    # the tooth's own deflection remains, the larger part of the reading at mid-thickness
    assert 0.5 * raw < corrected < raw


def test_case1_fe_compliance_is_symmetric_positive_and_softest_at_the_tip(coarse_teeth):
    for data in coarse_teeth.values():
        tooth = FeTooth(data, "right")
        c = tooth.compliance_mm_per_n
        assert np.allclose(c, c.T) and np.linalg.eigvalsh(c).min() >= -1e-15
        diag = np.diag(c).reshape(data.radius_mm.shape[1:])
        # the tip row (s = 1) is softer than the form-limit row in mid-face
        mid = diag.shape[1] // 2
        assert diag[-1, mid] > 3 * diag[0, mid]
        # interpolation: a grid node gets weight 1 on itself
        pts = data.points_mm[1].reshape(-1, 3)
        W = tooth.weights(pts)
        assert np.allclose(W, np.eye(len(pts)), atol=1e-6)
