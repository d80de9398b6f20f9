"""FE root stress against ISO 6336-3 method B in the near-cylindrical, near-parallel limit (issue 32).

    python benchmarks/rating_fe_vs_iso.py [--positions N]

A case-1-like pair made nearly cylindrical and nearly parallel (cone angles 0.05 deg, shaft angle
3 deg, a spur pinion, a tip round of 0.3 m_n), rated at 1000 N m:

1. the ISO load case on the FE tooth: the full normal force at the outer point of single pair
   contact (d_en of method B), uniform along the face of the pinion's middle section; the FE root
   stress (max principal, loaded fillet) against sigma_F0 of the same virtual gear;
2. the loaded contact: ``beveloid rating`` (LTCA with the FE tooth, the root stress maximum over the
   mesh cycle) against ISO sigma_F of each member (K_A = K_v = 1).

The FE data is cached (BEVELOID_CACHE_DIR); the first run builds it (about a minute per member).
"""
from __future__ import annotations

import argparse

from beveloid import rating
from beveloid.pair import Pair
from beveloid.rating.fe_check import iso_load_case
from beveloid.spec import load_example, spec_from_dict, spec_to_dict


def near_parallel_pair(pinion_helix_deg=0.0, face_width_mm=None) -> Pair:
    d = spec_to_dict(load_example("case1"))
    d["pair"]["shaft_angle_deg"] = 3.0
    d["pinion"].update(cone_angle_deg=0.05, helix_angle_deg=pinion_helix_deg, cutter_tip_radius_coefficient=0.3)
    d["gear"].update(cone_angle_deg=0.05, cutter_tip_radius_coefficient=0.3)
    if face_width_mm is not None:
        d["pinion"]["face_width_mm"] = face_width_mm
    return Pair.from_spec(spec_from_dict(d))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--positions", type=int, default=20)
    args = ap.parse_args()
    pair = near_parallel_pair()
    for member in ("pinion", "gear"):
        fe, iso = iso_load_case(pair, member)
        print(f"1. ISO load case, {member}: FE {fe:.2f} MPa, ISO sigma_F0 {iso:.2f} MPa, FE/ISO {fe / iso:.3f}")
    r = rating.analyze(pair, rating.Options(torque_nm=1000.0, positions=args.positions, tooth_model="fe"))
    for name, m in r.members.items():
        s = m.sections["middle"]
        print(f"2. LTCA + FE, {name}: root stress max {m.root_stress_max_mpa:.1f} MPa ({m.root_stress_location}); "
              f"ISO sigma_F middle {s.sigma_F_mpa:.1f} MPa (K_Fbeta {s.K_Fbeta:.3f}); FE/ISO "
              f"{m.root_stress_max_mpa / s.sigma_F_mpa:.3f}")


if __name__ == "__main__":
    main()
