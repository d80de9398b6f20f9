"""``beveloid rating``: the JSON contract (strict), the local values against the LTCA they come from,
the factors, and bad input (one line, exit 2)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from beveloid import cli, ltca, rating
from beveloid.pair import Pair
from beveloid.rating.report import SEC_KEYS
from beveloid.solver import Solver
from beveloid.spec import load_example, spec_from_dict, spec_to_dict

REPO = Path(__file__).resolve().parents[2]
C1 = str(REPO / "examples" / "case1.toml")
CASE1_TEXT = (REPO / "examples" / "case1.toml").read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def case1_rating():
    d = spec_to_dict(load_example("case1"))
    d["rating"].update(K_A=1.25, K_v=1.1, pinion_speed_rpm=1000.0, life_hours=2000.0)
    pair = Pair.from_spec(spec_from_dict(d))
    options = rating.Options(ltca.Options(positions=2, tooth_model="plate"))
    lt = ltca.analyze(pair, ltca.LoadCase(800.0 * 1.25 * 1.1), options.ltca, solver=Solver())
    return pair, lt, rating.analyze(pair, ltca.LoadCase(800.0), options, ltca_result=lt)


def test_json_contract_is_complete_and_strict(case1_rating):
    _, _, result = case1_rating
    out = result.to_json()
    json.dumps(out, allow_nan=False)
    assert out["torque_nm"] == 800.0
    for member in ("pinion", "gear"):
        m = out[member]
        assert set(m["sections"]) == {"toe", "middle", "heel"}
        for sec in m["sections"].values():
            assert tuple(sec) == SEC_KEYS and all(isinstance(v, float) for v in sec.values())
        for key in ("root_stress_max_mpa", "contact_pressure_max_mpa", "safety_bending", "safety_pitting",
                    "safety_bending_iso", "safety_pitting_iso"):
            assert key in m
        assert m["safety_bending_iso"] == min(s.safety_bending_iso for s in result.members[member].sections.values())
    v = out["verdict"]
    assert v["lowest"] in ("S_F", "S_H") and v["member"] in ("pinion", "gear")
    assert isinstance(out["notes"], list) and out["notes"]


def test_local_contact_stress_is_the_ltca_surface_peak_at_ka_kv_t(case1_rating):
    """The verdict's contact pressure is the LTCA's (at K_A K_v T) read beyond the edge bands
    (rating.edge.surface_peaks), never above the largest pressure of any loaded cell."""
    from beveloid.rating.edge import surface_peaks

    pair, lt, result = case1_rating
    assert lt.torque_nm == pytest.approx(800.0 * 1.25 * 1.1)
    peak = float(np.nanmax(surface_peaks(lt, pair.geometry)))
    assert peak <= float(np.nanmax(lt.pressure_mpa[lt.converged]))
    f = result.factors
    geom = pair.geometry
    for member in ("pinion", "gear"):
        m = result.members[member]
        assert m.contact_pressure_max_mpa == peak
        assert abs(result.loaded.peak_face_z_mm[member]) <= geom.member(member).face_width_mm / 2
        assert m.safety_pitting == pytest.approx(f.contact_strength_mpa(member) / peak)


def test_iso_stresses_carry_the_load_and_life_factors(case1_rating):
    _, _, result = case1_rating
    f = result.factors
    assert f.cycles["pinion"] == pytest.approx(60 * 1000.0 * 2000.0)
    assert f.cycles["gear"] == pytest.approx(60 * 1000.0 * 2000.0 * 29 / 45)
    # ISO 6336-3 case-hardened: log-log between (3e6, 1.0) and (1e10, 0.85) at N_L = 1.2e8
    assert f.Y_NT("pinion") == pytest.approx(np.exp(np.log(0.85) * np.log(1.2e8 / 3e6) / np.log(1e10 / 3e6)))
    for member in ("pinion", "gear"):
        for s in result.members[member].sections.values():
            assert s.sigma_F_mpa == pytest.approx(s.sigma_F0_mpa * 1.25 * 1.1 * s.K_F_beta)
            assert s.sigma_H_mpa == pytest.approx(s.sigma_H0_mpa * np.sqrt(1.25 * 1.1 * s.K_H_beta))
            # Y_X = 1.05 - 0.01 m_n = 0.99 (case-hardened, m_n = 6 mm; N_L above the knee: whole)
            assert s.safety_bending_iso == pytest.approx(
                f.root_limit_mpa[member] * 2.0 * f.Y_NT(member) * 0.99 / s.sigma_F_mpa)
            assert s.K_H_beta >= 1.0 and 1.0 <= s.K_F_beta <= s.K_H_beta


def run_cli(capsys, argv):
    rc = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return rc, out, err


@pytest.mark.parametrize("section,line,key", [
    ("[rating]", "K_A = 0.9", "rating.K_A = 0.9"),
    ("[material]", "gear_root_stress_limit_mpa = 0", "material.gear_root_stress_limit_mpa = 0"),
    ("[material]", "pinion_contact_stress_limit_mpa = -5", "material.pinion_contact_stress_limit_mpa = -5"),
    ("[rating]", "life_hours = -10\npinion_speed_rpm = 100", "rating.life_hours = -10"),
    ("[rating]", "life_hours = 10", "rating.life_hours = 10"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, section, line, key):
    path = tmp_path / "bad.toml"
    text = CASE1_TEXT
    if section == "[rating]":
        text += f"\n[rating]\n{line}\n"
    else:
        text += f"\n[material]\n{line}\n"
    path.write_text(text, encoding="utf-8")
    rc, out, err = run_cli(capsys, ["rating", path, "--torque-nm", "100"])
    assert rc == 2 and out == ""
    assert len(err.splitlines()) == 1 and key in err and "Traceback" not in err


def test_bad_torque_is_one_line_and_exit_2(capsys):
    rc, out, err = run_cli(capsys, ["rating", C1, "--torque-nm", "0"])
    assert rc == 2 and out == "" and len(err.splitlines()) == 1 and "--torque-nm = 0" in err


def test_a_section_without_a_method_b_answer_is_null_with_its_reason(case1_rating, monkeypatch):
    from beveloid.rating import analysis, iso6336

    pair, lt, _ = case1_rating

    def no_tangent(_pair):
        raise ValueError("method B: no fillet tangent of 30 deg (test)")

    monkeypatch.setattr(iso6336, "bending_geometry", no_tangent)
    result = analysis.analyze(pair, ltca.LoadCase(800.0), rating.Options(ltca.Options(positions=2, tooth_model="plate")),
                              ltca_result=lt)
    out = result.to_json()
    json.dumps(out, allow_nan=False)
    assert all(v is None for v in out["pinion"]["sections"]["toe"].values())
    assert out["pinion"]["safety_bending_iso"] is None
    assert out["verdict"]["source"] == "local" and out["verdict"]["lowest"] == "S_H"
    assert any("no fillet tangent" in n for n in out["notes"])


def test_plot_target_is_refused_before_computing(capsys, monkeypatch, tmp_path):
    def boom(*a, **k):
        raise AssertionError("computed before checking --plot")

    monkeypatch.setattr(rating, "analyze", boom)
    folder = tmp_path / "f.png"
    folder.mkdir()
    for target, words in ((folder, "is a folder"), (tmp_path / "plot.svg", "ending in .png"), ("", "an empty name")):
        rc, out, err = run_cli(capsys, ["rating", C1, "--torque-nm", "100", "--plot", target])
        assert rc == 2 and out == "" and len(err.splitlines()) == 1 and "--plot = " in err and words in err


def test_plot_and_table(tmp_path, capsys, monkeypatch, case1_rating):
    pair, lt, _ = case1_rating
    real = rating.analyze
    monkeypatch.setattr(rating, "analyze", lambda p, load, o, **k: real(pair, load, o, ltca_result=lt, **k))
    target = tmp_path / "r.png"
    rc, out, err = run_cli(capsys, ["rating", C1, "--torque-nm", "800", "--plot", target])
    assert rc in (0, 4) and target.stat().st_size > 10_000
    assert "verdict: lowest safety" in out and out.count(" toe ") == 2


def test_edge_contact_above_its_limit_makes_the_verdict_conditional(case1_rating):
    """The edge-contact rule (docs/rating.md 6): case 1 at 1100 N m (K_A K_v T) runs onto a flank edge; the rule
    judges the share of the mesh's load within 0.05 m_n of the edge (edge.edge_loads), not the singular edge
    peak.  Every safety meets its minimum; with that share at 1.05 x the rule's 2 % the verdict is conditional,
    not a pass, and names the edge and its relief; at 0.95 x it passes."""
    import dataclasses

    from beveloid.rating.edge import edge_loads
    from beveloid.rating.verdict import EDGE_SHARE

    pair, lt, result = case1_rating
    edge = result.loaded.edge
    band = edge_loads(lt, pair.geometry)
    assert edge is not None and edge.share == band.share and edge.pressure_mpa == band.pressure_mpa
    assert edge.pressure_mpa < np.nanmax(lt.pair_edge_max_pressure_mpa)  # the band's mean, not the singular peak
    assert edge.edge in ("toe", "heel", "tip") and edge.where == f"the {edge.edge} of the {edge.member}"

    def verdict(share):
        loaded = dataclasses.replace(result.loaded, edge=dataclasses.replace(edge, share=share * EDGE_SHARE))
        return rating.verdict(dataclasses.replace(result, loaded=loaded))

    v = verdict(1.05)
    assert v["edge_contact"]["exceeds"] and v["edge_contact"]["safety"] == pytest.approx(1 / 1.05)
    assert v["meets_S_Fmin"] and v["meets_S_Hmin"]
    assert v["status"] == "conditional" and v["passes"] is False and v["exit_status"] == 4
    assert v["condition"] == f"passes only if {edge.where} is relieved ({edge.relief})"
    assert "edge-contact rule" in v["line"] and "CONDITIONAL" in v["line"] and edge.where in v["line"]
    v = verdict(0.95)
    assert v["edge_contact"]["exceeds"] is False and v["status"] == "passes" and v["passes"] is True
    assert v["condition"] is None and "edge-contact rule" not in v["line"] and v["exit_status"] == 0


def test_the_table_has_units_and_no_null_with_a_unit(capsys, monkeypatch, case1_rating):
    """Issue 45: a units row under the header; a value that is not computed is "null", never "null MPa"."""
    pair, lt, _ = case1_rating
    real = rating.analyze
    monkeypatch.setattr(rating, "analyze", lambda p, load, o, **k: real(pair, load, o, ltca_result=lt, **k))
    rc, out, _ = run_cli(capsys, ["rating", C1, "--torque-nm", "800", "--tooth-model", "plate"])
    assert rc == rating.verdict(real(pair, ltca.LoadCase(800.0), rating.Options(ltca.Options(positions=2,
                                                                                             tooth_model="plate")),
                                     ltca_result=lt))["exit_status"]
    lines = out.splitlines()
    assert "[MPa]" in lines[2] and "[mm]" in lines[2] and "[deg]" in lines[2]
    assert "root stress max null," in out and "null MPa" not in out
    assert "K_H_beta" in out and "N/mm" in out and "case-hardened MQ" in out


def result_geometry(_result):
    return Pair.example("case1").geometry


def test_json_names_the_face_load_factors_and_the_material(case1_rating):
    _, _, result = case1_rating
    out = result.to_json()
    for member in ("pinion", "gear"):
        m = out[member]
        fl = result.loaded.face_load[member]
        assert m["K_H_beta"] == pytest.approx(max(fl.K_H_beta, 1.0))
        # K_F_beta = K_H_beta^N_F, N_F = (b/h)^2 / (1 + b/h + (b/h)^2) at the pair's smaller b/h (ISO 6336-1)
        g = result_geometry(result)
        bh = min(g.pinion.face_width_mm, g.gear.face_width_mm) / max(
            g.member(x).tip_height_mm + g.member(x).cutter_addendum_mm for x in ("pinion", "gear"))
        assert m["K_F_beta"] == pytest.approx(m["K_H_beta"] ** (bh ** 2 / (1 + bh + bh ** 2)), rel=1e-12)
        assert m["material"]["type"] == "case-hardened" and m["material"]["sigma_Hlim_mpa"] == 1500.0
        assert m["face_load"]["peak_line_load_n_per_mm"] == pytest.approx(fl.peak_line_load_n_per_mm)
    assert out["K_v"] == 1.1 and out["K_v_source"] == "user" and out["dynamic_factor"] is None
    assert out["verdict"]["status"] in ("passes", "conditional", "fails")


def test_each_section_gives_every_input_of_method_b(case1_rating):
    """Issue 57.8: an independent ISO implementation fed only a section's JSON (the virtual gear's own
    m_n and alpha_n, not the rack's; its diameters, rack, the loaded face length and the mate) gets the
    section's s_Fn, rho_F, h_Fe, Y_F, Y_S and Z_H back."""
    import math

    from beveloid.rating import iso6336

    _, _, result = case1_rating
    out = result.to_json()
    for member in ("pinion", "gear"):
        for sec in out[member]["sections"].values():
            beta = math.radians(abs(sec["helix_angle_deg"]))
            an = math.radians(sec["normal_pressure_angle_deg"])
            mn = sec["normal_module_mm"]
            z = round(sec["reference_diameter_mm"] * math.cos(beta) / mn)
            gear = iso6336.CylindricalGear(z, mn, an, beta, sec["normal_profile_shift"], sec["tip_diameter_mm"],
                                           sec["rack_dedendum_mm"], sec["rack_tip_radius_mm"])
            mate = iso6336.CylindricalGear(int(sec["mate_teeth"]), mn, an, beta, sec["mate_normal_profile_shift"],
                                           sec["mate_tip_diameter_mm"], sec["mate_rack_dedendum_mm"],
                                           sec["mate_rack_tip_radius_mm"])
            pair = iso6336.CylindricalPair(gear, mate, sec["loaded_face_width_mm"])
            b = iso6336.bending_geometry(pair)
            assert an != pytest.approx(math.radians(20.0), abs=1e-3)  # the flank's own, not the rack's 20 deg
            for key, value in (("s_Fn_mm", b.s_Fn_mm), ("rho_F_mm", b.rho_F_mm), ("h_Fe_mm", b.h_Fe_mm),
                               ("Y_F", b.Y_F), ("Y_S", b.Y_S), ("virtual_teeth", b.virtual_teeth)):
                assert value == pytest.approx(sec[key], rel=1e-12), (member, key)
            assert iso6336.contact_factors(pair, 2.1e5, 0.3, 2.1e5, 0.3).Z_H == pytest.approx(sec["Z_H"], rel=1e-12)
