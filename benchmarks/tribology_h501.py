"""The FZG H501 helical pair (parallel axes) through the tribology: the numbers of docs/tribology.md,
"A helical pair".  Usage: ``python benchmarks/tribology_h501.py``."""
import math

import numpy as np

from beveloid import ltca, tribology
from beveloid.pair import Pair
from beveloid.spec import spec_from_dict

#: the density at 15 C that gives 873.3 kg/m^3 at 70 C on our density line (docs/tribology.md, "The oil"):
#: 37.41 mm^2/s x 873.3 kg/m^3 = 32.67 mPa s, the published dynamic viscosity
RHO_15 = 32.67 / 37.41 * 1000 + 0.7 * (70.0 - 15.0)
#: the published normal profile shift x1 = 0.1809; the spec takes the transverse xt = x cos(beta)
XT1 = 0.1809 * math.cos(math.radians(15.0))
SPEC = {
    "pair": dict(normal_module_mm=3.5, normal_pressure_angle_deg=20.0, shaft_angle_deg=0.0001, offset_mm=91.5),
    "pinion": dict(teeth=20, cone_angle_deg=0.0001, helix_angle_deg=15.0, profile_shift=XT1, face_width_mm=23.0,
                   roughness_ra_um=0.6),
    "gear": dict(teeth=30, cone_angle_deg=-0.0001, face_width_mm=23.0, roughness_ra_um=0.6),
    "lubricant": dict(base_oil="mineral", iso_vg=150, kinematic_viscosity_mm2_s=37.41, density_15_kg_m3=RHO_15,
                      temperature_c=70.0, pressure_viscosity_coefficient_1_per_gpa=50.23, lubricant_factor_xl=0.846),
}
PUBLISHED = dict(mu=0.0420, loss_w=82.20, central_um=(0.51, 0.73), min_um=(0.36, 0.54))


def main():
    pair = Pair.from_spec(spec_from_dict(SPEC))
    xn2 = pair.design.gear.profile_shift / math.cos(math.radians(15.0))
    print(f"gear normal profile shift from a = 91.5 mm: {xn2:.4f} (published 0.0891)")
    for flank in ("left", "right"):
        result = ltca.analyze(pair, ltca.LoadCase(100.0), ltca.Options(flank=flank, tooth_model="plate"))
        t = tribology.evaluate(result, pair, 1000.0)
        hc, hm = (np.asarray(a, dtype=float) for a in (t.pair_film_thickness_central_um, t.pair_film_thickness_min_um))
        print(f"{flank}: eta {t.dynamic_viscosity_mpa_s:.2f} mPa s, mu_global {t.friction_coefficient_global:.5f}"
              f" (published {PUBLISHED['mu']}), loss {t.mesh_power_loss_w:.2f} W (published {PUBLISHED['loss_w']}),"
              f" H_V {t.loss_factor_hv:.4f}")
        for name, h, (lo, hi) in (("central", hc, PUBLISHED["central_um"]), ("minimum", hm, PUBLISHED["min_um"])):
            a, b = np.nanmin(h), np.nanmax(h)
            print(f"  {name} film {a:.3f}-{b:.3f} um (published {lo}-{hi}: ends {100 * (a / lo - 1):+.0f} %,"
                  f" {100 * (b / hi - 1):+.0f} %)")


if __name__ == "__main__":
    main()
