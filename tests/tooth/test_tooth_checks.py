"""Whole-tooth checks (beveloid/tooth/): the transverse sections against the generated surface,
undercut and pointed tips on designs chosen to have them, interference, contact ratio, and the
design command's JSON, table and plot."""
from __future__ import annotations

import json
import math
import tomllib

import numpy as np
import pytest

from beveloid.solver import Solver
from beveloid import tca
from beveloid.pair import Pair
from beveloid.spec import example_text
from beveloid.tooth import contact, profile, report, sections, tip, undercut
from beveloid.tooth import fillet as F

MEMBERS = ("pinion", "gear")
FLANKS = ("left", "right")


def _spec(pair=None, **members):
    d = tomllib.loads(example_text("case1"))
    d["pair"].update(pair or {})
    for name, keys in members.items():
        d[name].update(keys)
    return d


#: a small pinion on a steep cone: undercut toward the toe, pointed toward the heel
STEEP = _spec(pair=dict(offset_mm=146.0),
              pinion=dict(teeth=13, cone_angle_deg=8.0, profile_shift=0.45, face_width_mm=60.0),
              gear=dict(face_width_mm=60.0))
#: the gear's tip reaches the pinion's fillet: a deep gear addendum against a pinion cut with a full tip round
DEEP = _spec(gear=dict(addendum_coefficient=1.2), pinion=dict(cutter_tip_radius_coefficient=0.45))


@pytest.fixture(scope="module")
def steep():
    return Pair.from_spec(STEEP)


@pytest.fixture(scope="module")
def steep_result(steep):
    return report.analyze(steep)


def _polar_angle(p):
    return math.atan2(p[1], p[0])


@pytest.mark.parametrize("member", MEMBERS)
def test_section_thickness_is_the_generated_surfaces(pair1, member):
    """The derived section (involutes of the section's rack) against the 3D generated flanks: the
    angle between the two flanks' points at a radius of a section, at the toe, centre and heel."""
    g = pair1.geometry
    for z_face in (-sections.half_face(g, member), 0.0, sections.half_face(g, member)):
        z = float(sections.member_z(g, member, z_face))
        s = sections.section(g, member, z_face)
        for radius in (float(s.tip_radius), 0.5 * (float(s.tip_radius) + float(s.base_radius_left))):
            left = profile.flank_at_radius(g, member, "left", z, radius)[0]
            right = profile.flank_at_radius(g, member, "right", z, radius)[0]
            angle = _polar_angle(right) - _polar_angle(left)
            th = sections.thickness_at_radius(g, member, z_face, radius)
            assert angle == pytest.approx(float(th.thickness_angle), abs=1e-12)
            assert float(th.arc_thickness) == pytest.approx(radius * angle, abs=1e-10)


@pytest.mark.parametrize("member", MEMBERS)
def test_section_is_the_designs_at_the_reference_section(pair2, member):
    """Transverse pressure angles are the design's; the tip thickness at the reference section (z = 0
    of S_i) is the one the design checks with the spur formula there."""
    g, m = pair2.geometry, getattr(pair2.design, member)
    s = sections.section(g, member, sections.face_z(g, member, 0.0))
    assert float(s.pressure_angle_left) == pytest.approx(m.transverse_pressure_angle_left, abs=1e-14)
    assert float(s.pressure_angle_right) == pytest.approx(m.transverse_pressure_angle_right, abs=1e-14)
    inv = lambda x: math.tan(x) - x  # noqa: E731
    r, m_t = m.reference_pitch_radius_mm, m.transverse_module_mm
    aL, aR = m.transverse_pressure_angle_left, m.transverse_pressure_angle_right
    r_a = r + m.profile_shift * m_t + m.addendum_coefficient * m.normal_module_mm / math.cos(m.cone_angle)
    s_t = math.pi * m_t / 2 + m.profile_shift * m_t * (math.tan(aL) + math.tan(aR))
    s_a = r_a * (s_t / r + sum(inv(a) - inv(math.acos(r * math.cos(a) / r_a)) for a in (aL, aR)))
    assert float(s.tip_radius) == pytest.approx(r_a, abs=1e-10)
    assert float(s.tip_arc_thickness) == pytest.approx(s_a, abs=1e-10)


