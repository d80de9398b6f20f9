"""The flank outline the figures draw (plots.flank_outline): toe, tip, heel and the form limit."""
from __future__ import annotations

import math

import numpy as np
import pytest

from beveloid.plots import flank_outline
from beveloid.tca import surface


@pytest.mark.parametrize("which", ["pinion", "gear"])
@pytest.mark.parametrize("flank", ["left", "right"])
def test_form_limit_is_the_generating_line_at_each_axial_position(geom1, which, flank):
    """The lower edge lies on the form limit l = 0 (a point of the generated surface at that axial
    position, re-found here by a dense scan of u), the upper edge on the tip cone, across the face."""
    zs, rs = flank_outline(geom1, which, flank, n=12)
    m = geom1.member(which)
    toe, heel = m.face_limits
    z, form, tip = zs[:12], rs[:12], rs[12:24][::-1]
    assert z[0] == pytest.approx(min(toe, heel)) and z[-1] == pytest.approx(max(toe, heel))
    assert np.allclose(tip, [m.tip_radius(v) for v in z], atol=1e-12)
    us = np.linspace(-3 * abs(heel - toe), 3 * abs(heel - toe), 200001) + 0.5 * (toe + heel)
    pts = surface(geom1, which, flank, np.zeros_like(us), us).point
    for zz, r in zip(z, form):
        k = int(np.argmin(np.abs(pts[:, 2] - zz)))
        assert abs(pts[k, 2] - zz) < 1e-3
        assert r == pytest.approx(math.hypot(pts[k, 0], pts[k, 1]), abs=1e-3)
    assert np.all(form < tip)
