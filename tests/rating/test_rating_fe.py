"""The local root stress: the FE tooth (issue 31) against ISO 6336-3 in the near-cylindrical limit, and
how the LTCA's FE root stress enters the rating.

The near-cylindrical, near-parallel pinion (cone angles 0.05 deg, shaft angle 3 deg, spur, a tip
round of 0.3 m_n; case 1 otherwise, face width 20 mm to keep the FE build short) under ISO's own load
case (the whole normal force at d_en, uniform along the face): the FE root stress (max principal
stress in the loaded fillet, default refinement) is at least sigma_F0 and at most 10 % above, the band
reported for FE against ISO 6336-3 method B on cylindrical spur gears (docs/rating.md 5 says where
it comes from and what was measured: FE/ISO = 1.014 with the read-out on a fixed grid, the FE maximum over the
face; `python benchmarks/rating_fe_vs_iso.py --pinion-face-mm 20 --iso-load-case-only`).
"""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from beveloid import ltca, rating
from beveloid.pair import Pair
from beveloid.rating.fe_check import iso_load_case_detail
from beveloid.solver import Solver
from beveloid.spec import load_example, spec_from_dict, spec_to_dict


@pytest.mark.long_running
def test_fe_root_stress_matches_iso_sigma_f0_in_the_near_cylindrical_near_parallel_limit(monkeypatch, tmp_path):
    monkeypatch.setenv("BEVELOID_CACHE_DIR", str(tmp_path))  # its FE data: not into the user's cache folder
    d = spec_to_dict(load_example("case1"))
    d["pair"]["shaft_angle_deg"] = 3.0
    d["pinion"].update(cone_angle_deg=0.05, helix_angle_deg=0.0, cutter_tip_radius_coefficient=0.3,
                       face_width_mm=20.0)
    d["gear"].update(cone_angle_deg=0.05, cutter_tip_radius_coefficient=0.3)
    r = iso_load_case_detail(Pair.from_spec(spec_from_dict(d)), "pinion", "right", 1000.0)
    # FE maximum / sigma_F0 measured 1.014 (median over the face 0.948).  Lower bound 1: ISO's Y_F Y_S is the
    # notch peak of a plane section, and this short face (b / h = 1.5) peaks above its middle toward a free face
    # end, so its maximum is not below sigma_F0.  Upper bound: the +10 % reported between FE and ISO 6336-3
    # method B for spur gears at the outer point of single contact (docs/rating.md 5).
    assert r.fe_face_median_mpa < r.fe_max_mpa
    assert r.sigma_F0_mpa <= r.fe_max_mpa <= 1.10 * r.sigma_F0_mpa


def test_the_ltca_root_stress_gives_the_local_bending_safety():
    """The FE fields of an LTCA result (tooth_model "fe": pair_root_stress_mpa and where) become
    root_stress_max_mpa, its face position and S_F = sigma_Flim Y_ST Y_NT Y_X / sigma_F,local; the
    verdict's bending side is then the local one."""
    pair = Pair.example("case1")
    lt = ltca.analyze(pair, ltca.LoadCase(800.0), ltca.Options(positions=2, tooth_model="plate"), solver=Solver())
    stress = {"pinion": 3.0 * np.nan_to_num(lt.pair_load_n) / 100.0, "gear": 2.0 * np.nan_to_num(lt.pair_load_n) / 100}
    where = {m: np.zeros(lt.pair_load_n.shape + (2,)) for m in stress}
    for m in where:
        where[m][..., 0] = pair.geometry.member(m).reference_section_offset_mm + 5.0  # 5 mm from the middle
        where[m][..., 1] = 0.4
    fe = dataclasses.replace(lt, tooth_model="fe", pair_root_stress_mpa=stress, pair_root_stress_where=where)
    result = rating.analyze(pair, ltca.LoadCase(800.0), rating.Options(ltca.Options(positions=2, tooth_model="plate")), ltca_result=fe)
    f = result.factors
    for m in ("pinion", "gear"):
        top = float(np.max(stress[m]))
        member = result.members[m]
        assert member.root_stress_max_mpa == pytest.approx(top)
        assert member.safety_bending == pytest.approx(f.root_limit_mpa[m] * 2.0 * 0.99 / top)  # Y_X at m_n 6: 0.99
        assert member.root_stress_location["face_z_mm"] == pytest.approx(5.0)
        assert member.root_stress_location["height_above_root_mm"] == pytest.approx(0.4)
        assert "face z 5.0 mm" in member.root_stress_where
    out = result.to_json()
    assert out["pinion"]["root_stress_max_mpa"] == pytest.approx(float(np.max(stress["pinion"])))
    local = sorted((s[3], s[0]) for s in result.safeties() if s[1] == "S_F" and s[2] == "local")
    assert local == [("gear", pytest.approx(f.root_limit_mpa["gear"] * 2.0 * 0.99 / float(np.max(stress["gear"])))),
                     ("pinion", pytest.approx(f.root_limit_mpa["pinion"] * 2.0 * 0.99 / float(np.max(stress["pinion"]))))]


def test_the_local_bending_safety_decides_over_the_iso_one():
    """Where the FE root stress exists its S_F decides: an FE stress 10 x the pair's the ISO sigma_F makes the
    local S_F the lowest of all; an FE stress well below ISO's passes a minimum the ISO S_F fails."""
    pair = Pair.example("case1")
    lt = ltca.analyze(pair, ltca.LoadCase(800.0), ltca.Options(positions=2, tooth_model="plate"), solver=Solver())
    options = rating.Options(ltca.Options(positions=2, tooth_model="plate"))
    iso = rating.analyze(pair, ltca.LoadCase(800.0), options, ltca_result=lt)
    iso_min = min(s.safety_bending_iso for m in iso.members.values() for s in m.sections.values())

    def with_root_stress(mpa, s_fmin):
        stress = {m: np.where(np.isfinite(lt.pair_load_n), mpa, np.nan) for m in ("pinion", "gear")}
        where = {m: np.zeros(lt.pair_load_n.shape + (2,)) for m in stress}
        fe = dataclasses.replace(lt, tooth_model="fe", pair_root_stress_mpa=stress, pair_root_stress_where=where)
        d = spec_to_dict(pair.spec)
        d["rating"]["S_Fmin"] = s_fmin
        return rating.analyze(Pair.from_spec(spec_from_dict(d)), ltca.LoadCase(800.0), options, ltca_result=fe).verdict()

    sigma_flim = iso.factors.root_limit_mpa["pinion"]
    v = with_root_stress(20.0 * sigma_flim, 1.4)  # local S_F = 2 sigma_Flim Y_X / (20 sigma_Flim) = 0.1 x 0.99
    assert (v["lowest"], v["source"], v["value"]) == ("S_F", "local", pytest.approx(0.1 * 0.99))
    assert v["meets_S_Fmin"] is False and v["passes"] is False
    # local S_F = 10 iso_min (FE stress a tenth of ISO's): S_Fmin = 2 iso_min fails every ISO S_F, not the local
    v = with_root_stress(2.0 * sigma_flim / (10.0 * iso_min), 2.0 * iso_min)
    assert v["meets_S_Fmin"] is True
