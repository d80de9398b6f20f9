"""The rating's estimate of whether the FE root stress is converged (issue 57.5,
beveloid/rating/root_convergence.py)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from beveloid import ltca, rating
from beveloid.fe import cache
from beveloid.fe.contact import FeTooth
from beveloid.rating import root_convergence

pytestmark = pytest.mark.xdist_group(name="fe_case1")


@pytest.fixture(scope="module")
def coarser_teeth(case1, coarsen):
    """The session's coarse FE tooth coarsened once more (the check's mesh)."""
    from beveloid.fe.tooth import tooth_data

    m = ltca.Material.from_spec(case1.spec)
    c = coarsen * root_convergence.CHECK_COARSEN
    return {"pinion": tooth_data(case1, "pinion", m.pinion_e_mpa, m.pinion_nu, coarsen=c),
            "gear": tooth_data(case1, "gear", m.gear_e_mpa, m.gear_nu, coarsen=c)}


@pytest.fixture(scope="module")
def both_windows(case1, coarsen):
    """The session's coarse FE tooth read through its own window and through the check's (the coarser
    tooth's), from one solve: {member: (own, check's)}."""
    from beveloid.fe.tooth import tooth_data

    m = ltca.Material.from_spec(case1.spec)
    c = coarsen * root_convergence.CHECK_COARSEN
    return {"pinion": tooth_data(case1, "pinion", m.pinion_e_mpa, m.pinion_nu, coarsen=coarsen, smooth=(True, c)),
            "gear": tooth_data(case1, "gear", m.gear_e_mpa, m.gear_nu, coarsen=coarsen, smooth=(True, c))}


@pytest.fixture(scope="module")
def same_window_teeth(both_windows):
    """The session's coarse FE tooth read through the check's window."""
    return {m: both_windows[m][1] for m in both_windows}


def test_one_solve_reads_the_tooth_through_both_windows_as_two_solves_do(both_windows, coarse_teeth, coarsen):
    """tooth_data with a tuple of read-outs: the first read-out's data is the default call's (coarse_teeth, its
    own solve) to round-off, and the second reads the same solution through the check's wider window."""
    from dataclasses import fields

    from beveloid.fe.tooth import ToothData

    for m, (own, check) in both_windows.items():
        for f in fields(ToothData):
            if f.name == "stats":  # timings
                continue
            np.testing.assert_allclose(getattr(own, f.name), getattr(coarse_teeth[m], f.name), rtol=1e-9,
                                       atol=1e-12 * float(np.abs(getattr(own, f.name)).max(initial=0.0)), err_msg=f.name)
        assert np.array_equal(check.compliance_mm_per_n, own.compliance_mm_per_n)
        assert check.smoothing_mm[1] == pytest.approx(2.0 * own.smoothing_mm[1], rel=1e-12)
        assert not np.allclose(check.stress_mpa_per_n, own.stress_mpa_per_n, rtol=1e-3)


