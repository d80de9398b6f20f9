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