def test_case1_has_no_limit_reached(pair1):
    res = report.analyze(pair1)
    assert res.statuses == ()
    for member in MEMBERS:
        t = res.tip[member]
        assert not t.pointed and t.min_mm > 0.5 * pair1.geometry.normal_module_mm
        assert res.undercut[member] == {"left": None, "right": None}


def test_undercut_range_ends_where_the_form_point_meets_the_interference_point(steep, steep_result):
    """At the end of the undercut range the flank point cut by the rack's form point lies on the base
    circle (T); inside the range the fillet crosses the flank above the base circle; outside it not."""
    g = steep.geometry
    for flank in FLANKS:
        cut = steep_result.undercut["pinion"][flank]
        w = sections.half_face(g, "pinion")
        assert cut is not None and cut.from_mm == pytest.approx(-w) and -w < cut.to_mm < w
        assert abs(float(undercut.depth(g, "pinion", flank, cut.to_mm))) < 1e-9
        assert cut.depth_mm == pytest.approx(float(undercut.depth(g, "pinion", flank, -w)), abs=1e-12)
        z_end = float(sections.member_z(g, "pinion", cut.to_mm))
        s = sections.section(g, "pinion", cut.to_mm)
        pt, _ = profile.flank_in_section(g, "pinion", flank, z_end, 0.0)
        assert math.hypot(pt[0], pt[1]) == pytest.approx(float(getattr(s, f"base_radius_{flank}")), abs=1e-6)
        inside = float(sections.member_z(g, "pinion", 0.5 * (cut.from_mm + cut.to_mm)))
        l_form, r_form, _ = profile.form_limit(g, "pinion", flank, inside)
        s_in = sections.section(g, "pinion", 0.5 * (cut.from_mm + cut.to_mm))
        assert l_form > 0 and r_form > float(getattr(s_in, f"base_radius_{flank}"))
        outside = float(sections.member_z(g, "pinion", 0.5 * (cut.to_mm + w)))
        assert profile.form_limit(g, "pinion", flank, outside)[0] == 0.0
    assert steep_result.undercut["gear"] == {"left": None, "right": None}
    assert [s for s, _ in steep_result.statuses].count("undercut") == 2


def test_pointed_tip_and_where_the_flanks_meet(steep, steep_result):
    g = steep.geometry
    t = steep_result.tip["pinion"]
    w = sections.half_face(g, "pinion")
    assert t.pointed and t.heel_mm < 0 < t.toe_mm and t.pointed_to_mm == pytest.approx(w)
    assert abs(float(tip.thickness(g, "pinion", t.pointed_from_mm))) < 1e-9
    assert t.min_at_mm == pytest.approx(w) and t.min_mm == pytest.approx(t.heel_mm)
    # the generated flanks meet at the reported radius, below the tip cone
    z = float(sections.member_z(g, "pinion", t.min_at_mm))
    left = profile.flank_at_radius(g, "pinion", "left", z, t.pointed_tip_radius_mm)[0]
    right = profile.flank_at_radius(g, "pinion", "right", z, t.pointed_tip_radius_mm)[0]
    assert abs(_polar_angle(right) - _polar_angle(left)) < 1e-12
    assert t.pointed_tip_below_mm > 0
    assert "pointed" in [s for s, _ in steep_result.statuses]
    assert not steep_result.tip["gear"].pointed