def test_a_first_rating_solves_each_members_default_mesh_once(case1, coarse_teeth, coarser_teeth, same_window_teeth,
                                                              coarsen, rated, monkeypatch, tmp_path):
    """With an empty FE cache, a rating with the check solves each member's default mesh once (its own read-out
    and the check's same window from that solve, written as two entries) and the check's coarsened mesh once;
    a second rating solves nothing.  The FE computation (fe.tooth.tooth_data) is replaced by the module's data,
    counting its calls; the cache is real, in tmp_path."""
    from beveloid.fe import tooth

    check = coarsen * root_convergence.CHECK_COARSEN
    by = {(coarsen, True): coarse_teeth, (check, True): coarser_teeth, (coarsen, check): same_window_teeth}
    calls = []

    def compute(pair, member, e_mpa, nu, refinement=1, progress=None, coarsen=1.0, smooth=True):
        calls.append((member, coarsen, smooth))
        if isinstance(smooth, tuple):
            return tuple(by[coarsen, s][member] for s in smooth)
        return by[coarsen, smooth][member]

    monkeypatch.setenv("BEVELOID_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(tooth, "tooth_data", compute)
    options = rating.Options(ltca.Options(positions=5, tooth_model="fe", fe_coarsen=coarsen))
    first = rating.analyze(case1, ltca.LoadCase(1500.0), options)
    solved = sorted((str(m), c) for m, c, _ in calls)
    assert solved == sorted([("gear", coarsen), ("gear", check), ("pinion", coarsen), ("pinion", check)])
    assert len(list((tmp_path / "fe").glob("*.npz"))) == 6  # per member: the default, its same window, the coarsened
    calls.clear()
    again = rating.analyze(case1, ltca.LoadCase(1500.0), options)
    assert calls == []
    # the same numbers as the rating that read each tooth from its own computation
    for r in (first, again):
        for m in ("pinion", "gear"):
            got, want = r.loaded.root_stress_convergence[m], rated[2].loaded.root_stress_convergence[m]
            for k in ("default_mpa", "coarse_mpa", "same_window_mpa", "change", "window_effect", "coarse_gci"):
                assert got[k] == pytest.approx(want[k], rel=1e-9), (m, k)


@pytest.fixture(scope="module")
def rated(case1, coarse_teeth, coarser_teeth, same_window_teeth, coarsen):
    """(the LTCA at the session's coarse tooth, the LTCA at the check's, the rating of the first)."""
    check = coarsen * root_convergence.CHECK_COARSEN
    by_coarsen = {(coarsen, None): coarse_teeth, (check, None): coarser_teeth, (coarsen, check): same_window_teeth}
    mp = pytest.MonkeyPatch()
    mp.setattr(cache, "cached_tooth_data", lambda pair, member, *a, coarsen=1.0, smooth=True, **k:
               (by_coarsen[coarsen, None if smooth is True else smooth][member], "hit"))
    try:
        options = ltca.Options(positions=5, tooth_model="fe", fe_coarsen=coarsen)
        lt = ltca.analyze(case1, ltca.LoadCase(1500.0), options)
        lt_coarser = ltca.analyze(case1, ltca.LoadCase(1500.0),
                                  ltca.Options(positions=5, tooth_model="fe",
                                               fe_coarsen=coarsen * root_convergence.CHECK_COARSEN))
        # the asked positions alone: the rating's root stress is then the LTCA's (its refinement between
        # positions, tests/rating/test_rating_positions.py, may read a larger one at an added angle)
        result = rating.analyze(case1, ltca.LoadCase(1500.0), rating.Options(options, refine_positions=False),
                                ltca_result=lt)
    finally:
        mp.undo()
    return lt, lt_coarser, result


def _largest(data, lt, member):
    """The largest root stress of ``lt``'s converged loaded pairs read by the tooth of ``data``."""
    tooth = FeTooth(data, lt.flank)
    pts = lt.gap.pinion_point if member == "pinion" else lt.gap.gear_point
    forces = np.where(lt.gap.in_flank, lt.pressure_mpa * lt.cell_area_mm2[..., None], 0.0)
    best = -np.inf
    for j in np.flatnonzero(lt.converged):
        for k in range(forces.shape[1]):
            if np.nansum(forces[j, k]) > 0:
                best = max(best, tooth.root_stress(pts[j, k], forces[j, k]).tension_mpa)
    return best


def test_the_rating_json_gives_the_root_stress_and_its_reading_on_a_coarser_mesh(rated, coarse_teeth, coarser_teeth,
                                                                                 same_window_teeth, coarsen, case1):
    lt, _, result = rated
    d = json.loads(json.dumps(result.to_json(), allow_nan=False))
    top = lt.root_stress_max_mpa()
    for m in ("pinion", "gear"):
        e = d[m]["root_stress_convergence"]
        assert e["default_mpa"] == pytest.approx(top[m], rel=1e-12)
        assert e["default_mpa"] == pytest.approx(d[m]["root_stress_max_mpa"], rel=1e-12)
        # the same loads, every converged loaded pair, read by the coarser tooth and by the default's mesh
        # through the coarser tooth's window: the mesh's change at a fixed window
        assert e["coarse_mpa"] == pytest.approx(_largest(coarser_teeth[m], lt, m), rel=1e-9)
        assert e["same_window_mpa"] == pytest.approx(_largest(same_window_teeth[m], lt, m), rel=1e-9)
        assert e["change"] == pytest.approx(e["same_window_mpa"] / e["coarse_mpa"] - 1.0, rel=1e-12)
        assert e["window_effect"] == pytest.approx(e["default_mpa"] / e["same_window_mpa"] - 1.0, rel=1e-12)
        # the session's tooth (coarsen 3) reads through 2.25 of its refinement-1 fillet elements, the check's
        # (coarsen 6) through 4.5 (fe.contact.readout_window_mm)
        assert e["window_ratio"] == pytest.approx(2.0)
        assert same_window_teeth[m].smoothing_mm[1] == pytest.approx(coarser_teeth[m].smoothing_mm[1], rel=1e-12)
        assert same_window_teeth[m].smoothing_mm[1] == pytest.approx(2.0 * coarse_teeth[m].smoothing_mm[1], rel=1e-12)
        # the two-mesh index, kept as the alarm under its own name
        assert e["coarse_gci"] == pytest.approx(3.0 * abs(e["same_window_mpa"] / e["coarse_mpa"] - 1.0), rel=1e-12)
        face = case1.geometry.member(m).face_width_mm
        assert e["end_span_mm"] == pytest.approx(face / 16) and 0.0 <= e["face_end_distance_mm"] <= face / 2
        assert e["fillet_radius_per_module"] == pytest.approx(e["fillet_radius_mm"] / 6.0, rel=1e-12)
        assert e["fillet_radius_elements"] == pytest.approx(e["fillet_radius_mm"] / e["fillet_element_mm"], rel=1e-12)
        # the session's tooth is coarsened 3 times: outside the mesh docs/validation.md 10.2 validated, so not
        # shown converged, whatever its coarse check says, and no estimate
        assert e["converged"] is False and e["error_estimate"] is None and e["error_band"] is None
        assert {"parameter": "fe_coarsen", "value": coarsen, "low": 1.0, "high": 1.0} in e["outside_range"]
        assert "fe_coarsen 3 (validated 1)" in next(a for a in d["verdict"]["assumptions"] if f"the {m}'s local S_F" in a)
    # case 1 (m_n 6): the pinion's fillet at the floor 0.04 m_n; the gear's radius (0.279 mm) under 1.75 floor
    # elements sets its elements (fe.mesh.FILLET_RADIUS_ELEMENTS)
    conv = d["pinion"]["root_stress_convergence"], d["gear"]["root_stress_convergence"]
    assert conv[0]["fillet_element_mm"] == pytest.approx(0.04 * 6.0 * coarsen)
    assert conv[1]["fillet_element_mm"] == pytest.approx(conv[1]["fillet_radius_mm"] / 1.75 * coarsen)


def test_the_root_stress_of_the_ltca_and_of_the_ratings_s_f_is_the_read_out_one(rated, raw_coarse_pinion, coarse_teeth,
                                                                               case1):
    """One root stress: the LTCA's largest, the one the rating's local S_F divides by and its JSON reports are
    the same number, the LTCA's loads read with the FE tooth's read-out (fe.contact.readout_matrix, the data's
    fillet stresses); the nodal means' largest is another number."""
    from beveloid.ltca.model.teeth import root_stresses

    lt, _, result = rated
    d = json.loads(json.dumps(result.to_json(), allow_nan=False))
    top = lt.root_stress_max_mpa()
    teeth = (FeTooth(coarse_teeth["pinion"], lt.flank), FeTooth(coarse_teeth["gear"], lt.flank))
    read = root_stresses(teeth, lt, lt.converged)["tension"]["pinion"]
    raw = root_stresses((FeTooth(raw_coarse_pinion, lt.flank), teeth[1]), lt, lt.converged)["tension"]["pinion"]
    assert top["pinion"] == pytest.approx(float(np.nanmax(read)), rel=1e-12)
    assert d["pinion"]["root_stress_max_mpa"] == pytest.approx(top["pinion"], rel=1e-12)
    assert result.members["pinion"].root_stress_max_mpa == pytest.approx(top["pinion"], rel=1e-12)  # S_F's
    assert abs(float(np.nanmax(raw)) / top["pinion"] - 1.0) > 0.005


def test_reading_the_same_loads_on_the_coarser_mesh_stands_for_its_own_ltca(rated):
    """The estimate keeps the default's load distribution: the coarser tooth's own LTCA gives nearly the
    same largest root stress (the load sharing moves little with the mesh)."""
    _, lt_coarser, result = rated
    own = lt_coarser.root_stress_max_mpa()
    for m in ("pinion", "gear"):
        assert result.loaded.root_stress_convergence[m]["coarse_mpa"] == pytest.approx(own[m], rel=0.02)


def test_a_root_stress_not_shown_converged_is_a_note_naming_an_unresolved_notch(rated):
    _, _, result = rated
    est = result.loaded.root_stress_convergence
    notes = [n for n in result.notes if "FE root stress is not shown converged" in n]
    assert len(notes) == sum(1 for e in est.values() if e["converged"] is False)
    def entry(**k):
        e = dict({"default_mpa": 370.8, "coarse_mpa": 254.5, "same_window_mpa": 352.1, "change": 352.1 / 254.5 - 1,
                  "check_coarsen": 2.0, "coarse_gci": 3 * (352.1 / 254.5 - 1), "fillet_radius_mm": 0.0086,
                  "fillet_element_mm": 0.05, "face_end_distance_mm": 10.0, "end_span_mm": 3.125}, **k)
        e["outside_range"] = root_convergence.outside_validated(e, 1, 1.0, 4.0)  # design B's gear (m_n 4)
        e["converged"] = not e["outside_range"]
        return e

    (line,) = root_convergence.convergence_notes({"gear": entry()})
    assert "gear" in line and "+38.3%" in line and "352 MPa" in line and "notch the mesh does not resolve" in line
    assert "the fillet's smallest radius 0.002" in line and "m_n (validated 0.0284 m_n ... 0.1234 m_n)" in line
    assert "the coarse check's change +38.3% (validated" in line
    # a rounded rack: its radius above the range (design B's gear at 0.38 m_n: rho_F 1.52 mm, elements 0.76 mm)
    (line,) = root_convergence.convergence_notes({"gear": entry(fillet_radius_mm=1.52, fillet_element_mm=0.76,
                                                                change=0.02)})
    assert "notch" not in line and "the fillet's smallest radius 0.3800 m_n (validated" in line
    assert "the coarse check's change" not in line
    # inside the range: converged, no note
    inside = entry(fillet_radius_mm=0.2, fillet_element_mm=0.2 / 1.75, change=0.05)
    assert inside["converged"] is True and root_convergence.convergence_notes({"gear": inside}) == []
    # inside but read at a face end: the note says where and why
    end = {"pinion": entry(fillet_radius_mm=0.2, fillet_element_mm=0.2 / 1.75, change=0.001, face_end_distance_mm=1.66)}
    (line,) = root_convergence.convergence_notes(end)
    assert "1.7 mm from a face end" in line and "lumped" in line and "distance from a face end 1.7 mm" in line


def test_the_fillet_of_a_sharp_racks_gear_is_below_its_elements_and_a_rounded_rack_resolves_it():
    """An 80-tooth gear cut by the default sharp rack (like design B's gear of docs/validation.md 10.2, whose
    trochoid is 0.04 mm long with a 0.009 mm radius at the bottom, where its root stress was read): the
    fillet's smallest radius is below the fillet's elements (the notch floor's), a notch the mesh does not
    resolve; a rack tip radius of 0.38 m_n gives a fillet radius above them."""
    from beveloid.pair import Pair
    from beveloid.spec import spec_from_toml_bytes

    text = """[pair]
normal_module_mm = 3.0
normal_pressure_angle_deg = 20.0
shaft_angle_deg = 6.0
offset_mm = 147.5
[pinion]
teeth = 20
cone_angle_deg = 1.0
helix_angle_deg = 15.0
profile_shift = 0.0
face_width_mm = 24.0
[gear]
teeth = 80
cone_angle_deg = 1.0
face_width_mm = 24.0
"""
    sharp = Pair.from_spec(spec_from_toml_bytes(text.encode()))
    rho, h = root_convergence._fillet(sharp, "gear", 1, 1.0)
    assert rho < h  # measured 0.018 mm against 0.0375 mm (0.0125 m_n: fe.mesh.FILLET_SIZE_NOTCH_PER_MODULE)
    rounded = Pair.from_spec(spec_from_toml_bytes((text + "cutter_tip_radius_coefficient = 0.38\n").encode()))
    rho, h = root_convergence._fillet(rounded, "gear", 1, 1.0)
    assert rho > 1.5 * h  # 1.14 mm against 0.57 mm


def test_fe_checks_disagreement_names_both_fillet_meshes_and_an_unresolved_notch():
    """fe-check's note where the two FE root stresses differ: the fillet elements of both meshes and, where
    the fillet's radius is below the FE tooth's elements (design B's gear: CalculiX 0.55 of the FE tooth,
    docs/validation.md 10.2), that neither resolves the notch."""
    from beveloid.fecheck.check import root_stress_notes
    from beveloid.fecheck.result import ContactNumbers

    def block(pinion, gear):
        return ContactNumbers.of([1.0], [1.0], [1.0], 1.0, {"pinion": pinion, "gear": gear}, 1.0)

    fillets = {"pinion": (0.367, 0.551, 0.184), "gear": (0.009, 0.48, 0.16)}
    notes = root_stress_notes(block(335.4, 196.5), block(386.7, 358.1), 1, fillets)
    assert len(notes) == 2
    pinion, gear = notes
    assert "0.551 mm here, 0.184 mm in the FE tooth" in pinion and "notch" not in pinion
    # the two read-outs: the LTCA's smoothed fillet stresses against CalculiX's nodal maximum
    assert "the LTCA's fillet stresses read on a grid fixed by the geometry" in pinion
    assert "radius 0.009 mm, a notch neither mesh resolves" in gear
    # the sectors' fillets coarser than the FE tooth's: the note names --fine-fillets; at equal sizes it does not
    assert "--fine-fillets meshes the sectors' fillets at the FE tooth's sizes" in pinion
    (same,) = root_stress_notes(block(335.4, 196.5), block(386.7, 358.1), 1, {"pinion": (0.367, 0.184, 0.184)})[:1]
    assert "0.184 mm here, 0.184 mm in the FE tooth" in same and "--fine-fillets" not in same
    plain = root_stress_notes(block(335.4, 196.5), block(386.7, 358.1), 1)
    assert len(plain) == 2 and all("in the FE tooth" not in n and "notch" not in n for n in plain)


def test_the_check_can_be_left_out_and_a_bad_switch_is_refused(rated, case1):
    """optimize's rating constraint leaves the check out (its verdict does not read it): no coarsened FE tooth."""
    from beveloid.errors import OptionError

    lt, _, _ = rated
    # the asked positions alone: the refinement's added positions would build the FE data of the teeth the
    # fixture made outside the cache (~10 s of CPU; the refinement is tests/rating/test_rating_positions.py's)
    off = rating.analyze(case1, ltca.LoadCase(1500.0), rating.Options(lt.options, root_stress_check=False,
                                                                      refine_positions=False), ltca_result=lt)
    d = off.to_json()
    assert d["pinion"]["root_stress_convergence"] is None and d["gear"]["root_stress_convergence"] is None
    assert not [n for n in off.notes if "not shown converged" in n]
    with pytest.raises(OptionError, match="root_stress_check"):
        rating.Options(lt.options, root_stress_check="yes")
