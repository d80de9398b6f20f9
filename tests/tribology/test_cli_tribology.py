"""`beveloid ltca` with a lubricant and a speed: the JSON keys of issue 58, the CSV rows, the
efficiency map from one contact solve per torque, and bad input (one line, exit 2)."""
import csv
import json

import pytest

from beveloid import cli, ltca

FZG_TOML = """
[pair]
normal_module_mm = 4.5
normal_pressure_angle_deg = 20.0
shaft_angle_deg = 0.0001
offset_mm = 91.5
[pinion]
teeth = 16
cone_angle_deg = 0.0001
helix_angle_deg = 0.0
profile_shift = 0.1817
face_width_mm = 14.0
roughness_ra_um = 0.4
[gear]
teeth = 24
cone_angle_deg = -0.0001
face_width_mm = 14.0
roughness_ra_um = 0.31
[lubricant]
iso_vg = 32
temperature_c = 60.0
fzg_load_stage = 12
"""
FAST = ["--flank", "left", "--tooth-model", "plate", "--positions", "8", "--grid", "7x9"]
KEYS = ("input_power_w", "mesh_power_loss_w", "efficiency", "friction_coefficient_global", "friction_coefficient_mean",
        "pair_film_thickness_central_um", "pair_film_thickness_min_um", "lambda_min", "flash_temperature_max_c",
        "contact_temperature_max_c", "scuffing_safety")


def run(capsys, *argv):
    rc = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return rc, out, err


@pytest.fixture
def spec(tmp_path):
    p = tmp_path / "fzg.toml"
    p.write_text(FZG_TOML)
    return p


def test_json_keys_and_csv_rows(capsys, spec, tmp_path):
    rc, out, err = run(capsys, "ltca", spec, "--torque-nm", "200", "--speed-rpm", "1500", "--json",
                       "--csv", tmp_path / "o", *FAST)
    assert rc == 0, err
    d = json.loads(out)
    for key in KEYS:
        assert key in d, key
    assert d["input_power_w"] == pytest.approx(200 * 1500 * 3.141592653589793 / 30)
    assert 0.98 < d["efficiency"] < 1.0
    assert d["scuffing_safety"] > 1.0
    loads = d["pair_normal_load_n"]
    for rows in (d["pair_film_thickness_central_um"], d["pair_film_thickness_min_um"]):
        assert len(rows) == len(loads) and all(len(r) == len(d["tooth_pairs"]) for r in rows)
        for r, lr in zip(rows, loads):
            for h, f in zip(r, lr):
                assert (h is None) == (not f), (h, f)  # null exactly where a pair carries no load
    with open(tmp_path / "o" / "tribology.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and {"position", "pair", "sliding_lengthwise_m_s", "flash_temperature_c"} <= set(rows[0])
    assert len({(r["position"], r["pair"], r["cell"]) for r in rows}) == len(rows)  # one row per cell and position


def test_efficiency_map_solves_each_torque_once(capsys, spec, monkeypatch):
    calls = []
    real = ltca.analyze_many

    def counted(*a, **kw):
        calls.append(kw.get("torques_nm"))
        return real(*a, **kw)

    monkeypatch.setattr(ltca, "analyze_many", counted)
    rc, out, err = run(capsys, "ltca", spec, "--torque-nm", "100,200", "--speed-rpm", "500,1000,1500", "--json", *FAST)
    assert rc == 0, err
    assert len(calls) == 1  # one batch of contact solves for both torques, none per speed
    m = json.loads(out)["efficiency_map"]
    assert m["torque_nm"] == [100.0, 200.0] and m["speed_rpm"] == [500.0, 1000.0, 1500.0]
    eff = m["efficiency"]
    assert len(eff) == 2 and all(len(r) == 3 for r in eff)
    # the loss grows with the speed at a torque
    assert m["mesh_power_loss_w"][1][0] < m["mesh_power_loss_w"][1][1] < m["mesh_power_loss_w"][1][2]


@pytest.mark.parametrize("edit, fragment", [
    (("iso_vg = 32", "iso_vg = 33"), "lubricant.iso_vg = 33"),
    (("temperature_c = 60.0", "temperature_c = -30.0"), "lubricant.temperature_c = -30"),
    (("temperature_c = 60.0", "temperature_c = 201.0"), "lubricant.temperature_c = 201"),
    (("roughness_ra_um = 0.4", "roughness_ra_um = -0.4"), "pinion.roughness_ra_um = -0.4"),
])
def test_bad_lubricant_input_is_one_line_exit_2(capsys, tmp_path, edit, fragment):
    p = tmp_path / "bad.toml"
    p.write_text(FZG_TOML.replace(*edit))
    rc, out, err = run(capsys, "ltca", p, "--torque-nm", "200", "--speed-rpm", "1500", *FAST)
    assert rc == 2 and out == ""
    assert len(err.splitlines()) == 1 and fragment in err and "Traceback" not in err


def test_a_speed_without_a_lubricant_is_refused(capsys, tmp_path):
    p = tmp_path / "dry.toml"
    p.write_text(FZG_TOML.split("[lubricant]")[0].replace("roughness_ra_um = 0.4\n", ""))
    rc, out, err = run(capsys, "ltca", p, "--torque-nm", "200", "--speed-rpm", "1500", *FAST)
    assert rc == 2 and out == ""
    assert len(err.splitlines()) == 1 and "--speed-rpm" in err and "[lubricant]" in err