@pytest.mark.parametrize("flank", FLANKS)
def test_contact_ratio_is_the_tca_envelope_share(pair1, flank):
    """The pair's contact interval ends on the tips (aligned case 1), and its length matches the share of
    pair 0's active points in the TCA mesh (to the mesh's grid step)."""
    g = pair1.geometry
    c = contact.flank_contact(g, flank)
    assert {c.start_boundary, c.end_boundary} == {"pinion tip", "gear tip"}
    assert c.interference == () and min(c.form_margin_mm.values()) > 0
    positions = 181
    res = tca.mesh_flank(g, flank, positions=positions, pairs=3, window_pitches=3, solver=Solver("numpy"))
    pair0 = (res.tooth_pair == 0) & res.active
    step = 3 / (positions - 1)
    assert abs(pair0.sum() * step - c.contact_ratio) <= 2 * step
    # just inside the ends pair 0 carries the contact; the end points lie on the boundaries
    x_end = tca.solve_grid(g, flank, np.zeros(5), np.array([c.start_rad, c.end_rad]), solver=Solver("numpy")).x[0]
    margins = tca.contact_margins(g, flank, x_end)
    names = list(tca.tca_kernels.CONTACT_BOUNDARIES)
    assert abs(margins[0, names.index(c.start_boundary)]) < 1e-6
    assert abs(margins[1, names.index(c.end_boundary)]) < 1e-6


@pytest.mark.long_running
def test_interference_when_the_mating_tip_reaches_the_fillet():
    """A deep gear addendum against a pinion flank shortened by a full tip round: the conjugate contact
    runs into the pinion's form limit (the TCA blank starts the flank at the round's junction l_t) before
    the gear's tip is reached; with the paper's sharp rack the same pair does not interfere and its
    contact lasts longer (to the gear's tip)."""
    res = report.analyze(Pair.from_spec(DEEP))
    assert [s for s, _ in res.statuses] == ["interference", "interference"]
    sharp = Pair.from_spec(_spec(gear=dict(addendum_coefficient=1.2))).geometry
    for flank, c in res.contact.items():
        assert c.interference == ("pinion form limit",)
        assert "pinion form limit" in (c.start_boundary, c.end_boundary)
        assert c.form_margin_mm["pinion"] > -1e-6  # the TCA keeps to the true form limit
        s = contact.flank_contact(sharp, flank)
        assert s.interference == () and s.form_margin_mm["pinion"] > 0
        assert {s.start_boundary, s.end_boundary} == {"pinion tip", "gear tip"}
        assert s.contact_ratio > c.contact_ratio + 0.01


