"""Contact ellipses: the outline is where the measured separation of the placed flanks equals
the approach, semi-axes scale with sqrt(approach), the truncated chord ends on a flank
boundary, a flat direction is a status (never NaN in the JSON)."""
import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from beveloid.solver import Solver
from beveloid import contact_ellipse, curvature, tca
from beveloid.generated import flank_boundaries, placement
from test_tca_curvature import _height

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("flank", tca.FLANKS)
def test_outline_is_the_approach_of_the_measured_separation(geom1, flank):
    e = np.array([0.1, 0.05, -0.05, 0.001, 0.0005])
    ref = tca.reference_contact(geom1, flank)
    phi1 = ref.pinion_angle - 0.2 * geom1.pitch_angles[0]
    x = tca.solve_grid(geom1, flank, e[None], [phi1], solver=Solver("numpy")).x[0, 0]
    approach = 0.001  # a ~ 10 mm: fourth-order terms of the separation stay below 1 % (5 % at 23 mm)
    ce = contact_ellipse.ellipses(geom1, flank, x[None], [phi1], e, approach_mm=approach)
    assert ce.status == ("ellipse",)
    a, b = ce.semi_axes_mm[0]
    assert a >= b > 0
    rc = curvature.relative_curvature(geom1, flank, x, phi1, e)
    major2 = rc.basis @ ce.major_axis[0]
    assert math.isclose(math.degrees(math.atan2(major2[1], major2[0])) % 180, ce.major_axis_deg[0] % 180, abs_tol=1e-9)
    minor2 = np.array([-major2[1], major2[0]])
    sep = lambda s, v: (_height(geom1, "gear", flank, x, phi1, e, rc, s * v)  # noqa: E731
                        - _height(geom1, "pinion", flank, x, phi1, e, rc, s * v))
    for s, v in ((b, minor2), (a, major2)):
        even = 0.5 * (sep(s, v) + sep(-s, v))  # the second-order part (third-order terms cancel)
        assert abs(even - approach) <= 0.02 * approach, (s, even)
    # a and b scale with sqrt(approach)
    ce4 = contact_ellipse.ellipses(geom1, flank, x[None], [phi1], e, approach_mm=4 * approach)
    assert np.allclose(ce4.semi_axes_mm, 2 * ce.semi_axes_mm, rtol=1e-12)


def test_truncated_chord_ends_on_a_flank_boundary(geom1):
    """Where the chord is shorter than 2a, one end lies on a boundary of one member (margin 0)."""
    fr = tca.mesh_flank(geom1, "right", positions=9, pairs=1, solver=Solver("numpy"))
    e = np.zeros(5)
    ce = contact_ellipse.flank_ellipses(geom1, fr, e)
    cut = [i for i, st in enumerate(ce.status) if st == "ellipse" and ce.truncated_length_mm[i] < 2 * ce.semi_axes_mm[i, 0] - 1e-6]
    assert cut, "the right flank of case 1 has ellipses longer than its flanks"
    for i in cut:
        for side, sign in ((0, -1), (1, 1)):
            s = ce.truncated_mm[i, side]
            if s >= ce.semi_axes_mm[i, 0] - 1e-9:
                continue
            end = ce.point[i] + sign * s * ce.major_axis[i]
            margins = []
            for which, P in (("pinion", placement.pinion_placement(fr.pinion_angle[i], geom1.placement())),
                             ("gear", placement.gear_placement(fr.unknowns[i, 4], e, geom1.placement()))):
                # nearest surface point to the chord end, then its margins
                q = P.rotation.T @ (end - P.translation)
                l, u = (fr.unknowns[i, 0], fr.unknowns[i, 1]) if which == "pinion" else (fr.unknowns[i, 2], fr.unknowns[i, 3])
                for _ in range(20):
                    jet = geom1.surface_jet(which, "right", l, u)
                    d = np.linalg.lstsq(jet.point_D_lu, q - jet.point, rcond=None)[0]
                    l, u = l + d[0], u + d[1]
                p = geom1.surface(which, "right", l, u).point
                margins.append(flank_boundaries.flank_margins(p, l, geom1.member(which).blank()).margins.min())
            assert min(margins) == pytest.approx(0, abs=2e-3), (i, side, margins)
            assert max(margins) >= -2e-3


def test_flat_direction_is_a_status_never_nan():
    lmin = np.array([0.01, 1e-13, 0.0, -1e-3, 0.01, 0.02])
    lmax = np.array([0.04, 0.04, 0.04, 0.04, -0.01, 0.04])
    valid = np.array([True, True, True, True, True, False])
    st = contact_ellipse.classify(lmin, lmax, valid)
    assert list(st) == ["ellipse", "line contact", "line contact", "no ellipse", "no ellipse", "no contact"]


def test_json_is_strict_for_a_line_contact(geom1):
    """A line contact (forced by a flat H) gives null semi-axes, a status and finite chords."""
    fr = tca.mesh_flank(geom1, "left", positions=5, pairs=1, solver=Solver("numpy"))
    ce = contact_ellipse.flank_ellipses(geom1, fr, np.zeros(5))
    axes = ce.semi_axes_mm.copy()  # the result's own arrays are read-only
    axes[:, 0] = np.nan
    ce = dataclasses.replace(ce, semi_axes_mm=axes,
                             status=["line contact" if s == "ellipse" else s for s in ce.status])
    text = json.dumps(ce.to_json(), allow_nan=False)
    assert "line contact" in text


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), float("inf"), 2.0])
def test_check_approach_refuses(bad):
    with pytest.raises(ValueError, match="approach_mm"):
        contact_ellipse.check_approach(bad)
