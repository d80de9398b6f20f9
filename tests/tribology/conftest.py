"""Shared fixtures of the tribology tests: the FZG C14 pair of issue 58 and a crossed-helical pair."""
import pytest

from beveloid import ltca
from beveloid.pair import Pair
from beveloid.spec import spec_from_dict

#: the FZG C14 spur pair as a beveloid (shaft and cone angles 1e-4 deg), its oil and roughness
FZG_C14 = {
    "pair": dict(normal_module_mm=4.5, normal_pressure_angle_deg=20.0, shaft_angle_deg=0.0001, offset_mm=91.5),
    "pinion": dict(teeth=16, cone_angle_deg=0.0001, helix_angle_deg=0.0, profile_shift=0.1817, face_width_mm=14.0,
                   roughness_ra_um=0.4),
    "gear": dict(teeth=24, cone_angle_deg=-0.0001, face_width_mm=14.0, roughness_ra_um=0.31),
    # 15.12 mm^2/s at 60 C; the density at 15 C that gives 878.3 kg/m^3 at 60 C: 13.28 mPa s
    "lubricant": dict(base_oil="mineral", iso_vg=32, kinematic_viscosity_mm2_s=15.12, density_15_kg_m3=909.8,
                      temperature_c=60.0, pressure_viscosity_coefficient_1_per_gpa=20.47, lubricant_factor_xl=0.85),
}


def spec_dict(base=FZG_C14, **sections):
    out = {k: dict(v) for k, v in base.items()}
    for name, values in sections.items():
        out.setdefault(name, {}).update(values)
    return out


def plate_options(**kw):
    return ltca.Options(flank="left", tooth_model="plate", **kw)


@pytest.fixture(scope="session")
def fzg_pair():
    return Pair.from_spec(spec_from_dict(spec_dict(lubricant=dict(friction_coefficient=0.0449))))


@pytest.fixture(scope="session")
def fzg_ltca(fzg_pair):
    return ltca.analyze(fzg_pair, ltca.LoadCase(200.0), plate_options())


def crossed_helical(shaft_angle_deg, mu=0.05):
    """A crossed-helical pair near the limit: cone angles 1e-4 deg, the helix angles splitting the shaft
    angle equally (the bound's case), the FZG teeth and oil, a constant friction coefficient."""
    half = shaft_angle_deg / 2
    return Pair.from_spec(spec_from_dict(spec_dict(
        pair=dict(shaft_angle_deg=shaft_angle_deg, offset_mm=91.5 / 1.0),
        pinion=dict(helix_angle_deg=half, profile_shift=0.0),
        lubricant=dict(friction_coefficient=mu))))


@pytest.fixture(scope="session")
def cases():
    """The helpers above, for the test modules (tests/ has no packages)."""
    import types

    return types.SimpleNamespace(crossed_helical=crossed_helical, plate_options=plate_options, spec_dict=spec_dict)
