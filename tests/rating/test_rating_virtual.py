"""The virtual cylindrical gear of a beveloid section (beveloid/rating/virtual.py).

* In the cylindrical limit (cone angles -> 0) the toe, middle and heel sections give the same gear,
  and it is the member's cylindrical helical gear: teeth, m_n, alpha_n, |beta|, x_n = x_t m_t / m_n,
  the tip diameter d + 2 (h_a + x_n m_n) and the rack's dedendum.
* With a cone angle, each flank's transverse pressure angle and base radius are those of the
  generated section (generated/tooth_sections.py), and the shift grows by tan(gamma) per mm of face
  toward the heel (the root cone's slope).
"""
from __future__ import annotations

import math

import pytest

from beveloid.pair import Pair
from beveloid.rating.virtual import section_gear
from beveloid.spec import load_example, spec_from_dict, spec_to_dict
from beveloid.tooth import sections


@pytest.fixture(scope="module")
def near_cylindrical():
    d = spec_to_dict(load_example("case1"))
    d["pinion"]["cone_angle_deg"] = 1e-6
    d["gear"]["cone_angle_deg"] = 1e-6
    return Pair.from_spec(spec_from_dict(d))


@pytest.mark.parametrize("member", ["pinion", "gear"])
@pytest.mark.parametrize("flank", ["left", "right"])
def test_sections_agree_and_equal_the_cylindrical_gear_in_the_cylindrical_limit(near_cylindrical, member, flank):
    pair = near_cylindrical
    g, design = pair.geometry, getattr(pair.design, member)
    m = g.member(member)
    mn, an, beta = g.normal_module_mm, g.normal_pressure_angle, design.helix_angle
    x_n = design.profile_shift * (mn / math.cos(beta)) / mn
    w = sections.half_face(g, member)
    for at in (-w, 0.0, w):
        v = section_gear(g, member, at, flank).gear
        assert v.teeth == m.teeth
        assert v.normal_module_mm == pytest.approx(mn, rel=1e-7)
        assert v.normal_pressure_angle == pytest.approx(an, abs=1e-7)
        assert v.helix_angle == pytest.approx(abs(beta), abs=1e-7)
        assert v.profile_shift == pytest.approx(x_n, abs=1e-6)
        d = m.teeth * mn / math.cos(beta)
        assert v.tip_diameter_mm == pytest.approx(d + 2 * (m.tip_height_mm + x_n * mn), rel=1e-7)
        assert v.rack_dedendum_mm == pytest.approx(m.cutter_addendum_mm, rel=1e-9)


@pytest.mark.parametrize("member", ["pinion", "gear"])
@pytest.mark.parametrize("flank", ["left", "right"])
def test_each_flank_is_the_generated_sections_involute(member, flank):
    pair = Pair.example("case1")
    g = pair.geometry
    m = g.member(member)
    w = sections.half_face(g, member)
    shifts = []
    for at in (-w, 0.0, w):
        sg = section_gear(g, member, at, flank)
        sec = sections.section(g, member, at)
        assert sg.gear.transverse_pressure_angle == pytest.approx(float(getattr(sec, f"pressure_angle_{flank}")),
                                                                  abs=1e-12)
        assert sg.gear.base_diameter_mm / 2 == pytest.approx(float(getattr(sec, f"base_radius_{flank}")), rel=1e-12)
        assert sg.gear.reference_diameter_mm / 2 == pytest.approx(m.pitch_radius_mm, rel=1e-12)
        shifts.append(sg.radial_shift_mm)
    slope = math.tan(m.cone_angle)
    assert shifts[2] - shifts[1] == pytest.approx(slope * w, rel=1e-9)
    assert shifts[1] - shifts[0] == pytest.approx(slope * w, rel=1e-9)
    # the two flanks' helix angles straddle the rack's (tan beta cos gamma is their mean tangent)
    bl = section_gear(g, member, 0.0, "left").helix_angle_signed
    br = section_gear(g, member, 0.0, "right").helix_angle_signed
    assert (math.tan(bl) + math.tan(br)) / 2 == pytest.approx(math.tan(m.helix_angle) * math.cos(m.cone_angle))


def test_iso_section_rating_is_finite_or_null_with_a_reason_over_random_designs():
    """Seeded random variations of case 1 (cone angles, tip round, shift): each
    section of each member is rated with finite values, or is null with its reason; never an exception."""
    import numpy as np

    from beveloid.design import DesignError
    from beveloid.rating.analysis import RateInput, rate_section
    from beveloid.rating.face_load import FaceLoad
    from beveloid.rating.factors import Factors
    from beveloid.spec import SpecError

    rng = np.random.default_rng(3)
    rated = 0
    for _ in range(12):
        d = spec_to_dict(load_example("case1"))
        d["pinion"]["cone_angle_deg"] = float(rng.uniform(0.05, 4.0))
        d["gear"]["cone_angle_deg"] = float(rng.uniform(0.05, 3.0))
        d["pinion"]["profile_shift"] = float(rng.uniform(0.0, 0.3))
        for m in ("pinion", "gear"):
            d[m]["cutter_tip_radius_coefficient"] = float(rng.uniform(0.0, 0.3))
        try:
            pair = Pair.from_spec(spec_from_dict(d))
        except (DesignError, SpecError):
            continue
        g = pair.geometry
        no_ltca = {m: FaceLoad(None, None, None, None, None, None) for m in ("pinion", "gear")}
        inp = RateInput(g, "right", 500.0, min(g.pinion.face_width_mm, g.gear.face_width_mm), no_ltca,
                        Factors.from_spec(pair.spec), (206000.0, 0.3, 206000.0, 0.3))
        for member in ("pinion", "gear"):
            w = sections.half_face(g, member)
            for at in (-w, 0.0, w):
                s = rate_section(inp, member, at)
                if s.status.startswith("ISO not computed"):
                    assert math.isnan(s.sigma_F0_mpa)
                else:
                    assert all(math.isfinite(v) and v > 0 for v in (s.sigma_F0_mpa, s.sigma_H0_mpa, s.bending.Y_F,
                                                                     s.bending.Y_S, s.safety_bending_iso))
                    rated += 1
    assert rated >= 30