@pytest.mark.long_running
def test_design_json_table_and_plot(tmp_path, capsys, steep_result):
    from beveloid import cli

    path = tmp_path / "steep.toml"
    lines = []
    for sec, keys in STEEP.items():
        lines.append(f"[{sec}]")
        lines += [f"{k} = {v!r}" for k, v in keys.items()]
    path.write_text("\n".join(lines) + "\n")
    png = tmp_path / "sections.png"
    assert cli.main(["design", str(path), "--json", "--plot", str(png)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out["pinion"]["tip_transverse_thickness_mm"]) == {"toe", "middle", "heel"}
    assert out["pinion"]["tip_transverse_thickness_mm"]["heel"] < 0
    assert set(out["pinion"]["undercut"]) == {"left", "right"}
    assert set(out["pinion"]["undercut"]["left"]) == {"from_mm", "to_mm", "depth_mm"}
    assert out["gear"]["undercut"] == {"left": None, "right": None}
    assert set(out["contact_ratio"]) == {"left", "right"} and all(1 < v < 2 for v in out["contact_ratio"].values())
    assert {s["status"] for s in out["tooth_status"]} == {"undercut", "pointed"}
    assert png.stat().st_size > 10_000 and png.read_bytes()[:4] == b"\x89PNG"
    assert out["contact_ratio"] == {fl: c.contact_ratio for fl, c in steep_result.contact.items()}
    table = steep_result.table()
    assert "contact ratio" in table and "status pointed: pointed: pinion teeth" in table


def test_options_are_validated():
    with pytest.raises(ValueError, match="contact_per_pitch"):
        report.Options(contact_per_pitch=2)


def test_rounded_rack_raises_the_form_point(pair1):
    """With a tip round the involute starts at l_t > 0: the form radius grows, the undercut depth drops
    by l_t's depth, rho (1 - sin alpha_n) / cos(gamma) in the reference section (cone tilt)."""
    g0 = pair1.geometry
    g = Pair.from_spec(_spec(pinion=dict(cutter_tip_radius_coefficient=0.38))).geometry
    s0 = sections.section(g0, "pinion", 0.0)
    s = sections.section(g, "pinion", 0.0)
    rho = g.pinion.cutter_tip_radius_mm
    l_t = float(F.tip_round(g, "pinion").junction_l)
    assert l_t > 0
    z = float(sections.member_z(g, "pinion", 0.0))
    assert float(s.form_radius_left) > float(s0.form_radius_left)
    pt, _ = profile.flank_in_section(g, "pinion", "left", z, l_t)
    assert math.hypot(pt[0], pt[1]) == pytest.approx(float(s.form_radius_left), abs=1e-9)
    shift = float(s0.undercut_depth_left - s.undercut_depth_left)
    assert shift == pytest.approx(rho * (1 - math.sin(g.normal_pressure_angle)) / math.cos(g.pinion.cone_angle),
                                  rel=1e-9)


def test_the_contact_ratio_is_the_unmodified_flanks_and_says_so(pair1):
    """0.1 um of lead crowning took the design's contact ratio from ~1.6 to 1.0000 (issue 60): crowned flanks
    touch one pair at a time without load.  The design reports the unmodified flanks' ratio (that of the
    same file without the crowning), names it, and keeps the modified flanks' unloaded one beside it."""
    bare = report.analyze(pair1)
    crowned = report.analyze(Pair.from_spec(_spec(pinion=dict(lead_crowning_um=0.1))))
    assert bare.unmodified is None and "carry no modification" in bare.contact_ratio_basis
    assert crowned.contact_ratio == bare.contact_ratio  # the same aligned TCA of the same involute flanks
    assert all(v > 1.5 for v in crowned.contact_ratio.values())
    assert all(c.contact_ratio < 1.001 for c in crowned.contact.values())  # the modified flanks, unloaded
    out = crowned.pair_json()
    assert out["contact_ratio"] == crowned.contact_ratio and "unmodified flanks" in out["contact_ratio_basis"]
    assert out["contact_ratio_modified_unloaded"] == {fl: c.contact_ratio for fl, c in crowned.contact.items()}
    table = crowned.table()
    assert f"of the unmodified flanks (crowning, relief and lead slope taken off): left " \
           f"{crowned.contact_ratio['left']:.4f}" in table
    assert "beveloid ltca" in table and "loaded_contact_ratio" in table


def test_a_unit_slip_is_said_first(tmp_path, capsys):
    """issue 60: module 30 typed for 3 designs (exit 0) a pair whose unmodified contact ratio is below 1 on
    both flanks (working pressure angle 7.4 deg, a negative mounting distance): `design` says so first, on
    stderr and at the top of its table, and its JSON carries the status; the intended pair says nothing."""
    from pathlib import Path

    from beveloid import cli

    text = (Path(__file__).resolve().parents[1] / "data" / "issue60_pair.toml").read_text()
    slip = tmp_path / "m30.toml"
    slip.write_text(text.replace("normal_module_mm = 3.0", "normal_module_mm = 30.0"))
    assert cli.main(["design", str(slip)]) == 0
    out, err = capsys.readouterr()
    assert out.startswith("WARNING: not a usable pair as it stands: the contact ratio is below 1 on both flanks")
    assert "working normal pressure angle is 7.41 deg" in out and "pinion -3548.7 mm" in out
    assert "check pair.normal_module_mm and pair.offset_mm" in out and len(err.splitlines()) == 1
    assert cli.main(["design", str(slip), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert sum(s["status"] == "contact ratio below 1" for s in d["tooth_status"]) == 2
    good = tmp_path / "m3.toml"
    good.write_text(text)
    assert cli.main(["design", str(good)]) == 0
    out, err = capsys.readouterr()
    assert "WARNING" not in out + err and "contact ratio below 1" not in out
