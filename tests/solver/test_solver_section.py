"""solver.section.point_at_radius: the one Newton for a flank point at a radius in a section."""
from __future__ import annotations

import math

import numpy as np

from beveloid.solver.section import point_at_radius


def _args(geom, which):
    m = geom.member(which)
    return m.tooth_surface, geom.surface_params(which), m.cutter_addendum_mm / math.cos(geom.normal_pressure_angle)


def test_points_lie_at_the_radius_and_in_the_section_elementwise_and_scalar(geom1):
    for which in ("pinion", "gear"):
        model, params, l0 = _args(geom1, which)
        m = geom1.member(which)
        toe, heel = m.face_limits
        z = np.linspace(min(toe, heel), max(toe, heel), 7)[:, None]
        r = m.working_pitch_radius_mm + np.array([-1.0, 0.0, 1.0])[None, :]
        for flank in ("left", "right"):
            sp = point_at_radius(model, flank, params, r, z, l0)
            assert sp.point.shape == (7, 3, 3) and sp.converged.all()
            assert np.abs(np.hypot(sp.point[..., 0], sp.point[..., 1]) - r).max() < 1e-10
            assert np.abs(sp.point[..., 2] - z).max() < 1e-10
            one = point_at_radius(model, flank, params, r[0, 1], z[3, 0], l0)
            assert one.l_mm.shape == () and one.l_mm == sp.l_mm[3, 1] and one.u_mm == sp.u_mm[3, 1]


def test_a_radius_the_flank_never_reaches_is_not_converged(geom1):
    """Inside the base cylinder there is no involute point: the element says so, its neighbours do not care."""
    model, params, l0 = _args(geom1, "pinion")
    z = geom1.pinion.reference_section_offset_mm
    sp = point_at_radius(model, "left", params, np.array([geom1.pinion.working_pitch_radius_mm, 1.0]), z, l0)
    assert sp.converged.tolist() == [True, False]