@pytest.mark.parametrize("tip_radius", [0.0, 0.3])
def test_method_b_root_chord_and_radius_are_those_of_the_generated_fillet(tip_radius):
    """A straight (beta = 0), near-cylindrical pinion: the project's generated root fillet
    (generated/root_fillet.py, the envelope of the rack's tip round) cut by a transverse section has
    its 30 deg tangent where ISO 6336-3 method B puts it on the virtual gear: s_Fn and rho_F agree."""
    import numpy as np
    from scipy.optimize import brentq

    from beveloid.rating import iso6336
    from beveloid.rating.virtual import mate_gear
    from beveloid.tooth import fillet

    d = spec_to_dict(load_example("case1"))
    d["pinion"].update(cone_angle_deg=1e-6, helix_angle_deg=0.0, cutter_tip_radius_coefficient=tip_radius)
    d["gear"]["cone_angle_deg"] = 1e-6
    g = Pair.from_spec(spec_from_dict(d)).geometry
    junction = float(fillet.tip_round(g, "pinion").junction_psi) if tip_radius else 1.5

    def point(psi):  # the right flank's fillet in the section z = 0 (u = 0: beta = gamma = 0); tooth on the x axis
        return fillet.fillet(g, "pinion", "right", np.atleast_1d(psi), np.zeros(1)).point[0, :2]

    def angle(psi, h=1e-7):
        t = point(psi + h) - point(psi - h)
        return math.degrees(math.atan2(abs(t[1]), abs(t[0])))  # to the centre line (x axis)

    psis = np.linspace(1e-6, junction - 1e-6, 400)
    a = np.array([angle(p) for p in psis]) - 30.0
    k = int(np.nonzero(a[:-1] * a[1:] <= 0)[0][0])
    psi = brentq(lambda p: angle(p) - 30.0, psis[k], psis[k + 1], xtol=1e-14)
    p = point(psi)
    h = 1e-4
    d1 = (point(psi + h) - point(psi - h)) / (2 * h)
    d2 = (point(psi + h) - 2 * p + point(psi - h)) / h ** 2
    rho_f = np.hypot(*d1) ** 3 / abs(d1[0] * d2[1] - d1[1] * d2[0])

    sg = section_gear(g, "pinion", 0.0, "right")
    bend = iso6336.bending_geometry(iso6336.CylindricalPair(sg.gear, mate_gear(g, sg, "right"), 50.0))
    assert bend.s_Fn_mm == pytest.approx(2 * abs(p[1]), rel=1e-6)
    assert bend.rho_F_mm == pytest.approx(rho_f, rel=1e-3)


def test_virtual_gear_follows_the_real_fillet_along_the_face_of_a_straight_beveloid():
    """A straight pinion (beta = 0) with a cone angle of 3 deg: in the toe, middle and heel sections
    the generated fillet's 30 deg chord (real beveloid, rack tilted) grows by ~10 % with the rack
    shift, and method B on each section's virtual gear follows it within 0.05 % (the tilted tip round
    cut by the section, O(gamma^2), is what remains)."""
    import numpy as np
    from scipy.optimize import brentq

    from beveloid.rating import iso6336
    from beveloid.rating.virtual import mate_gear
    from beveloid.tooth import fillet

    d = spec_to_dict(load_example("case1"))
    d["pinion"].update(cone_angle_deg=3.0, helix_angle_deg=0.0, cutter_tip_radius_coefficient=0.3)
    g = Pair.from_spec(spec_from_dict(d)).geometry
    junction = float(fillet.tip_round(g, "pinion").junction_psi)
    w = sections.half_face(g, "pinion")
    chords = []
    for at in (-w, 0.0, w):
        z = float(sections.member_z(g, "pinion", at))

        def point(psi, flank="right"):
            def off(u):
                return fillet.fillet(g, "pinion", flank, np.atleast_1d(psi), np.atleast_1d(u)).point[0, 2] - z
            u = brentq(off, z - 20, z + 20, xtol=1e-13)
            return fillet.fillet(g, "pinion", flank, np.atleast_1d(psi), np.atleast_1d(u)).point[0, :2]

        c = 0.5 * (math.atan2(*point(1e-6)[::-1]) + math.atan2(*point(1e-6, "left")[::-1]))  # tooth centre line
        axis = np.array([math.cos(c), math.sin(c)])

        def angle(psi, h=1e-7):
            t = point(psi + h) - point(psi - h)
            return math.degrees(math.acos(abs(t @ axis) / np.hypot(*t)))

        psis = np.linspace(1e-6, junction - 1e-6, 40)
        a = np.array([angle(p) for p in psis]) - 30.0
        k = int(np.nonzero(a[:-1] * a[1:] <= 0)[0][0])
        p = point(brentq(lambda q: angle(q) - 30.0, psis[k], psis[k + 1], xtol=1e-12))
        real = 2 * abs(p[0] * axis[1] - p[1] * axis[0])
        sg = section_gear(g, "pinion", at, "right")
        iso = iso6336.bending_geometry(iso6336.CylindricalPair(sg.gear, mate_gear(g, sg, "right"), 50.0)).s_Fn_mm
        assert iso == pytest.approx(real, rel=5e-4)
        chords.append(real)
    assert chords[2] / chords[0] > 1.05
