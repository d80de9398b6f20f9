"""The faces of a tooth as the export samples them: sections exact, neighbours sharing their rows.

These hold for any source of the root transition (the swap point, sampling.root_transition), so that
fitted faces and mesh rows join without gaps."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid.tooth.sampling import ExportGeometryError, ToothSampler, rotate_z

S = np.linspace(0.0, 1.0, 7)


@pytest.mark.parametrize("member", ["pinion", "gear"])
def test_faces_lie_in_their_sections_and_share_their_boundary_rows(pair1, member):
    sampler = ToothSampler(pair1.geometry, member)
    z = np.linspace(*sorted(sampler.z_range_mm), 5)
    face = {name: sampler.face_points(name, S, z) for name in
            ("flank_left", "flank_right", "fillet_left", "fillet_right", "tip", "root")}
    for name, pts in face.items():
        assert np.allclose(pts[..., 2], z[None, :], rtol=0, atol=1e-9), name
    tol = 1e-9
    assert np.allclose(face["fillet_left"][-1], face["flank_left"][0], atol=tol)
    assert np.allclose(face["fillet_right"][-1], face["flank_right"][0], atol=tol)
    assert np.allclose(face["tip"][0], face["flank_left"][-1], atol=tol)
    assert np.allclose(face["tip"][-1], face["flank_right"][-1], atol=tol)
    assert np.allclose(face["root"][0], face["fillet_right"][0], atol=tol)
    assert np.allclose(face["root"][-1], rotate_z(face["fillet_left"][0], sampler.pitch_angle_rad), atol=tol)
    radius = {name: np.hypot(pts[..., 0], pts[..., 1]) for name, pts in face.items()}
    assert np.allclose(radius["tip"], sampler.tip_radius_mm(z)[None, :], atol=tol)
    assert np.allclose(radius["root"], sampler.root_radius_mm(z)[None, :], atol=tol)
    for flank in ("left", "right"):  # the flank runs up from the form limit, inside the blank
        r = radius[f"flank_{flank}"]
        assert np.all(np.diff(r, axis=0) > 0) and np.all(r[0] > sampler.root_radius_mm(z))


def test_a_section_without_involute_up_to_the_tip_is_refused_in_one_line():
    """Case 1 with the longest pinion face: at the toe the tip circle lies inside the base circle, a
    tooth the export's faces (fillet, flank, tip land) cannot describe; said in one line, with where."""
    from beveloid.pair import Pair
    from beveloid.spec import load_example, spec_to_dict

    data = spec_to_dict(load_example("case1"))
    data["pinion"].update(face_width_mm=900.0)
    sampler = ToothSampler(Pair.from_spec(data).geometry, "pinion")
    with pytest.raises(ExportGeometryError, match=r"^pinion: at z = -?\d+\.\d{3} mm the left flank has no involute up"
                                                 r" to the tip \(its tip circle lies inside the base circle"):
        sampler.check_buildable(np.linspace(*sorted(sampler.z_range_mm), 5))


def test_a_pointed_section_ends_where_the_flanks_cross():
    """A pinion pointed toward its heel: both flanks end at the same point, at the radius where the
    section's involutes cross (tooth.tip, from the derived section: independent of the sampler's Newton on
    the surfaces), below the tip cone; the tooth has a tip land up to where tooth.tip finds it pointed."""
    import tomllib

    from beveloid.pair import Pair
    from beveloid.spec import example_text
    from beveloid.tooth import sections, tip

    d = tomllib.loads(example_text("case1"))
    d["pair"].update(offset_mm=146.0 / 3, normal_module_mm=2.0)
    d["pinion"].update(teeth=13, cone_angle_deg=8.0, profile_shift=0.45, face_width_mm=21.0)
    d["gear"].update(face_width_mm=10.0)
    g = Pair.from_spec(d).geometry
    t = tip.tip_thickness(g, "pinion")
    assert t.pointed and t.pointed_to_mm == 10.5
    z_face = 0.5 * (t.pointed_from_mm + t.pointed_to_mm)
    z = float(sections.member_z(g, "pinion", z_face))
    sampler = ToothSampler(g, "pinion")
    ends = [sampler.flank_points(f, np.array([1.0]), np.array([z]))[0, 0] for f in ("left", "right")]
    assert np.linalg.norm(ends[0] - ends[1]) <= 1e-6
    radius = float(np.hypot(*ends[0][:2]))
    assert radius == pytest.approx(tip.pointed_tip_radius(g, "pinion", z_face), abs=1e-6)
    assert radius < float(sampler.tip_radius_mm(z)) - 0.01
    pieces = sampler.tip_pieces(sorted(sampler.z_range_mm))
    assert [landed for _, _, landed in pieces] == [True, False]
    z_pointed = float(sections.member_z(g, "pinion", t.pointed_from_mm))  # tooth.tip's own root, on the sections
    assert pieces[0][1] == pieces[1][0] == pytest.approx(z_pointed, abs=1e-6)


def test_a_relieved_flank_runs_into_its_root_fillet():
    """Issue 48: a flank modification the rack's fillet does not carry (end relief, lead slope) leaves a
    step of micrometres at the form limit; the sampled flank closes it over s < BLEND_FRACTION and is the
    generated flank above."""
    import tomllib

    from beveloid.tooth.sampling import BLEND_FRACTION
    from beveloid.pair import Pair
    from beveloid.spec import example_text

    doc = tomllib.loads(example_text("case1"))
    doc["pinion"].update(end_relief_um=20.0, end_relief_length_mm=6.0, lead_slope_um=15.0)
    sampler = ToothSampler(Pair.from_spec(doc).geometry, "pinion")
    z = np.linspace(*sorted(sampler.z_range_mm), 5)
    for flank in ("left", "right"):
        step = np.linalg.norm(sampler.flank_blend_mm(flank, z), axis=-1)
        assert 1e-3 < step.max() < 0.05  # micrometres, not zero: the generated flank does not close
        flank_pts = sampler.flank_points(flank, S, z)
        assert np.allclose(flank_pts[0], sampler.fillet_points(flank, np.array([1.0]), z)[0], atol=1e-9)
        above = S >= BLEND_FRACTION
        assert np.array_equal(flank_pts[above], sampler._generated_flank_points(flank, S[above], z))
    sampler.check_buildable(z)  # closes: no refusal
