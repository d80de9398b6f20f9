"""FE root stress against ISO 6336-3 method B in the near-cylindrical, near-parallel limit (issue 32).

    python benchmarks/rating_fe_vs_iso.py [--positions N] [--offset-mm A] [--gear-tip-round R]
                                          [--pinion-face-mm B] [--refinement N] [--iso-load-case-only]

A case-1-like pair made nearly cylindrical and nearly parallel (cone angles 0.05 deg, shaft angle
3 deg, a spur pinion, a tip round of 0.3 m_n), rated at 1000 N m:

1. the ISO load case on the FE tooth: the full normal force at the outer point of single pair
   contact (d_en of method B, at the same depth below the tip on the real section), uniform along
   the face of each member's middle section; the FE root stress (max principal, loaded fillet: its
   largest, and the median over 24 face slices of each slice's largest) against sigma_F0 of the same
   virtual gear, with where the FE peaks and where method B reads (its 30 deg tangent chord);
2. the loaded contact: ``beveloid rating`` (LTCA with the FE tooth, the root stress maximum over the
   mesh cycle) against ISO sigma_F of each member (K_A = K_v = 1).

The FE data is cached (BEVELOID_CACHE_DIR); the first run builds it (about a minute per member).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this checkout's beveloid, not an installed one

from beveloid import ltca, rating  # noqa: E402
from beveloid.pair import Pair  # noqa: E402
from beveloid.rating.fe_check import iso_load_case_detail  # noqa: E402
from beveloid.rating.virtual import section_gear  # noqa: E402
from beveloid.spec import load_example, spec_from_dict, spec_to_dict  # noqa: E402


def near_parallel_pair(pinion_helix_deg=0.0, face_width_mm=None, offset_mm=None, gear_tip_round=0.3,
                       shaft_angle_deg=3.0) -> Pair:
    """The benchmark's pair; ``offset_mm`` (case 1: 229 mm) sets the gear's profile shift (1.12 at 229 mm),
    ``gear_tip_round`` the gear's cutter tip radius coefficient."""
    d = spec_to_dict(load_example("case1"))
    d["pair"]["shaft_angle_deg"] = shaft_angle_deg
    if offset_mm is not None:
        d["pair"]["offset_mm"] = offset_mm
    d["pinion"].update(cone_angle_deg=0.05, helix_angle_deg=pinion_helix_deg, cutter_tip_radius_coefficient=0.3)
    d["gear"].update(cone_angle_deg=0.05, cutter_tip_radius_coefficient=gear_tip_round)
    if face_width_mm is not None:
        d["pinion"]["face_width_mm"] = face_width_mm
    return Pair.from_spec(spec_from_dict(d))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--positions", type=int, default=20)
    ap.add_argument("--offset-mm", type=float, default=None, help="the pair's offset (the gear's profile shift)")
    ap.add_argument("--gear-tip-round", type=float, default=0.3, help="the gear's cutter tip radius coefficient")
    ap.add_argument("--pinion-face-mm", type=float, default=None, help="the pinion's face width (the test: 20)")
    ap.add_argument("--refinement", type=int, default=1, help="the FE tooth's mesh refinement")
    ap.add_argument("--iso-load-case-only", action="store_true", help="skip the LTCA (part 2)")
    args = ap.parse_args()
    pair = near_parallel_pair(face_width_mm=args.pinion_face_mm, offset_mm=args.offset_mm,
                              gear_tip_round=args.gear_tip_round)
    for member in ("pinion", "gear"):
        x = section_gear(pair.geometry, member, 0.0, "right").gear.profile_shift
        d = iso_load_case_detail(pair, member, refinement=args.refinement)
        fe, iso = d.fe_max_mpa, d.sigma_F0_mpa
        print(f"1. ISO load case, {member} (x {x:.2f}, face {pair.geometry.member(member).face_width_mm:g} mm): "
              f"FE {fe:.2f} MPa, ISO sigma_F0 {iso:.2f} MPa, FE/ISO {fe / iso:.3f}; "
              f"FE median over the face {d.fe_face_median_mpa:.2f} MPa ({d.fe_face_median_mpa / iso:.3f}); FE max at "
              f"face z {d.fe_face_z_mm:.1f} mm, {d.fe_height_above_root_mm:.2f} mm above the root "
              f"(ISO's 30 deg chord: {d.iso_chord_height_above_root_mm:.2f} mm); q_s {d.notch_parameter:.2f}, "
              f"Y_S {d.Y_S:.3f}")
    if args.iso_load_case_only:
        return
    r = rating.analyze(pair, ltca.LoadCase(1000.0), rating.Options(ltca.Options(positions=args.positions, tooth_model="fe", fe_refinement=args.refinement)))
    for name, m in r.members.items():
        s = m.sections["middle"]
        print(f"2. LTCA + FE, {name}: root stress max {m.root_stress_max_mpa:.1f} MPa ({m.root_stress_location}); "
              f"ISO sigma_F middle {s.sigma_F_mpa:.1f} MPa (K_F_beta {s.K_F_beta:.3f}); FE/ISO "
              f"{m.root_stress_max_mpa / s.sigma_F_mpa:.3f}")


if __name__ == "__main__":
    main()
