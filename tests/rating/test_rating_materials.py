"""Materials of the rating (docs/rating.md 4.1): ISO 6336-5 limits by type and quality, the ISO
6336-2/-3 life curves per type, user limits overriding, and bad values (one line, exit 2)."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from beveloid import cli
from beveloid.rating.factors import Factors
from beveloid.rating.materials import MATERIALS, life_factor, limits_mpa
from beveloid.spec import load_example, spec_from_dict, spec_to_dict

REPO = Path(__file__).resolve().parents[2]
CASE1_TEXT = (REPO / "examples" / "case1.toml").read_text(encoding="utf-8")


def factors(**material):
    d = spec_to_dict(load_example("case1"))
    d["material"].update(material)
    d["rating"].update(pinion_speed_rpm=1000.0, life_hours=20000.0)  # N_L pinion 1.2e9, gear 7.7e8
    return Factors.from_spec(spec_from_dict(d))


def test_default_is_case_hardened_mq_as_before():
    f = factors()
    for m in ("pinion", "gear"):
        assert f.contact_limit_mpa[m] == 1500.0 and f.root_limit_mpa[m] == 500.0
        assert f.material[m]["type"] == "case-hardened" and f.material[m]["quality"] == "MQ"


def test_iso_tr_6336_30_example_1_life_factors():
    """ISO/TR 6336-30:2017 example 1 (case-hardened) prints Z_NT 0.910 at N_L = 1.080e9 and 0.962 at
    1.783e8 (reference column of MATISO_6336.example_01 in gfsReboucas/Drivetrain)."""
    z = MATERIALS["case-hardened"].z_nt
    assert round(life_factor(z, 1.080e9), 3) == 0.910
    assert round(life_factor(z, 1.783e8), 3) == 0.962


@pytest.mark.parametrize("kind,z_static,z_knee,y_static,y_static_at", [
    ("case-hardened", 1.6, 5e7, 2.5, 1e3), ("through-hardened", 1.6, 5e7, 2.5, 1e4), ("nitrided", 1.3, 2e6, 1.6, 1e3),
    ("nitrocarburised", 1.1, 2e6, 1.1, 1e3), ("grey-cast-iron", 1.3, 2e6, 1.6, 1e3),
    ("nodular-cast-iron", 1.6, 5e7, 2.5, 1e4)])
def test_life_curves_per_type(kind, z_static, z_knee, y_static, y_static_at):
    """ISO 6336-2 Table 2 / ISO 6336-3 Table 3: the static value, 1 at the knee (Z: 5e7 or 2e6, Y: 3e6),
    0.85 at 1e10, power laws between (log-log straight)."""
    m = MATERIALS[kind]
    assert life_factor(m.z_nt, 1e4) == z_static and life_factor(m.z_nt, z_knee) == pytest.approx(1.0)
    assert life_factor(m.y_nt, y_static_at) == y_static and life_factor(m.y_nt, 3e6) == pytest.approx(1.0)
    assert life_factor(m.z_nt, 1e11) == 0.85 and life_factor(m.y_nt, 1e11) == 0.85
    # halfway in log N between the knee and 1e10 the factor is the geometric mean of 1 and 0.85
    assert life_factor(m.y_nt, (3e6 * 1e10) ** 0.5) == pytest.approx(0.85 ** 0.5, rel=1e-12)


def test_limits_by_type_quality_and_hardness():
    """ISO 6336-5:2016 Table 1, sigma_lim = A x + B."""
    assert limits_mpa("nitrided", "ME", None) == (1450.0, 468.0)
    assert limits_mpa("case-hardened", "ML", None) == (1300.0, 312.0)
    assert limits_mpa("through-hardened", "MQ", 300.0) == pytest.approx((1.313 * 300 + 373, 0.425 * 300 + 187))
    assert limits_mpa("grey-cast-iron", "MQ", 200.0) == pytest.approx((1.033 * 200 + 132, 0.256 * 200 + 8))
    f = factors(gear_material="through-hardened", gear_material_quality="ME", gear_surface_hardness_hv=350.0,
                pinion_material="nitrocarburised")
    assert f.contact_limit_mpa["gear"] == pytest.approx(2.213 * 350 + 260)
    assert f.contact_limit_mpa["pinion"] == pytest.approx(1.167 * 400 + 425)  # default 400 HV
    # the gear's life: through-hardened Y_NT from 2.5 at 1e4 (not 1e3), the pinion's nitrocarburised curves
    assert f.Y_NT("gear") == pytest.approx(life_factor(MATERIALS["through-hardened"].y_nt, 1.2e9 * 29 / 45))
    assert f.Z_NT("pinion") == pytest.approx(0.85 ** (math.log(1.2e9 / 2e6) / math.log(5e3)))


def test_explicit_limits_override_the_material():
    f = factors(pinion_material="nitrided", pinion_contact_stress_limit_mpa=1111.0)
    assert f.contact_limit_mpa["pinion"] == 1111.0 and f.root_limit_mpa["pinion"] == 420.0
    assert f.material["pinion"]["sigma_Hlim_from"] == "user" and f.material["pinion"]["sigma_Flim_from"] == "ISO 6336-5"
    # ...and the life curves stay the material's
    assert f.Z_NT("pinion") == pytest.approx(life_factor(MATERIALS["nitrided"].z_nt, 1.2e9))


@pytest.mark.parametrize("line,key", [
    ('pinion_material = "bronze"', 'material.pinion_material = "bronze"'),
    ('gear_material_quality = "MX"', 'material.gear_material_quality = "MX"'),
    ('pinion_surface_hardness_hv = 300', 'material.pinion_surface_hardness_hv = 300: not used'),
    ('gear_material = "through-hardened"\ngear_surface_hardness_hv = 500', 'material.gear_surface_hardness_hv = 500'),
    ('gear_material = "grey-cast-iron"\ngear_surface_hardness_hv = 200', 'material.gear_surface_hardness_hv = 200'),
])
def test_bad_material_is_one_line_and_exit_2(tmp_path, capsys, line, key):
    path = tmp_path / "bad.toml"
    path.write_text(CASE1_TEXT + f"\n[material]\n{line}\n", encoding="utf-8")
    rc = cli.main(["rating", str(path), "--torque-nm", "100"])
    out, err = capsys.readouterr()
    assert rc == 2 and out == "" and len(err.splitlines()) == 1 and key in err and "Traceback" not in err
